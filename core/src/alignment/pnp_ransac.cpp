#include "alignment/pnp_ransac.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "ldsm/error.h"

namespace ldsm {
namespace {

constexpr int kSampleSize = 4;  // AP3P: three correspondences solve, the fourth picks a solution
// The bound of pnpSamplesForInliers counts a clean sample as finding every inlier; with noisy
// corners its pose often keeps fewer, and a pose with exactly min_inliers needs several clean
// samples: at the bound itself vamr_desk_loop's relocalisation after a gap found 14 inliers of
// 39 where the full run found 15 (the minimum), and rendered correspondences with exactly 15 of
// 20-29 right 30 of the full run's 34 successes (all 34 at three and at ten times the bound:
// PnpRansac.CappedSamplesKeepTheSuccessesOfTheFullRun). Ten times the bound. (Measured before
// the inliers were counted again against the refined pose, which keeps the inlier or two a clean
// sample's pose misses: 40 of 40 in both since.)
constexpr int kBoundMultiple = 10;
// Refinements in all: one on RANSAC's inliers, then on each larger recounted set (a second
// recount rarely adds any).
constexpr int kRefinements = 3;

// Levenberg-Marquardt on the correspondences `inliers` from (rvec, tvec); false (pose unchanged)
// when it fails or leaves a non-finite pose.
bool refineOnInliers(const std::vector<cv::Point3d>& object, const std::vector<cv::Point2d>& image,
                     const cv::Matx33d& K, const std::vector<int>& inliers, cv::Mat& rvec,
                     cv::Mat& tvec) {
  std::vector<cv::Point3d> inlier_object;
  std::vector<cv::Point2d> inlier_image;
  for (const int i : inliers) {
    inlier_object.push_back(object[static_cast<std::size_t>(i)]);
    inlier_image.push_back(image[static_cast<std::size_t>(i)]);
  }
  cv::Mat rvec_lm = rvec.clone(), tvec_lm = tvec.clone();
  try {
    if (cv::solvePnP(inlier_object, inlier_image, K, cv::noArray(), rvec_lm, tvec_lm, true,
                     cv::SOLVEPNP_ITERATIVE) &&
        cv::checkRange(rvec_lm) && cv::checkRange(tvec_lm)) {
      rvec = rvec_lm;
      tvec = tvec_lm;
      return true;
    }
  } catch (const cv::Exception&) {
    // a degenerate inlier set: the pose before stands
  }
  return false;
}

// OpenCV's pose (Rodrigues vector, translation) as a rotation matrix and a translation.
void poseFromOpenCv(const cv::Mat& rvec, const cv::Mat& tvec, Eigen::Matrix3d& R,
                    Eigen::Vector3d& t) {
  cv::Matx33d Rcv;
  cv::Rodrigues(rvec, Rcv);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = Rcv(r, c);
  }
  t = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
}

// The correspondences (increasing indices) that the pose (R, t) projects in front of the camera
// within `threshold_px` of their pixels (OpenCV's RANSAC inlier test, plus depth > 0).
std::vector<int> reprojectionInliers(const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<Eigen::Vector2d>& pixels,
                                     const PinholeIntrinsics& camera, const Eigen::Matrix3d& R,
                                     const Eigen::Vector3d& t, double threshold_px) {
  std::vector<int> inliers;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = R * points[i] + t;
    if (!(p.z() > 0)) continue;
    const Eigen::Vector2d error(camera.fx * p.x() / p.z() + camera.cx - pixels[i].x(),
                                camera.fy * p.y() / p.z() + camera.cy - pixels[i].y());
    if (error.squaredNorm() <= threshold_px * threshold_px) inliers.push_back(static_cast<int>(i));
  }
  return inliers;
}

}  // namespace

int pnpSamplesForInliers(int correspondences, int inliers, double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0))
    throw InputError("PnP RANSAC: confidence must be in (0, 1)");
  if (correspondences <= 0 || inliers <= 0 || inliers > correspondences) return 0;
  const double clean = std::pow(static_cast<double>(inliers) / correspondences, kSampleSize);
  if (clean >= 1.0) return 1;
  // log1p: a tiny clean probability still gives a huge count (log(1 - 1e-17) rounds to 0).
  const double n = std::ceil(std::log1p(-confidence) / std::log1p(-clean));
  constexpr double kMostSamples = 1e9;
  return !(n < kMostSamples) ? static_cast<int>(kMostSamples) : n < 1.0 ? 1 : static_cast<int>(n);
}

int pnpRansacSamples(const PnpRansacSettings& settings, int correspondences) {
  if (!settings.cap_samples_for_min_inliers) return settings.max_iterations;
  if (correspondences < settings.min_inliers) return 0;
  const int bound = pnpSamplesForInliers(
      correspondences, std::max(settings.min_inliers, kSampleSize), settings.confidence);
  return bound < settings.max_iterations / kBoundMultiple ? kBoundMultiple * bound
                                                          : settings.max_iterations;
}

PnpRansacResult solvePnpRansac(const std::vector<Eigen::Vector3d>& points,
                               const std::vector<Eigen::Vector2d>& pixels,
                               const PinholeIntrinsics& camera, const PnpRansacSettings& settings) {
  if (points.size() != pixels.size()) {
    throw InputError("PnP RANSAC: " + std::to_string(points.size()) + " points but " +
                     std::to_string(pixels.size()) + " pixels");
  }
  if (!(camera.fx > 0 && camera.fy > 0 && std::isfinite(camera.cx) && std::isfinite(camera.cy) &&
        std::isfinite(camera.fx) && std::isfinite(camera.fy))) {
    throw InputError("PnP RANSAC: invalid pinhole intrinsics (fx, fy must be finite and > 0)");
  }
  if (settings.max_iterations < 1 || !(settings.inlier_threshold_px > 0) ||
      !(settings.confidence > 0 && settings.confidence < 1) || settings.min_inliers < 0) {
    throw InputError("PnP RANSAC: settings out of range");
  }
  PnpRansacResult result;
  constexpr std::size_t kMinCorrespondences = 6;
  if (points.size() < kMinCorrespondences) return result;
  const int iterations = pnpRansacSamples(settings, static_cast<int>(points.size()));
  if (iterations == 0) return result;

  std::vector<cv::Point3d> object(points.size());
  std::vector<cv::Point2d> image(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || !pixels[i].allFinite()) {
      throw InputError("PnP RANSAC: correspondence " + std::to_string(i) + " is not finite");
    }
    object[i] = cv::Point3d(points[i].x(), points[i].y(), points[i].z());
    image[i] = cv::Point2d(pixels[i].x(), pixels[i].y());
  }
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  bool ok = false;
  try {
    // Minimal samples of four correspondences (AP3P: three solve, the fourth picks among the
    // solutions) rather than the five of EPnP: with 12 of 36 matches right one sample in 120 is
    // clean instead of one in 480, and each is cheaper. 300 five-point samples missed the pose
    // at such ratios in 6 of 43 synthetic scenes (docs/loop-closure.md).
    ok = cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, iterations,
                            static_cast<float>(settings.inlier_threshold_px), settings.confidence,
                            inliers, cv::SOLVEPNP_AP3P);
  } catch (const cv::Exception&) {
    ok = false;  // degenerate configurations make some OpenCV solvers throw: no pose
  }
  // OpenCV ends an AP3P RANSAC with EPnP on the inliers; Levenberg-Marquardt from there
  // minimises their reprojection error (what the iterative solver's RANSAC ended with). RANSAC
  // stops drawing as soon as the inlier share it has found makes a better sample unlikely, so
  // with noisy corners its best pose may keep fewer inliers than the refined pose does (11 of 15
  // exact correspondences with 0.5 px noise on one machine, all 15 on another): the inliers are
  // counted again against the refined pose, and a larger set is refined once more. Should a
  // refinement fail, the pose before it stands.
  for (int round = 0; ok && inliers.size() >= kMinCorrespondences && round < kRefinements;
       ++round) {
    if (!refineOnInliers(object, image, K, inliers, rvec, tvec)) break;
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    poseFromOpenCv(rvec, tvec, R, t);
    std::vector<int> recounted =
        reprojectionInliers(points, pixels, camera, R, t, settings.inlier_threshold_px);
    if (recounted.size() <= inliers.size()) break;
    inliers = std::move(recounted);
  }
  if (!ok || rvec.empty() || tvec.empty()) {
    result.inliers = std::move(inliers);
    return result;
  }
  Eigen::Matrix3d Re;
  Eigen::Vector3d t;
  poseFromOpenCv(rvec, tvec, Re, t);
  std::sort(inliers.begin(), inliers.end());
  if (!Re.allFinite() || !t.allFinite()) {
    result.inliers = std::move(inliers);
    return result;
  }
  result.has_pose = true;
  result.T_camera_points = SE3d(Re, t);
  result.success = static_cast<int>(inliers.size()) >= settings.min_inliers;
  result.inliers = std::move(inliers);
  return result;
}

}  // namespace ldsm
