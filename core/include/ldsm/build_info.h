// What this build of the engine computes with, so that figures from different machines are never
// compared blindly: the SIMD kernels compiled in, and OpenCV's version and the CPU features its
// run-time dispatch uses (ORB and FAST in loop closure pick code paths by CPU).
#pragma once

#include <string>

namespace ldsm {

struct BuildInfo {
  std::string version;              ///< ldsm, "major.minor.patch"
  std::string simd;                 ///< the engine's SIMD kernels: "sse", "neon" or "scalar"
  std::string opencv_version;       ///< e.g. "4.6.0"
  bool opencv_optimized = true;     ///< cv::useOptimized(): OpenCV's optimised code paths on
  std::string opencv_cpu_features;  ///< cv::getCPUFeaturesLine(): baseline and dispatched
};

BuildInfo buildInfo();

}  // namespace ldsm
