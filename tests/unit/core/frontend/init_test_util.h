// Helpers of the initializer tests: camera set-up, running the initializer over a rendered
// sequence, and comparing its result with the scene's truth.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

#include "camera/pyramid_camera.h"
#include "frontend/coarse_initializer.h"
#include "image/image_pyramid.h"
#include "init_scene.h"
#include "test_paths.h"

namespace ldsm::init_test {

inline PinholeIntrinsics makeIntrinsics(int width, int height, double focal) {
  PinholeIntrinsics K;
  K.fx = focal;
  K.fy = focal;
  K.cx = (width - 1) / 2.0;
  K.cy = (height - 1) / 2.0;
  K.width = width;
  K.height = height;
  return K;
}

/// CPU time of the calling thread in milliseconds (not inflated by other processes' load).
/// The frames of ../shared/data/euroc_v101_static95 (the drone standing still), sorted; empty when
/// the data is absent.
inline std::vector<std::string> eurocStandingStillFrames() {
  const std::string dir = test::sharedData("euroc_v101_static95/mav0/cam0/data");
  std::vector<std::string> files;
  if (dir.empty()) return files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".png") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

/// The pinhole part of EuRoC cam0 (the raw images are distorted; that does not matter for "does
/// not initialise").
inline PinholeIntrinsics eurocCam0() {
  PinholeIntrinsics K;
  K.fx = 458.654;
  K.fy = 457.296;
  K.cx = 367.215;
  K.cy = 248.375;
  K.width = 752;
  K.height = 480;
  return K;
}

/// Reads a grey image file into `image` (of its size); false when unreadable or of another size.
inline bool readGrey(const std::string& file, ImageF& image) {
  const cv::Mat grey = cv::imread(file, cv::IMREAD_GRAYSCALE);
  if (grey.cols != image.width() || grey.rows != image.height()) return false;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) image(x, y) = grey.at<std::uint8_t>(y, x);
  return true;
}

inline double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

struct InitRun {
  int completed_at = -1;  ///< index of the pose at which addFrame() returned true
  int failures = 0;
  int snaps = 0;            ///< frames that ended in kConfirming
  double max_flow = 0;      ///< largest translation flow seen
  double max_parallax = 0;  ///< largest rotation-free parallax seen
  double ms_per_frame = 0;  ///< CPU time of addFrame() (excluding the reference frame)
};

/// Renders the scene at each of `poses` (camera-to-world) and feeds the frames to `init`, until
/// it completes (when stop_at_complete). `on_frame` (optional) sees the initializer after each
/// frame.
inline InitRun runSequence(CoarseInitializer& init, const InitScene& scene,
                           const std::vector<SE3d>& poses, const PinholeIntrinsics& K, float noise,
                           unsigned seed, bool stop_at_complete, bool verbose = false) {
  std::mt19937 rng(seed);
  ImagePyramid pyramid(K.width, K.height, 5);
  InitRun run;
  double ms = 0;
  int timed = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const ImageF image = scene.render(poses[i], K, 2, noise, &rng);
    pyramid.build(image.view());
    const double t0 = threadCpuMs();
    const bool done = init.addFrame(pyramid, 1.0);
    const double t1 = threadCpuMs();
    if (i > 0) {
      ms += t1 - t0;
      ++timed;
    }
    const InitFrameStats& s = init.lastFrameStats();
    if (init.failed()) ++run.failures;
    if (init.status() == InitStatus::kConfirming) ++run.snaps;
    if (i > 0 && s.flow_translation > run.max_flow) run.max_flow = s.flow_translation;
    if (i > 0 && s.parallax > run.max_parallax) run.max_parallax = s.parallax;
    if (verbose) {
      const Eigen::Vector3d w = init.currentPose().so3().log() * 57.29578;
      std::printf(
          "frame %3zu: %-22s flow %6.2f par %5.2f rms %6.2f good %.2f it %3d  t=(%.4f %.4f %.4f) "
          "w=(%.3f %.3f %.3f)\n",
          i, toString(init.status()), s.flow_translation, s.parallax, s.rms_residual,
          s.good_fraction, s.iterations, init.currentPose().translation().x(),
          init.currentPose().translation().y(), init.currentPose().translation().z(), w.x(), w.y(),
          w.z());
    }
    if (done) {
      run.completed_at = static_cast<int>(i);
      if (stop_at_complete) break;
    }
  }
  run.ms_per_frame = timed > 0 ? ms / timed : 0;
  return run;
}

}  // namespace ldsm::init_test
