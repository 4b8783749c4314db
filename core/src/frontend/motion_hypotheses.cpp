#include "frontend/motion_hypotheses.h"

#include <algorithm>
#include <cmath>

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

HypothesisTrackingResult trackWithHypotheses(CoarseTracker& tracker, const ImagePyramid& frame,
                                             double exposure, const MotionHistory& history,
                                             const HypothesisSettings& settings) {
  HypothesisTrackingResult best;
  const SE3d constant_velocity = motionHypothesis(0, history, settings, nullptr);
  best.T_frame_ref = constant_velocity;
  best.affine = history.last_affine;
  LevelValues abort_rmse = noAbortThresholds();
  const int coarsest = tracker.levels() - 1;
  const int count = motionHypothesisCount(settings);
  for (int i = 0; i < count; ++i) {
    MotionHypothesisKind kind;
    SE3d T = motionHypothesis(i, history, settings, &kind);
    // Skip basic hypotheses equal to the constant-velocity guess (e.g. without a velocity,
    // double / half / zero motion are all the same).
    if (i >= 1 && i < kBasicHypotheses && isSameMotion(T, constant_velocity)) continue;
    AffineLight affine = history.last_affine;
    CoarseTrackingResult tracking;
    ++best.tried;
    if (!tracker.track(frame, exposure, T, affine, coarsest, abort_rmse, tracking)) continue;
    const double rmse = tracking.rmse(0);
    if (!(rmse < best.rmse)) continue;
    best.success = true;
    best.hypothesis = i;
    best.kind = kind;
    best.rmse = rmse;
    best.T_frame_ref = T;
    best.affine = affine;
    best.tracking = tracking;
    // Later hypotheses must do clearly better on every level, or they stop early.
    for (int l = 0; l <= coarsest; ++l) {
      if (std::isfinite(tracking.rmse(l)))
        abort_rmse(l) = tracking.rmse(l) * settings.retrack_threshold;
    }
    if (rmse < history.last_rmse * settings.retrack_threshold) break;
  }
  return best;
}

}  // namespace ldsm
