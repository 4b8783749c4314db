// Linked into every test executable: the diagnostic switches of docs/determinism.md, so that the
// whole suite can be run as if on another machine.
//   LDSM_CV_UNOPTIMIZED=1  OpenCV's run-time dispatched (SSE4/AVX/AVX-512) code paths off
//   OPENBLAS_CORETYPE=...  read by OpenBLAS itself, when it is the BLAS the process loads
#include <cstdlib>
#include <string>

#include <opencv2/core/utility.hpp>

namespace {

const bool kApplied = [] {
  const char* v = std::getenv("LDSM_CV_UNOPTIMIZED");
  if (v != nullptr && std::string(v) == "1") cv::setUseOptimized(false);
  return true;
}();

}  // namespace
