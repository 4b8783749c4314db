// "loop": a rectangular corridor ring (centre line 16 m x 10 m, 52 m long, 2.4 m wide, 2.6 m high)
// with pillars, cabinets, doors and posters. The camera walks the centre line counter-clockwise at
// about 1 m/s; the path is periodic (54 s), so the start pose is revisited exactly. "loop2" walks
// the same ring twice (map reuse: the second lap should hardly add to the map).
#include <vector>

#include "ldsm/drivers/sim/det_math.h"
#include "scene_builder.h"
#include "texture_library.h"

namespace ldsm::drivers::sim {

namespace {

SimScene makeLoopLaps(const char* name, int laps) {
  constexpr std::uint32_t kSeed = 0x100bu;
  SimScene scene;
  scene.name = name;
  scene.description = laps == 1 ? "rectangular corridor loop" : "rectangular corridor loop, twice";
  SceneBuilder b(scene, kSeed);

  constexpr double kHeight = 2.6, kSegment = 4.0;
  constexpr double ox0 = -9.2, ox1 = 9.2, oy0 = -6.2, oy1 = 6.2;  // outer walls
  constexpr double ix0 = -6.8, ix1 = 6.8, iy0 = -3.8, iy1 = 3.8;  // inner block
  const std::vector<int> outer = {kBrick, kPlaster, kConcrete, kChecker, kBlobs, kPlaster};
  const std::vector<int> inner = {kPlaster, kConcrete, kBlobs, kBrick, kWood};

  // Outer walls face inwards (concave corners: extend the ends); the inner block's corners are
  // convex, so its walls must not stick out.
  b.addWall(ox0, oy0, ox1, oy0, 0, kHeight, outer, kSegment, kWallMargin);
  b.addWall(ox1, oy0, ox1, oy1, 0, kHeight, outer, kSegment, kWallMargin);
  b.addWall(ox1, oy1, ox0, oy1, 0, kHeight, outer, kSegment, kWallMargin);
  b.addWall(ox0, oy1, ox0, oy0, 0, kHeight, outer, kSegment, kWallMargin);
  b.addWall(ix0, iy0, ix1, iy0, 0, kHeight, inner, kSegment, 0.0);
  b.addWall(ix1, iy0, ix1, iy1, 0, kHeight, inner, kSegment, 0.0);
  b.addWall(ix1, iy1, ix0, iy1, 0, kHeight, inner, kSegment, 0.0);
  b.addWall(ix0, iy1, ix0, iy0, 0, kHeight, inner, kSegment, 0.0);

  // Floor and ceiling: bottom and top strips span the full width, side strips fill in between.
  const int floors[4] = {kFloorTiles, kWood, kFloorTiles, kConcrete};
  const double strips[4][4] = {{ox0, ox1, oy0, iy0},
                               {ox1 - 2.4, ox1, iy0, iy1},
                               {ox0, ox1, iy1, oy1},
                               {ox0, ox0 + 2.4, iy0, iy1}};
  for (int i = 0; i < 4; ++i) {
    const double* s = strips[i];
    b.addHorizontal(s[0], s[1], s[2], s[3], 0.0, SurfaceKind::Floor, floors[i], kSegment, {});
    b.addHorizontal(s[0], s[1], s[2], s[3], kHeight, SurfaceKind::Ceiling, kCeilingPanels, kSegment,
                    {});
  }

  // Pillars against the outer walls and cabinets against the inner block.
  const double pillar_x[] = {-6.0, -1.5, 3.0, 7.5};
  for (double x : pillar_x) {
    b.addBox(x - 0.15, x + 0.15, oy0, oy0 + 0.3, 0, kHeight, kConcrete, false);
    b.addBox(-x - 0.15, -x + 0.15, oy1 - 0.3, oy1, 0, kHeight, kConcrete, false);
  }
  b.addBox(ox1 - 0.3, ox1, -1.0, -0.7, 0, kHeight, kConcrete, false);
  b.addBox(ox0, ox0 + 0.3, 1.5, 1.8, 0, kHeight, kConcrete, false);
  b.addBox(-3.5, -2.5, iy0 - 0.4, iy0, 0, 1.0, kWood, true);
  b.addBox(4.0, 5.2, iy1, iy1 + 0.45, 0, 1.2, kChecker, true);
  b.addBox(ix1, ix1 + 0.4, 0.5, 1.3, 0, 0.9, kWood, true);
  b.addBox(ix0 - 0.35, ix0, -2.5, -1.6, 0, 1.5, kBlobs, true);

  // Lamps along the centre line.
  for (double x = -7.5; x <= 7.6; x += 3.0) {
    b.addLight({x, -5.0, kHeight - 0.5}, 1.3);
    b.addLight({-x, 5.0, kHeight - 0.5}, 1.3);
  }
  for (double y = -2.0; y <= 2.1; y += 4.0) {
    b.addLight({8.0, y, kHeight - 0.5}, 1.3);
    b.addLight({-8.0, -y, kHeight - 0.5}, 1.3);
  }

  CameraPath& p = scene.path;
  p.control_points = rectangleControlPoints(-8.0, 8.0, -5.0, 5.0, 1.3, 1.0);
  p.closed = true;
  constexpr double kPeriod = 54.0;
  p.span_duration_s = kPeriod / static_cast<double>(p.control_points.size());
  p.heading_from_tangent = true;
  // Head motion with whole numbers of cycles per lap, so the path is exactly periodic.
  p.yaw = {{0.05, kPeriod / 13, 0.3}, {0.02, kPeriod / 29, 1.1}};
  p.pitch = {{0.03, kPeriod / 17, 1.0}};
  p.roll = {{0.015, kPeriod / 11, 2.0}};
  p.lateral = {{0.15, kPeriod / 7, 0.5}};
  p.vertical = {{0.04, kPeriod / 23, 0.0}};
  scene.default_duration_s = laps * kPeriod + 5.0;

  bakeSceneTextures(scene, kSeed);
  return scene;
}

}  // namespace

SimScene makeLoopScene() {
  return makeLoopLaps("loop", 1);
}

SimScene makeTwoLapLoopScene() {
  return makeLoopLaps("loop2", 2);
}

}  // namespace ldsm::drivers::sim
