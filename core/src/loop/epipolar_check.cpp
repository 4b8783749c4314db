#include "loop/epipolar_check.h"

#include <algorithm>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "ldsm/error.h"

namespace ldsm::loop {

EpipolarCheckResult checkEpipolar(const std::vector<Eigen::Vector2f>& a,
                                  const std::vector<Eigen::Vector2f>& b,
                                  const std::vector<DescriptorMatch>& matches,
                                  const EpipolarCheckSettings& settings) {
  EpipolarCheckResult r;
  r.matches = static_cast<int>(matches.size());
  if (r.matches < 8 || r.matches < settings.min_inliers) return r;
  std::vector<cv::Point2f> pa;
  std::vector<cv::Point2f> pb;
  pa.reserve(matches.size());
  pb.reserve(matches.size());
  for (const DescriptorMatch& m : matches) {
    if (m.query >= a.size() || m.train >= b.size()) {
      throw InputError("epipolar check: match (" + std::to_string(m.query) + ", " +
                       std::to_string(m.train) + ") out of range (" + std::to_string(a.size()) +
                       " and " + std::to_string(b.size()) + " features)");
    }
    pa.emplace_back(a[m.query].x(), a[m.query].y());
    pb.emplace_back(b[m.train].x(), b[m.train].y());
  }
  std::vector<std::uint8_t> mask;
  const cv::Mat f = cv::findFundamentalMat(pa, pb, cv::FM_RANSAC, settings.threshold_px,
                                           settings.confidence, settings.max_iterations, mask);
  if (f.empty() || mask.size() != matches.size()) return r;
  r.inliers = static_cast<int>(std::count(mask.begin(), mask.end(), std::uint8_t{1}));
  r.accepted = r.inliers >= settings.min_inliers;
  return r;
}

}  // namespace ldsm::loop
