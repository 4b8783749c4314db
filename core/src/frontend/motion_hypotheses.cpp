#include "frontend/motion_hypotheses.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace ldsm {

namespace {

constexpr int kBasicHypotheses = 5;

// Direction `index` of the 26 cube directions, unit length: the 6 axes first, then the 12 edge
// diagonals, then the 8 corner diagonals.
Eigen::Vector3d cubeDirection(int index) {
  int seen = 0;
  for (int nonzero = 1; nonzero <= 3; ++nonzero) {
    for (int i = -1; i <= 1; ++i) {
      for (int j = -1; j <= 1; ++j) {
        for (int k = -1; k <= 1; ++k) {
          if (std::abs(i) + std::abs(j) + std::abs(k) != nonzero) continue;
          if (seen++ == index) return Eigen::Vector3d(i, j, k).normalized();
        }
      }
    }
  }
  return Eigen::Vector3d::UnitX();
}

bool isSameMotion(const SE3d& a, const SE3d& b) {
  return (a.inverse() * b).log().norm() < 1e-9;
}

}  // namespace

const char* toString(MotionHypothesisKind kind) {
  switch (kind) {
    case MotionHypothesisKind::kConstantVelocity:
      return "constant velocity";
    case MotionHypothesisKind::kDoubleMotion:
      return "double motion";
    case MotionHypothesisKind::kHalfMotion:
      return "half motion";
    case MotionHypothesisKind::kZeroMotion:
      return "zero motion";
    case MotionHypothesisKind::kReferencePose:
      return "reference pose";
    case MotionHypothesisKind::kRotated:
      return "rotated";
  }
  return "unknown";
}

HypothesisSettings wideHypothesisSettings() {
  HypothesisSettings s;
  s.rotation_angles = {0.04, 0.08, 0.16, 0.24};
  s.rotation_angle_count = kMaxHypothesisAngles;
  return s;
}

int motionHypothesisCount(const HypothesisSettings& settings) {
  const int angles = std::clamp(settings.rotation_angle_count, 0, kMaxHypothesisAngles);
  return kBasicHypotheses + kRotationDirections * angles;
}

SE3d motionHypothesis(int index, const MotionHistory& history, const HypothesisSettings& settings,
                      MotionHypothesisKind* kind) {
  const SE3d V = history.has_velocity ? history.T_last_prelast : SE3d();
  const SE3d constant = V * history.T_last_ref;
  MotionHypothesisKind k = MotionHypothesisKind::kRotated;
  SE3d T = constant;
  switch (index) {
    case 0:
      k = MotionHypothesisKind::kConstantVelocity;
      break;
    case 1:
      k = MotionHypothesisKind::kDoubleMotion;
      T = V * constant;
      break;
    case 2:
      k = MotionHypothesisKind::kHalfMotion;
      T = SE3d::exp(0.5 * V.log()) * history.T_last_ref;
      break;
    case 3:
      k = MotionHypothesisKind::kZeroMotion;
      T = history.T_last_ref;
      break;
    case 4:
      k = MotionHypothesisKind::kReferencePose;
      T = SE3d();
      break;
    default: {
      // An extra rotation of the camera about its own centre: exp([0, w]) * T.
      const int r = index - kBasicHypotheses;
      const double angle =
          settings.rotation_angles[std::min(r / kRotationDirections, kMaxHypothesisAngles - 1)];
      SE3d::Tangent x = SE3d::Tangent::Zero();
      x.tail<3>() = angle * cubeDirection(r % kRotationDirections);
      T = SE3d::exp(x) * constant;
    }
  }
  if (kind != nullptr) *kind = k;
  return T;
}

namespace {

/// The search's state: the best result so far and the abort thresholds it implies.
class HypothesisSearch {
 public:
  HypothesisSearch(CoarseTracker& tracker, const ImagePyramid& frame, double exposure,
                   const MotionHistory& history, const HypothesisSettings& settings)
      : tracker_(tracker),
        frame_(frame),
        exposure_(exposure),
        history_(history),
        settings_(settings),
        abort_rmse_(noAbortThresholds()),
        coarsest_(tracker.levels() - 1) {
    best_.T_frame_ref = motionHypothesis(0, history, settings, nullptr);
    best_.affine = history.last_affine;
  }

  /// Tracks hypothesis i to level 0; true when the search is over (good enough).
  bool tryFully(int i) {
    MotionHypothesisKind kind;
    SE3d T = motionHypothesis(i, history_, settings_, &kind);
    AffineLight affine = history_.last_affine;
    CoarseTrackingResult tracking;
    ++best_.tried;
    if (!tracker_.track(frame_, exposure_, T, affine, coarsest_, abort_rmse_, tracking))
      return false;
    const double rmse = tracking.rmse(0);
    if (!(rmse < best_.rmse)) return false;
    best_.success = true;
    best_.hypothesis = i;
    best_.kind = kind;
    best_.rmse = rmse;
    best_.T_frame_ref = T;
    best_.affine = affine;
    best_.tracking = tracking;
    // Later hypotheses must do clearly better on every level, or they stop early.
    for (int l = 0; l <= coarsest_; ++l) {
      if (std::isfinite(tracking.rmse(l)))
        abort_rmse_(l) = tracking.rmse(l) * settings_.retrack_threshold;
    }
    return rmse < history_.last_rmse * settings_.retrack_threshold;
  }

  /// The coarsest-level RMSE of hypothesis i (infinity when it fails there).
  double screen(int i) {
    SE3d T = motionHypothesis(i, history_, settings_, nullptr);
    AffineLight affine = history_.last_affine;
    CoarseTrackingResult tracking;
    ++best_.screened;
    if (!tracker_.track(frame_, exposure_, T, affine, coarsest_, abort_rmse_, tracking, coarsest_))
      return std::numeric_limits<double>::infinity();
    return tracking.rmse(coarsest_);
  }

  const HypothesisTrackingResult& best() const { return best_; }

 private:
  CoarseTracker& tracker_;
  const ImagePyramid& frame_;
  double exposure_;
  const MotionHistory& history_;
  const HypothesisSettings& settings_;
  LevelValues abort_rmse_;
  int coarsest_;
  HypothesisTrackingResult best_;
};

}  // namespace

HypothesisTrackingResult trackWithHypotheses(CoarseTracker& tracker, const ImagePyramid& frame,
                                             double exposure, const MotionHistory& history,
                                             const HypothesisSettings& settings) {
  HypothesisSearch search(tracker, frame, exposure, history, settings);
  const SE3d constant_velocity = motionHypothesis(0, history, settings, nullptr);
  for (int i = 0; i < kBasicHypotheses; ++i) {
    // Skip basic hypotheses equal to the constant-velocity guess (e.g. without a velocity,
    // double / half / zero motion are all the same).
    if (i >= 1 && isSameMotion(motionHypothesis(i, history, settings, nullptr), constant_velocity))
      continue;
    if (search.tryFully(i)) return search.best();
  }
  const int count = motionHypothesisCount(settings);
  if (settings.screened_rotations <= 0) {
    for (int i = kBasicHypotheses; i < count; ++i)
      if (search.tryFully(i)) break;
    return search.best();
  }
  // Screened: every rotated hypothesis at the coarsest level, the best few in full. The fixed
  // array keeps this free of allocation (at most 26 * kMaxHypothesisAngles of them).
  std::array<std::pair<double, int>, kRotationDirections * kMaxHypothesisAngles> screened;
  int n = 0;
  for (int i = kBasicHypotheses; i < count; ++i) {
    const double rmse = search.screen(i);
    if (std::isfinite(rmse)) screened[static_cast<std::size_t>(n++)] = {rmse, i};
  }
  const int refined = std::min(n, settings.screened_rotations);
  std::partial_sort(screened.begin(), screened.begin() + refined, screened.begin() + n);
  for (int k = 0; k < refined; ++k)
    if (search.tryFully(screened[static_cast<std::size_t>(k)].second)) break;
  return search.best();
}

}  // namespace ldsm
