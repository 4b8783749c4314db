#include "ldsm/calib/camera_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "ldsm/camera/camera_model.h"
#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::string fmt(double v, int decimals = 2) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

void validate(const CameraCalibrationOptions& o, int width, int height) {
  if (o.model == CameraModelType::Fov)
    throw ConfigError("--model: the FOV model cannot be calibrated (pinhole, radtan, equidistant)");
  if (o.min_views < 3) throw ConfigError("camera calibration: min_views must be at least 3");
  if (!(o.blur_ratio > 1.0) || !(o.min_rejected_blur_px >= 0.0) || !(o.duplicate_fraction >= 0.0) ||
      !(o.outlier_ratio > 1.0))
    throw ConfigError(
        "camera calibration: blur_ratio and outlier_ratio must exceed 1, "
        "min_rejected_blur_px and duplicate_fraction must not be negative");
  if (width <= 0 || height <= 0)
    throw ConfigError("camera calibration: image size must be positive");
}

struct Solution {
  CameraIntrinsics intrinsics;
  std::vector<cv::Vec3d> rvecs, tvecs;
};

Solution solve(const std::vector<const BoardObservation*>& obs, int width, int height,
               CameraModelType model, const std::string& source) {
  std::vector<std::vector<cv::Point3f>> object(obs.size());
  std::vector<std::vector<cv::Point2f>> image(obs.size());
  for (std::size_t v = 0; v < obs.size(); ++v) {
    for (std::size_t k = 0; k < obs[v]->image_points.size(); ++k) {
      const auto& p = obs[v]->board_points[k];
      const auto& q = obs[v]->image_points[k];
      object[v].emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                             static_cast<float>(p.z()));
      image[v].emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
    }
  }
  const cv::Size size(width, height);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12);
  Solution s;
  s.intrinsics.model = model;
  s.intrinsics.width = width;
  s.intrinsics.height = height;
  try {
    cv::Mat K, D;
    std::vector<cv::Mat> rvecs, tvecs;
    const int pinhole_flags =
        cv::CALIB_FIX_K1 | cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
    cv::calibrateCamera(object, image, size, K, D, rvecs, tvecs,
                        model == CameraModelType::RadTan ? cv::CALIB_FIX_K3 : pinhole_flags,
                        criteria);
    if (model == CameraModelType::Equidistant) {
      // Start the fisheye model from the pinhole solution (its own start, f = width / pi, fails
      // on narrow lenses), and from scratch if that does not converge.
      std::vector<cv::Mat> obj64(obs.size()), img64(obs.size());
      for (std::size_t v = 0; v < obs.size(); ++v) {
        cv::Mat(object[v]).convertTo(obj64[v], CV_64FC3);
        cv::Mat(image[v]).convertTo(img64[v], CV_64FC2);
      }
      cv::Matx33d Kf = K;
      cv::Vec4d Df(0, 0, 0, 0);
      const int flags = cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW;
      std::vector<cv::Vec3d> rf, tf;
      try {
        cv::fisheye::calibrate(obj64, img64, size, Kf, Df, rf, tf,
                               flags | cv::fisheye::CALIB_USE_INTRINSIC_GUESS, criteria);
      } catch (const cv::Exception&) {
        Kf = cv::Matx33d::eye();
        Df = cv::Vec4d(0, 0, 0, 0);
        cv::fisheye::calibrate(obj64, img64, size, Kf, Df, rf, tf, flags, criteria);
      }
      s.intrinsics.fx = Kf(0, 0);
      s.intrinsics.fy = Kf(1, 1);
      s.intrinsics.cx = Kf(0, 2);
      s.intrinsics.cy = Kf(1, 2);
      s.intrinsics.distortion = {Df[0], Df[1], Df[2], Df[3]};
      s.rvecs = rf;
      s.tvecs = tf;
      return s;
    }
    s.intrinsics.fx = K.at<double>(0, 0);
    s.intrinsics.fy = K.at<double>(1, 1);
    s.intrinsics.cx = K.at<double>(0, 2);
    s.intrinsics.cy = K.at<double>(1, 2);
    if (model == CameraModelType::RadTan)
      s.intrinsics.distortion = {D.at<double>(0), D.at<double>(1), D.at<double>(2),
                                 D.at<double>(3)};
    for (std::size_t v = 0; v < obs.size(); ++v) {
      s.rvecs.emplace_back(rvecs[v].at<double>(0), rvecs[v].at<double>(1), rvecs[v].at<double>(2));
      s.tvecs.emplace_back(tvecs[v].at<double>(0), tvecs[v].at<double>(1), tvecs[v].at<double>(2));
    }
  } catch (const cv::Exception& e) {
    throw InputError(source + ": the calibration did not converge (" + e.err +
                     "); take more views with the board tilted in different directions");
  }
  return s;
}

/// Reprojection error of each corner of each view with the ldsm camera model (NaN where the model
/// cannot project the corner).
std::vector<std::vector<double>> reprojectionErrors(const std::vector<const BoardObservation*>& obs,
                                                    const Solution& s, const CameraModel& camera) {
  std::vector<std::vector<double>> errors(obs.size());
  for (std::size_t v = 0; v < obs.size(); ++v) {
    cv::Matx33d R;
    cv::Rodrigues(s.rvecs[v], R);
    for (std::size_t k = 0; k < obs[v]->board_points.size(); ++k) {
      const Eigen::Vector3d& X = obs[v]->board_points[k];
      Eigen::Vector3d p;
      for (int r = 0; r < 3; ++r)
        p(r) = R(r, 0) * X.x() + R(r, 1) * X.y() + R(r, 2) * X.z() + s.tvecs[v][r];
      Eigen::Vector2d px;
      errors[v].push_back(camera.project(p, &px) ? (px - obs[v]->image_points[k]).norm() : kNaN);
    }
  }
  return errors;
}

double rmsOf(const std::vector<double>& errors) {
  double sum = 0.0;
  for (const double e : errors) sum += std::isfinite(e) ? e * e : 1e6;
  return errors.empty() ? kNaN : std::sqrt(sum / static_cast<double>(errors.size()));
}

/// Fraction of the cells of an 8 x 6 grid over the image that hold at least one corner.
double coverage(const std::vector<Eigen::Vector2d>& corners, int width, int height) {
  constexpr int kCols = 8, kRows = 6;
  std::vector<bool> hit(kCols * kRows, false);
  for (const auto& c : corners) {
    const int cx = std::clamp(static_cast<int>(c.x() / width * kCols), 0, kCols - 1);
    const int cy = std::clamp(static_cast<int>(c.y() / height * kRows), 0, kRows - 1);
    hit[static_cast<std::size_t>(cy * kCols + cx)] = true;
  }
  return static_cast<double>(std::count(hit.begin(), hit.end(), true)) / (kCols * kRows);
}

std::string rejectionSummary(const std::vector<ViewReport>& views) {
  std::map<ViewStatus, int> count;
  for (const auto& v : views) ++count[v.status];
  std::string s;
  for (const ViewStatus st :
       {ViewStatus::NoBoard, ViewStatus::Blurred, ViewStatus::Duplicate, ViewStatus::Outlier})
    if (count[st] > 0)
      s += std::string(s.empty() ? "" : ", ") + toString(st) + ": " + std::to_string(count[st]);
  return s.empty() ? "none rejected" : s;
}

}  // namespace

const char* toString(ViewStatus status) {
  switch (status) {
    case ViewStatus::Used:
      return "used";
    case ViewStatus::NoBoard:
      return "no board";
    case ViewStatus::Blurred:
      return "blurred";
    case ViewStatus::Duplicate:
      return "duplicate";
    case ViewStatus::Outlier:
      return "outlier";
  }
  return "?";
}

CameraCalibrationResult calibrateCamera(const std::vector<BoardView>& views, int width, int height,
                                        const CameraCalibrationOptions& options,
                                        const std::string& source) {
  validate(options, width, height);
  CameraCalibrationResult result;
  std::vector<std::size_t> detected;
  for (std::size_t i = 0; i < views.size(); ++i) {
    ViewReport r;
    r.name = views[i].name;
    r.blur_px = kNaN;
    r.rms_px = kNaN;
    if (const auto& obs = views[i].observation) {
      if (obs->width != width || obs->height != height)
        throw InputError(source + ": " + views[i].name + " is " + std::to_string(obs->width) + "x" +
                         std::to_string(obs->height) + " but the other images are " +
                         std::to_string(width) + "x" + std::to_string(height));
      if (obs->image_points.size() != obs->board_points.size() ||
          obs->image_points.size() != obs->grid.size() || obs->image_points.size() < 4)
        throw InputError(source + ": " + views[i].name + ": inconsistent board observation");
      r.status = ViewStatus::Used;
      r.corners = static_cast<int>(obs->image_points.size());
      r.blur_px = obs->blur_px;
      detected.push_back(i);
    } else {
      r.reason = "board not found";
    }
    result.views.push_back(r);
  }
  if (detected.empty())
    throw InputError(source + ": the board was not found in any of the " +
                     std::to_string(views.size()) +
                     " images; check --board, that --cols and --rows count squares (not inner "
                     "corners), --marker and --dictionary for ChArUco, and that the whole board "
                     "is visible, in focus and evenly lit");

  // Blur, relative to the other views.
  std::vector<double> blurs;
  for (const std::size_t i : detected) blurs.push_back(result.views[i].blur_px);
  const double blur_median = median(blurs);
  const double blur_limit =
      std::max(options.blur_ratio * blur_median, options.min_rejected_blur_px);
  for (const std::size_t i : detected) {
    ViewReport& r = result.views[i];
    if (std::isfinite(blur_median) && std::isfinite(r.blur_px) && r.blur_px > blur_limit) {
      r.status = ViewStatus::Blurred;
      r.reason =
          "edge blur " + fmt(r.blur_px) + " px, the median view has " + fmt(blur_median) + " px";
    }
  }

  // Near-duplicates: the sharpest view of a group is kept.
  std::vector<std::size_t> order;
  for (const std::size_t i : detected)
    if (result.views[i].status == ViewStatus::Used) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const double ba = result.views[a].blur_px, bb = result.views[b].blur_px;
    return (std::isfinite(ba) ? ba : 1e9) < (std::isfinite(bb) ? bb : 1e9);
  });
  const double duplicate_px = options.duplicate_fraction * std::hypot(width, height);
  std::vector<std::size_t> kept;
  for (const std::size_t i : order) {
    const BoardObservation& obs = *views[i].observation;
    for (const std::size_t j : kept) {
      const double d = cornerDistance(*views[j].observation, obs);
      if (d < duplicate_px) {
        result.views[i].status = ViewStatus::Duplicate;
        result.views[i].reason = "board within " + fmt(d, 1) + " px of " + views[j].name;
        break;
      }
    }
    if (result.views[i].status == ViewStatus::Used) kept.push_back(i);
  }
  std::sort(kept.begin(), kept.end());

  auto requireViews = [&](std::size_t n) {
    if (static_cast<int>(n) >= options.min_views) return;
    throw InputError(source + ": only " + std::to_string(n) + " of " +
                     std::to_string(views.size()) + " images are usable (" +
                     rejectionSummary(result.views) + "); at least " +
                     std::to_string(options.min_views) +
                     " are needed: take more pictures of the whole board, held still, at "
                     "different distances and tilted in different directions, near the image "
                     "corners too");
  };
  requireViews(kept.size());

  std::unique_ptr<CameraModel> camera;
  Solution sol;
  std::vector<std::vector<double>> errors;
  for (int round = 0; round < 2; ++round) {
    std::vector<const BoardObservation*> obs;
    for (const std::size_t i : kept) obs.push_back(&*views[i].observation);
    sol = solve(obs, width, height, options.model, source);
    try {
      camera = makeCameraModel(sol.intrinsics);
    } catch (const InputError& e) {
      throw InputError(source + ": the calibration gave an invalid camera (" + e.what() +
                       "); take more views, with the board near the image corners too");
    }
    errors = reprojectionErrors(obs, sol, *camera);
    std::vector<double> rms;
    for (const auto& e : errors) rms.push_back(rmsOf(e));
    const double rms_median = median(rms);
    std::vector<std::size_t> inliers;
    for (std::size_t v = 0; v < kept.size(); ++v) {
      ViewReport& r = result.views[kept[v]];
      r.rms_px = rms[v];
      if (round == 0 && rms[v] > options.outlier_ratio * rms_median && rms[v] > 0.5) {
        r.status = ViewStatus::Outlier;
        r.reason = "reprojection RMS " + fmt(rms[v]) + " px, the median view has " +
                   fmt(rms_median) + " px";
      } else {
        inliers.push_back(kept[v]);
      }
    }
    if (inliers.size() == kept.size()) break;
    requireViews(inliers.size());
    for (const std::size_t i : kept)
      if (result.views[i].status == ViewStatus::Outlier) result.views[i].rms_px = kNaN;
    kept = inliers;
  }

  std::vector<double> all;
  for (std::size_t v = 0; v < kept.size(); ++v) {
    const BoardObservation& obs = *views[kept[v]].observation;
    for (std::size_t k = 0; k < errors[v].size(); ++k) {
      result.corners.push_back(obs.image_points[k]);
      result.corner_errors_px.push_back(errors[v][k]);
      all.push_back(errors[v][k]);
    }
  }
  result.rms_px = rmsOf(all);
  result.used_views = static_cast<int>(kept.size());
  result.calibration.input = sol.intrinsics;
  result.calibration.output.mode =
      options.model == CameraModelType::Pinhole ? OutputMode::None : OutputMode::Crop;
  result.calibration.output.width = width;
  result.calibration.output.height = height;

  const double cover = coverage(result.corners, width, height);
  if (cover < 0.6)
    result.warnings.push_back("the corners cover only " + fmt(100 * cover, 0) +
                              "% of the image; add views with the board near the edges and "
                              "corners, or the distortion there is extrapolated");
  if (result.rms_px > 1.0)
    result.warnings.push_back("reprojection RMS " + fmt(result.rms_px) +
                              " px is high; check the board is flat and its --square size, and "
                              "drop blurred images");
  if (result.used_views < 10)
    result.warnings.push_back("only " + std::to_string(result.used_views) +
                              " views used; 15-30 views give more reliable intrinsics");
  return result;
}

}  // namespace ldsm::calib
