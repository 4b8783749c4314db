// `ldsm sim`: renders a built-in synthetic scene into a TUM-Mono style folder (images, times.txt,
// camera.txt, pcalib.txt, vignette.png, groundtruth.txt), with a progress line on stderr and a
// summary on stdout. `ldsm sim --list` prints the scenes.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "ldsm/drivers/sim/sim_scene.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/drivers/sim/tum_mono_writer.h"
#include "ldsm/error.h"

namespace ldsm::app {
namespace {

namespace sim = drivers::sim;

struct SimCommandOptions {
  std::string scene;
  std::string out;
  std::string response = "gamma";
  double focal_error = 0.0;
  bool list = false;
  sim::SimOptions render;
};

void listScenes() {
  for (const std::string& name : sim::simSceneNames())
    std::printf("%-10s %s\n", name.c_str(), sim::simSceneDescription(name).c_str());
}

// Progress on stderr: a rewritten line on a terminal, a line per 10% otherwise.
class Progress {
 public:
  Progress() : tty_(isatty(fileno(stderr)) != 0), start_(std::chrono::steady_clock::now()) {}

  void operator()(std::int64_t done, std::int64_t total) {
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double fps = secs > 0.0 ? static_cast<double>(done) / secs : 0.0;
    if (tty_) {
      if (done % 10 == 0 || done == total) {
        std::fprintf(stderr, "\rsim: %lld/%lld frames (%.1f fps)", static_cast<long long>(done),
                     static_cast<long long>(total), fps);
        if (done == total) std::fputc('\n', stderr);
        std::fflush(stderr);
      }
      return;
    }
    const std::int64_t decile = done * 10 / total;
    if (decile > last_decile_ || done == total) {
      last_decile_ = decile;
      std::fprintf(stderr, "sim: %lld/%lld frames (%.1f fps)\n", static_cast<long long>(done),
                   static_cast<long long>(total), fps);
    }
  }

 private:
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  std::int64_t last_decile_ = 0;
};

int runSim(SimCommandOptions& o) {
  if (o.list) {
    listScenes();
    return 0;
  }
  if (o.scene.empty()) throw ConfigError("sim: --scene is required (see ldsm sim --list)");
  if (o.out.empty()) throw ConfigError("sim: --out is required");
  o.render.response = sim::parseSimResponse(o.response);
  sim::validate(o.render);
  sim::SimSource source(o.scene, o.render);
  sim::TumMonoWriteOptions write;
  write.focal_error = o.focal_error;
  Progress progress;
  const sim::TumMonoWriteSummary summary = sim::writeTumMonoSequence(
      source, o.out, write, [&](std::int64_t done, std::int64_t total) { progress(done, total); });

  const auto& cam = source.intrinsics();
  const double duration = static_cast<double>(summary.frames) / o.render.fps;
  std::printf("scene:        %s (%s)\n", o.scene.c_str(),
              sim::simSceneDescription(o.scene).c_str());
  std::printf("frames:       %lld (%dx%d at %g fps, %.2f s)\n",
              static_cast<long long>(summary.frames), cam.width, cam.height, o.render.fps,
              duration);
  std::printf("path length:  %.2f m\n", summary.path_length_m);
  std::printf("camera:       fx = fy = %.3f, cx = %.1f, cy = %.1f", cam.fx, cam.cx, cam.cy);
  if (o.focal_error != 0.0)
    std::printf(" (camera.txt: focal length off by %+.2f%%)", 100.0 * o.focal_error);
  std::printf("\nphotometric:  response %s, vignette %.2f, noise sigma %.2f, exposure %s\n",
              o.response.c_str(), o.render.vignette, o.render.noise_sigma,
              o.render.exposure_changes ? "varying" : "fixed");
  std::printf("output:       %s\n", summary.out_dir.c_str());
  return 0;
}

}  // namespace

void addSimCommand(CLI::App& app, CommandResult& result) {
  auto o = std::make_shared<SimCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "sim", "Render a synthetic scene with exact ground truth into a TUM-Mono style folder");
  sub->add_option("--scene", o->scene, "Scene name (see --list)");
  sub->add_option("--out", o->out, "Output folder (created)");
  sub->add_flag("--list", o->list, "List the scenes and exit");
  sub->add_option("--frames", o->render.frames, "Number of frames (0: the scene's default)")
      ->capture_default_str();
  sub->add_option("--width", o->render.width, "Image width")->capture_default_str();
  sub->add_option("--height", o->render.height, "Image height")->capture_default_str();
  sub->add_option("--fps", o->render.fps, "Frame rate")->capture_default_str();
  sub->add_option("--hfov", o->render.hfov_deg, "Horizontal field of view (degrees)")
      ->capture_default_str();
  sub->add_option("--noise", o->render.noise_sigma, "Noise standard deviation (grey levels)")
      ->capture_default_str();
  sub->add_flag("--exposure-changes", o->render.exposure_changes,
                "Vary the exposure time smoothly (about 0.5x to 2x)");
  sub->add_option("--exposure", o->render.exposure_ms, "Nominal exposure time (ms)")
      ->capture_default_str();
  sub->add_option("--vignette", o->render.vignette, "Vignette strength: 1 - V at the corners")
      ->capture_default_str();
  sub->add_option("--response", o->response, "Camera response curve")
      ->check(CLI::IsMember({"linear", "gamma", "scurve"}))
      ->capture_default_str();
  sub->add_option("--focal-error", o->focal_error,
                  "Relative error of the focal length written to camera.txt (e.g. 0.02)")
      ->capture_default_str();
  sub->add_option("--seed", o->render.seed, "Noise seed")->capture_default_str();
  sub->add_option("--supersampling", o->render.supersampling,
                  "Full-frame supersampling factor per axis (1-4)")
      ->capture_default_str();
  sub->add_flag("--no-edge-aa{false}", o->render.antialias_edges,
                "Do not anti-alias geometric edges (faster, aliased)");
  sub->add_option("--motion-blur", o->render.motion_blur_samples,
                  "Sub-frame poses averaged over the exposure (1: no blur)")
      ->capture_default_str();
  sub->callback([o, &result]() { result.exit_code = runSim(*o); });
}

}  // namespace ldsm::app
