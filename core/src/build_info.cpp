#include "ldsm/build_info.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/core/version.hpp>

#include "ldsm/version.h"

namespace ldsm {

BuildInfo buildInfo() {
  BuildInfo b;
  b.version = versionString();
#if defined(LDSM_SIMD_SSE)
  b.simd = "sse";
#elif defined(LDSM_SIMD_NEON)
  b.simd = "neon";
#else
  b.simd = "scalar";
#endif
  b.opencv_version = CV_VERSION;
  b.opencv_optimized = cv::useOptimized();
  b.opencv_cpu_features = cv::getCPUFeaturesLine();
  return b;
}

}  // namespace ldsm
