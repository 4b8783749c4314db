// Registry of the built-in scenes and the reference irradiance lookup.
#include "ldsm/drivers/sim/sim_scene.h"

#include <cmath>
#include <sstream>

#include "ldsm/error.h"
#include "scene_builder.h"

namespace ldsm::drivers::sim {
namespace {

struct SceneEntry {
  const char* name;
  SimScene (*make)();
};

constexpr SceneEntry kScenes[] = {
    {"loop", makeLoopScene},
    {"loop2", makeTwoLapLoopScene},
    {"forward", makeForwardScene},
    {"rotation", makeRotationScene},
    {"short", makeShortScene},
};

const SceneEntry& findScene(const std::string& name) {
  for (const SceneEntry& e : kScenes)
    if (name == e.name) return e;
  std::ostringstream os;
  os << "sim: unknown scene '" << name << "'; valid scenes:";
  for (const SceneEntry& e : kScenes) os << ' ' << e.name;
  throw InputError(os.str());
}

}  // namespace

double SimScene::irradianceAt(int quad, double u, double v) const {
  const SimQuad& q = quads.at(static_cast<std::size_t>(quad));
  const MipTexture& tex = textures.at(static_cast<std::size_t>(q.texture));
  double value = sampleLevelBilinear(tex, 0, (u + q.texture_offset_u) / tex.texel_size_m,
                                     (v + q.texture_offset_v) / tex.texel_size_m);
  if (q.detail >= 0) {
    const MipTexture& d = details.at(static_cast<std::size_t>(q.detail));
    value *= sampleLevelBilinear(d, 0, u / d.texel_size_m, v / d.texel_size_m);
  }
  return value;
}

std::vector<std::string> simSceneNames() {
  std::vector<std::string> names;
  for (const SceneEntry& e : kScenes) names.emplace_back(e.name);
  return names;
}

std::string simSceneDescription(const std::string& name) {
  const std::string n = findScene(name).name;
  if (n == "loop") return "closed rectangular corridor loop (52 m), revisits the start after 54 s";
  if (n == "loop2") return "the corridor loop walked twice (104 m, 113 s): the second lap revisits";
  if (n == "forward") return "forward motion down a 54 m corridor";
  if (n == "rotation") return "strong panning in a room while moving slowly";
  return "small room, gentle motion, 2 s (for tests)";
}

SimScene makeSimScene(const std::string& name, const SimOptions& options) {
  validate(options);
  SimScene scene = findScene(name).make();
  simFrameCount(scene, options);  // throws if the path is too short for the request
  return scene;
}

std::int64_t simFrameCount(const SimScene& scene, const SimOptions& options) {
  std::int64_t frames = options.frames;
  if (frames == 0)
    frames = static_cast<std::int64_t>(std::floor(scene.default_duration_s * options.fps + 0.5));
  // Frame i is at time i / fps; the last one must lie on the path.
  const double last_t = static_cast<double>(frames - 1) / options.fps;
  if (last_t > scene.path.duration()) {
    const std::int64_t max_frames =
        static_cast<std::int64_t>(std::floor(scene.path.duration() * options.fps)) + 1;
    std::ostringstream os;
    os << "sim option frames = " << frames << " is outside [1, " << max_frames << "] for scene '"
       << scene.name << "' at " << options.fps << " fps";
    throw ConfigError(os.str());
  }
  return frames;
}

}  // namespace ldsm::drivers::sim
