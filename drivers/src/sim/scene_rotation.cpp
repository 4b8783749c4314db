// "rotation": a furnished 8 m x 6 m room; the camera drifts slowly on a small ellipse while panning
// +-70 degrees (up to about 2.5 degrees per frame at 30 fps), with some pitch and roll.
#include <vector>

#include "scene_builder.h"
#include "texture_library.h"

namespace ldsm::drivers::sim {

SimScene makeRotationScene() {
  constexpr std::uint32_t kSeed = 0x2071u;
  SimScene scene;
  scene.name = "rotation";
  scene.description = "panning in a room";
  SceneBuilder b(scene, kSeed);

  constexpr double kHeight = 2.8;
  b.addRoom(-4.0, 4.0, -3.0, 3.0, 0.0, kHeight, {kBrick, kPlaster, kChecker, kConcrete, kBlobs},
            kWood, kCeilingPanels, 3.0);
  b.addBox(2.2, 2.6, 1.6, 2.0, 0, kHeight, kConcrete, false);
  b.addBox(-2.6, -2.2, -2.0, -1.6, 0, kHeight, kConcrete, false);
  b.addBox(3.2, 4.0, -2.0, -0.5, 0, 0.8, kWood, true);
  b.addBox(-1.0, 0.5, 2.4, 3.0, 0, 0.9, kChecker, true);
  b.addBox(-4.0, -3.4, 0.8, 2.0, 0, 2.0, kBlobs, true);
  b.addBox(0.8, 1.6, -3.0, -2.5, 0, 1.2, kWood, true);
  b.addLight({2.0, 1.5, kHeight - 0.5}, 1.4);
  b.addLight({-2.0, 1.5, kHeight - 0.5}, 1.4);
  b.addLight({2.0, -1.5, kHeight - 0.5}, 1.4);
  b.addLight({-2.0, -1.5, kHeight - 0.5}, 1.4);

  CameraPath& p = scene.path;
  p.control_points = ellipseControlPoints(0.5, 0.3, 1.4, 12);
  p.closed = true;
  p.span_duration_s = 2.0;
  p.heading_from_tangent = false;
  p.fixed_heading = {1, 0, 0};
  p.yaw = {{1.15, 7.2, 0.0}, {0.12, 2.9, 1.0}};
  p.pitch = {{0.15, 9.1, 0.3}};
  p.roll = {{0.06, 6.3, 0.7}};
  p.vertical = {{0.05, 5.0, 0.0}};
  scene.default_duration_s = 20.0;

  bakeSceneTextures(scene, kSeed);
  return scene;
}

}  // namespace ldsm::drivers::sim
