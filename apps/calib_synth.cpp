#include "calib_synth.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/image_file.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/drivers/sim/calibration_target.h"
#include "ldsm/drivers/sim/photometric_sequences.h"
#include "ldsm/error.h"

namespace ldsm::app {
namespace {

namespace fs = std::filesystem;
namespace sim = drivers::sim;

void makeDirectory(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": cannot create directory");
}

void synthBoard(const CalibSynthOptions& o) {
  calib::validateBoardSpec(o.board);
  if (o.views < 1 || o.views > 500 || o.blurred < 0 || o.duplicates < 0)
    throw ConfigError("calib synth: --views must be in 1..500, --blurred and --duplicates >= 0");
  const CameraIntrinsics truth = synthCamera(o.model, o.render.width, o.render.height);
  const auto camera = makeCameraModel(truth);
  sim::CalibrationTarget target;
  target.cols = o.board.cols;
  target.rows = o.board.rows;
  target.square_m = o.board.square_m;
  target.margin_m = 0.5 * o.board.square_m;
  if (o.board.type == calib::BoardType::Charuco) target.texture = calib::drawBoard(o.board, 40, 20);
  // The board spans about half the image width at the nominal distance.
  const double board_w = std::max(o.board.cols, o.board.rows) * o.board.square_m;
  const double distance = board_w * truth.fx / (0.5 * truth.width);
  const auto poses = sim::calibrationPoses(target, *camera, o.views, distance);
  if (poses.empty()) throw ConfigError("calib synth: the board does not fit in the view");

  const fs::path images = fs::path(o.out) / "images";
  makeDirectory(images);
  int index = 0;
  auto render = [&](const Pose& pose, double blur) {
    sim::TargetRenderOptions ro;
    ro.noise_sigma = o.render.noise_sigma;
    ro.noise_key = static_cast<std::uint32_t>(index) + o.render.seed * 7919u;
    ro.blur_sigma_px = blur;
    ImageU8 image;
    sim::renderTargetView(target, *camera, pose, ro, image);
    char name[32];
    std::snprintf(name, sizeof(name), "view_%03d.png", index++);
    calib::writePng((images / name).string(), image.view());
  };
  for (const Pose& p : poses) render(p, 0.0);
  for (int i = 0; i < o.duplicates; ++i) {
    Pose p = poses[static_cast<std::size_t>(i * 3) % poses.size()];
    p.translation.x() += 0.002;  // 2 mm: the same view for calibration purposes
    render(p, 0.0);
  }
  for (int i = 0; i < o.blurred; ++i)
    render(poses[static_cast<std::size_t>(i * 5 + 1) % poses.size()], 2.5);

  GeometricCalibration written;
  written.input = truth;
  written.output.mode =
      truth.model == CameraModelType::Pinhole ? OutputMode::None : OutputMode::Crop;
  written.output.width = truth.width;
  written.output.height = truth.height;
  calib::writeDsoCameraFile((fs::path(o.out) / "true_camera.txt").string(), written);
  std::printf("board views:  %d (%zu distinct, %d near-duplicates, %d blurred), %s %dx%d squares\n",
              index, poses.size(), o.duplicates, o.blurred, calib::toString(o.board.type),
              o.board.cols, o.board.rows);
  std::printf("camera:       %s fx %.3f fy %.3f cx %.3f cy %.3f (true_camera.txt)\n",
              cameraModelName(truth.model), truth.fx, truth.fy, truth.cx, truth.cy);
}

void writePhotometric(const CalibSynthOptions& o, const sim::ExposedFrames& frames, bool vignette) {
  sim::writeExposedFrames(o.out, frames.images, frames.exposures_ms);
  calib::writeInverseResponse((fs::path(o.out) / "true_pcalib.txt").string(),
                              frames.truth.inverse_response);
  if (vignette)
    calib::writeVignette((fs::path(o.out) / "true_vignette.png").string(), frames.truth.vignette);
  std::printf("images:       %zu (%dx%d), exposures %.3g to %.3g ms (times.txt)\n",
              frames.images.size(), o.render.width, o.render.height, frames.exposures_ms.front(),
              frames.exposures_ms.back());
  std::printf("photometric:  response %s, vignette %.2f, noise sigma %.2f (true_pcalib.txt%s)\n",
              sim::toString(o.render.response).c_str(), o.render.vignette, o.render.noise_sigma,
              vignette ? ", true_vignette.png" : "");
}

}  // namespace

CameraIntrinsics synthCamera(CameraModelType model, int width, int height) {
  CameraIntrinsics c;
  c.model = model;
  c.width = width;
  c.height = height;
  const bool fisheye = model == CameraModelType::Equidistant;
  c.fx = (fisheye ? 0.469 : 0.8203) * width;
  c.fy = (fisheye ? 0.466 : 0.8094) * width;
  c.cx = 0.504 * width - 0.5;
  c.cy = 0.4925 * height - 0.5;
  if (model == CameraModelType::RadTan) c.distortion = {-0.28, 0.09, 0.0012, -0.0009};
  if (fisheye) c.distortion = {0.04, -0.012, 0.003, -0.0006};
  if (model == CameraModelType::Fov) throw ConfigError("calib synth: --model fov is not supported");
  return c;
}

void runCalibSynth(const CalibSynthOptions& o) {
  if (o.out.empty()) throw ConfigError("calib synth: --out is required");
  sim::validate(o.render);
  if (o.kind == "board") {
    synthBoard(o);
  } else if (o.kind == "sweep") {
    const auto times = sim::exposureSweepTimes(0.05, 400, 40);
    std::vector<double> formed;
    if (o.auto_gain)
      for (const double t : times) formed.push_back(t * std::clamp(8.0 / t, 1.0, 16.0));
    writePhotometric(o, sim::renderExposureSweep("loop", o.render, times, formed), false);
    if (o.auto_gain) std::printf("auto-gain:    on (up to 16x below 8 ms)\n");
  } else if (o.kind == "flat") {
    writePhotometric(o, sim::renderFlatField(o.render, 0.6, sim::exposureSweepTimes(12, 20, 8)),
                     true);
  } else {
    throw ConfigError("calib synth: --kind must be board, sweep or flat");
  }
  std::printf("output:       %s\n", o.out.c_str());
}

}  // namespace ldsm::app
