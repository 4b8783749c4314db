// "short": a small room (5 m x 4 m) with a box; gentle motion for 2 s. Meant for fast tests.
#include <vector>

#include "scene_builder.h"
#include "texture_library.h"

namespace ldsm::drivers::sim {

SimScene makeShortScene() {
  constexpr std::uint32_t kSeed = 0x5407u;
  SimScene scene;
  scene.name = "short";
  scene.description = "small room";
  SceneBuilder b(scene, kSeed);

  constexpr double kHeight = 2.6;
  b.addRoom(-2.5, 2.5, -2.0, 2.0, 0.0, kHeight, {kPlaster, kBrick, kBlobs, kChecker}, kFloorTiles,
            kCeilingPanels, 3.0);
  b.addBox(1.2, 2.0, -1.9, -1.2, 0, 0.9, kWood, true);
  b.addBox(1.0, 1.3, 1.0, 1.3, 0, kHeight, kConcrete, false);
  b.addLight({1.0, 0.0, kHeight - 0.5}, 1.4);
  b.addLight({-1.2, 0.0, kHeight - 0.5}, 1.4);

  CameraPath& p = scene.path;
  p.control_points = ellipseControlPoints(0.3, 0.2, 1.3, 8);
  p.closed = true;
  p.span_duration_s = 1.0;
  p.heading_from_tangent = false;
  p.fixed_heading = {1, 0, 0};
  p.yaw = {{0.3, 4.0, 0.0}};
  p.pitch = {{0.05, 3.0, 0.0}};
  p.vertical = {{0.03, 2.5, 0.0}};
  scene.default_duration_s = 2.0;

  bakeSceneTextures(scene, kSeed);
  return scene;
}

}  // namespace ldsm::drivers::sim
