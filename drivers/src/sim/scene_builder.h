// Helpers that assemble scenes from axis-aligned walls, floors, ceilings and boxes.
#pragma once

#include <cstdint>
#include <vector>

#include "ldsm/drivers/sim/sim_scene.h"

namespace ldsm::drivers::sim {

/// Extensions (metres) of a rectangle beyond its nominal edges, so that walls, floors and
/// ceilings meeting at an angle overlap slightly behind each other and leave no cracks.
inline constexpr double kWallMargin = 0.02;

struct Margins {
  double u_begin = 0, u_end = 0, v_begin = 0, v_end = 0;
};

class SceneBuilder {
 public:
  /// Quads, lights and path go into `scene`; `seed` drives texture offsets and choices.
  SceneBuilder(SimScene& scene, std::uint32_t seed) : scene_(scene), seed_(seed) {}

  /// Adds one quad with a random offset of its albedo pattern. Returns its index.
  int addQuad(const Vec3& origin, const Vec3& axis_u, const Vec3& axis_v, double size_u,
              double size_v, SurfaceKind kind, int texture, const Margins& margins = {});

  /// A vertical wall from (ax, ay) to (bx, by) between heights z0 and z1, split into segments of
  /// at most max_segment metres (each with its own landmarks). The textures cycle through
  /// `textures` per segment, starting at a hashed position. The wall extends by `margin_ends`
  /// beyond its ends (use 0 at convex corners) and by kWallMargin below z0 and above z1, so
  /// floors and ceilings need no margins.
  void addWall(double ax, double ay, double bx, double by, double z0, double z1,
               const std::vector<int>& textures, double max_segment, double margin_ends);

  /// A horizontal rectangle [x0, x1] x [y0, y1] at height z (floor or ceiling), split into tiles of
  /// at most max_segment metres; `margins` extend the outer edges (u along x, v along y).
  void addHorizontal(double x0, double x1, double y0, double y1, double z, SurfaceKind kind,
                     int texture, double max_segment, const Margins& margins);

  /// A closed room [x0, x1] x [y0, y1] x [z0, z1] seen from inside.
  void addRoom(double x0, double x1, double y0, double y1, double z0, double z1,
               const std::vector<int>& wall_textures, int floor_texture, int ceiling_texture,
               double max_segment);

  /// A box standing on the floor, seen from outside: four sides and, if `top`, its top face.
  void addBox(double x0, double x1, double y0, double y1, double z0, double z1, int texture,
              bool top);

  void addLight(const Vec3& position, double intensity) {
    scene_.lights.push_back({position, intensity});
  }

  std::uint32_t nextHash() { return hash(counter_++); }

 private:
  std::uint32_t hash(std::uint32_t k) const;

  SimScene& scene_;
  std::uint32_t seed_;
  std::uint32_t counter_ = 0;
};

/// Bakes the shared texture library and every quad's detail map into `scene`.
void bakeSceneTextures(SimScene& scene, std::uint32_t seed);

/// Control points every `spacing` metres (approximately) around the rectangle
/// [x0, x1] x [y0, y1] at height z, counter-clockwise, starting at the middle of the bottom side.
std::vector<Vec3> rectangleControlPoints(double x0, double x1, double y0, double y1, double z,
                                         double spacing);

/// n control points on the ellipse (rx cos a, ry sin a, z), a = 2 pi i / n.
std::vector<Vec3> ellipseControlPoints(double rx, double ry, double z, int n);

// Scene factories (one file each).
SimScene makeLoopScene();
SimScene makeTwoLapLoopScene();
SimScene makeForwardScene();
SimScene makeRotationScene();
SimScene makeShortScene();

}  // namespace ldsm::drivers::sim
