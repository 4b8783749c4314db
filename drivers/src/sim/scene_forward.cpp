// "forward": a straight 54 m corridor (2.4 m wide, 2.6 m high) with pillars, cabinets, doors and
// posters; the camera walks down it at 1 m/s with some sway.
#include <vector>

#include "scene_builder.h"
#include "texture_library.h"

namespace ldsm::drivers::sim {

SimScene makeForwardScene() {
  constexpr std::uint32_t kSeed = 0xf0e3u;
  SimScene scene;
  scene.name = "forward";
  scene.description = "straight corridor";
  SceneBuilder b(scene, kSeed);

  constexpr double x0 = -2.0, x1 = 52.0, y0 = -1.2, y1 = 1.2, kHeight = 2.6;
  b.addRoom(x0, x1, y0, y1, 0.0, kHeight, {kPlaster, kBrick, kConcrete, kBlobs, kChecker},
            kFloorTiles, kCeilingPanels, 4.0);
  for (int i = 0; i < 10; ++i) {
    const double x = 3.0 + 5.0 * i;
    if (i % 2 == 0)
      b.addBox(x, x + 0.3, y0, y0 + 0.25, 0, kHeight, kConcrete, false);
    else
      b.addBox(x, x + 0.3, y1 - 0.25, y1, 0, kHeight, kConcrete, false);
  }
  for (int i = 0; i < 5; ++i) {
    const double x = 5.5 + 9.0 * i;
    const bool left = (i % 2) == 0;
    const double ya = left ? y1 - 0.4 : y0, yb = left ? y1 : y0 + 0.4;
    b.addBox(x, x + 1.0, ya, yb, 0, 0.8 + 0.2 * (i % 3), i % 2 ? kWood : kChecker, true);
  }
  for (double x = 0.0; x <= 51.0; x += 3.0) b.addLight({x, 0.0, kHeight - 0.5}, 1.3);

  CameraPath& p = scene.path;
  p.closed = false;
  // Uniform points on a straight line: the spline runs at 1 m per span, at x = -2 + (s + 2) = t.
  for (int k = 0; k < 52; ++k) p.control_points.push_back({-2.0 + k, 0.0, 1.3});
  p.span_duration_s = 1.0;
  p.start_span = 0.0;
  p.heading_from_tangent = true;
  p.yaw = {{0.06, 5.3, 0.0}, {0.02, 2.3, 1.0}};
  p.pitch = {{0.03, 6.1, 0.5}};
  p.roll = {{0.015, 4.7, 1.5}};
  p.lateral = {{0.2, 7.0, 0.0}};
  p.vertical = {{0.03, 3.1, 0.0}};
  scene.default_duration_s = 30.0;

  bakeSceneTextures(scene, kSeed);
  return scene;
}

}  // namespace ldsm::drivers::sim
