// Synthetic 3D scenes: textured rectangles (floors, ceilings, walls, boxes) lit by point lights,
// with a smooth camera path. Built-in scenes are made by name with makeSimScene().
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/drivers/sim/camera_path.h"
#include "ldsm/drivers/sim/det_vec.h"
#include "ldsm/drivers/sim/mip_texture.h"
#include "ldsm/drivers/sim/sim_options.h"

namespace ldsm::drivers::sim {

/// What a rectangle is; decides which landmarks (doors, posters, lamps, mats) it carries.
enum class SurfaceKind { Floor, Ceiling, Wall, Box };

/// A textured rectangle { origin + a * axis_u + b * axis_v : a in [0, size_u], b in [0, size_v] },
/// visible from both sides.
struct SimQuad {
  Vec3 origin;
  Vec3 axis_u{1, 0, 0};  ///< unit
  Vec3 axis_v{0, 1, 0};  ///< unit, orthogonal to axis_u
  double size_u = 1.0;   ///< metres
  double size_v = 1.0;   ///< metres
  SurfaceKind kind = SurfaceKind::Wall;
  int texture = 0;                ///< index into SimScene::textures (repeating albedo pattern)
  double texture_offset_u = 0.0;  ///< metres the pattern is shifted by
  double texture_offset_v = 0.0;
  int detail = -1;  ///< index into SimScene::details (landmarks x lighting), -1: none

  Vec3 normal() const { return cross(axis_u, axis_v); }
  Vec3 point(double u, double v) const { return (origin + u * axis_u) + v * axis_v; }
};

/// A point light (irradiance falls off with distance, Lambertian cosine, no shadows).
struct SimLight {
  Vec3 position;
  double intensity = 1.0;
};

struct SimScene {
  std::string name;
  std::string description;
  std::vector<SimQuad> quads;
  std::vector<MipTexture> textures;  ///< repeating albedo patterns, shared by quads
  std::vector<MipTexture> details;   ///< one clamped map per quad: landmark factor x lighting
  std::vector<SimLight> lights;
  CameraPath path;
  double default_duration_s = 0.0;  ///< length of the default sequence

  /// Reference irradiance of quad `quad` at (u, v) metres: the level-0 bilinear albedo pattern
  /// times the level-0 bilinear detail map, in double precision.
  double irradianceAt(int quad, double u, double v) const;
};

/// Names accepted by makeSimScene: "loop", "loop2", "forward", "rotation", "short".
std::vector<std::string> simSceneNames();

/// One-line description of a built-in scene (for `ldsm sim --list`).
std::string simSceneDescription(const std::string& name);

/// Builds a built-in scene (geometry, baked textures, camera path). Throws ldsm::InputError listing
/// the valid names when `name` is unknown, ldsm::ConfigError when `options` are invalid or ask for
/// more frames than an open path provides.
SimScene makeSimScene(const std::string& name, const SimOptions& options = {});

/// Number of frames a SimSource renders for `scene` with `options` (options.frames or the scene
/// default). Throws ldsm::ConfigError if an open path is too short for that many frames.
std::int64_t simFrameCount(const SimScene& scene, const SimOptions& options);

}  // namespace ldsm::drivers::sim
