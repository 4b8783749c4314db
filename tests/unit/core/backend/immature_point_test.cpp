#include "backend/immature_point.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "features/pixel_selector.h"
#include "ldsm/error.h"
#include "synthetic_images.h"

namespace ldsm {
namespace {

using test::makePyramid;
using test::PlaneScene;

SE3d pose(const Eigen::Vector3d& rotation, const Eigen::Vector3d& translation) {
  return SE3d(SO3d::exp(rotation), translation);
}

/// Keyframe 1 at the origin; frames 2 and 3 translated (20 and 45 cm, mostly sideways) and
/// slightly rotated, looking at a tilted textured plane about 3 m away.
class PlaneTrace : public ::testing::Test {
 protected:
  void SetUp() override {
    T_w_c[0] = SE3d();
    T_w_c[1] = pose({0.01, -0.02, 0.005}, {0.2, 0.03, 0.05});
    T_w_c[2] = pose({-0.01, 0.03, 0.01}, {0.45, -0.05, 0.1});
    for (int i = 0; i < 3; ++i) {
      images[i] = scene.render(T_w_c[i]);
      pyramids.push_back(makePyramid(images[i], 1));
    }
    PointSelectionConfig config;
    config.points_per_keyframe = 600;
    PixelSelector selector(scene.intrinsics.width, scene.intrinsics.height, config);
    const ImagePyramid host4 = makePyramid(images[0], 3);
    selector.select(host4, 1.f, selected);
    ASSERT_GT(selected.size(), 400u);
  }

  SE3f targetFromHost(int target) const {
    return (T_w_c[target].inverse() * T_w_c[0]).cast<float>();
  }
  double trueIdepth(float u, float v) const { return 1.0 / scene.depth(T_w_c[0], u, v); }
  ImageView<const GradientPixel> gradients(int i) const { return pyramids[i].gradients(0); }

  PlaneScene scene;
  SE3d T_w_c[3];
  ImageF images[3];
  std::vector<ImagePyramid> pyramids;
  std::vector<SelectedPixel> selected;
  TraceSettings settings;
};

double relativeError(const ImmaturePoint& p, double truth) {
  return std::abs(p.idepthEstimate() - truth) / truth;
}

TEST_F(PlaneTrace, ConvergesToTheTrueInverseDepth) {
  const LevelCamera cam = scene.camera();
  std::vector<ImmaturePoint> points;
  for (const auto& s : selected) points.emplace_back(gradients(0), s.u, s.v);

  std::map<TraceStatus, int> status;
  int good = 0, bracketed = 0, accurate = 0;
  for (auto& p : points) {
    ++status[p.trace(gradients(1), cam, targetFromHost(1), {1.f, 0.f}, settings)];
    if (p.lastStatus() != TraceStatus::kGood) continue;
    ++good;
    const double truth = trueIdepth(p.u(), p.v());
    bracketed += p.idepthMin() <= truth && truth <= p.idepthMax();
    accurate += relativeError(p, truth) < 0.05;
  }
  const int n = static_cast<int>(points.size());
  EXPECT_GE(good, 0.9 * n) << "OOB " << status[TraceStatus::kOob] << " OUTLIER "
                           << status[TraceStatus::kOutlier] << " BADCONDITION "
                           << status[TraceStatus::kBadCondition];
  EXPECT_GE(bracketed, 0.9 * good);
  EXPECT_GE(accurate, 0.9 * good);

  // A third frame with a longer baseline narrows the intervals further (points near the left
  // border leave the view).
  std::vector<double> errors;
  int visible = 0, converged = 0;
  for (auto& p : points) {
    if (p.lastStatus() != TraceStatus::kGood) continue;
    const double width_before = p.idepthMax() - p.idepthMin();
    const TraceStatus s = p.trace(gradients(2), cam, targetFromHost(2), {1.f, 0.f}, settings);
    if (s == TraceStatus::kGood) {
      EXPECT_LT(p.idepthMax() - p.idepthMin(), width_before);
    }
    if (s == TraceStatus::kOob) continue;
    ++visible;
    if (!p.isConverged(0.1f, 3.f)) continue;
    ++converged;
    errors.push_back(relativeError(p, trueIdepth(p.u(), p.v())));
  }
  EXPECT_GT(visible, 0.6 * good);
  EXPECT_GE(converged, 0.8 * visible);
  ASSERT_FALSE(errors.empty());
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.01);       // median
  EXPECT_LT(errors[errors.size() * 9 / 10], 0.03);  // 90th percentile
}

TEST_F(PlaneTrace, CompensatesAffineBrightness) {
  // Frame 2 with exposure-like change I' = 1.3 I + 10, traced with that transfer.
  ImageF bright = images[1];
  for (int y = 0; y < bright.height(); ++y)
    for (int x = 0; x < bright.width(); ++x) bright(x, y) = 1.3f * bright(x, y) + 10.f;
  const ImagePyramid target = makePyramid(bright, 1);
  int good = 0, accurate = 0;
  for (const auto& s : selected) {
    ImmaturePoint p(gradients(0), s.u, s.v);
    if (p.trace(target.gradients(0), scene.camera(), targetFromHost(1), {1.3f, 10.f}, settings) !=
        TraceStatus::kGood) {
      continue;
    }
    ++good;
    accurate += relativeError(p, trueIdepth(s.u, s.v)) < 0.05;
  }
  EXPECT_GE(good, 0.9 * selected.size());
  EXPECT_GE(accurate, 0.9 * good);
}

TEST_F(PlaneTrace, WrongBrightnessOffsetIsAnOutlier) {
  // After a good first trace, frame 3 is traced with a brightness offset 40 grey levels too high:
  // no position in the (narrow) interval matches.
  int traced = 0, outliers = 0;
  for (const auto& s : selected) {
    ImmaturePoint p(gradients(0), s.u, s.v);
    if (p.trace(gradients(1), scene.camera(), targetFromHost(1), {1.f, 0.f}, settings) !=
        TraceStatus::kGood) {
      continue;
    }
    const float before_min = p.idepthMin();
    const TraceStatus status =
        p.trace(gradients(2), scene.camera(), targetFromHost(2), {1.f, 40.f}, settings);
    if (status == TraceStatus::kOob || status == TraceStatus::kSkipped ||
        status == TraceStatus::kBadCondition) {
      continue;
    }
    ++traced;
    if (status == TraceStatus::kOutlier) {
      ++outliers;
      EXPECT_EQ(p.outlierCount(), 1);
      EXPECT_EQ(p.idepthMin(), before_min);  // the interval is kept
      EXPECT_FALSE(p.isConverged(1e9f, 0.f));
    }
  }
  EXPECT_GT(traced, 0.5 * selected.size());
  EXPECT_GE(outliers, 0.98 * traced);
}

TEST_F(PlaneTrace, ZeroTranslationIsSkipped) {
  const SE3f rotation_only(SO3f::exp(Eigen::Vector3f(0.01f, -0.02f, 0.005f)),
                           Eigen::Vector3f::Zero());
  for (const SE3f& T : {SE3f(), rotation_only}) {
    for (std::size_t i = 0; i < selected.size(); i += 10) {
      const SelectedPixel& s = selected[i];
      if (s.u < 30 || s.v < 30 || s.u > 290 || s.v > 210) continue;  // stays in view
      ImmaturePoint p(gradients(0), s.u, s.v, 0.2f, 0.5f);
      EXPECT_EQ(p.trace(gradients(0), scene.camera(), T, {1.f, 0.f}, settings),
                TraceStatus::kSkipped);
      EXPECT_EQ(p.idepthMin(), 0.2f);
      EXPECT_EQ(p.idepthMax(), 0.5f);
    }
  }
}

TEST_F(PlaneTrace, ConvergedIntervalIsSkipped) {
  // A +-0.1 % interval projects to far less than 1.5 px for a 20 cm baseline at 3 m.
  int skipped = 0, visible = 0;
  for (const auto& s : selected) {
    const auto truth = static_cast<float>(trueIdepth(s.u, s.v));
    ImmaturePoint p(gradients(0), s.u, s.v, 0.999f * truth, 1.001f * truth);
    const TraceStatus status =
        p.trace(gradients(1), scene.camera(), targetFromHost(1), {1.f, 0.f}, settings);
    if (status == TraceStatus::kOob) continue;  // left the view
    ++visible;
    skipped += status == TraceStatus::kSkipped;
    EXPECT_LT(p.lastPixelInterval(), 1.5f);
  }
  EXPECT_GT(visible, 0.8 * selected.size());
  EXPECT_EQ(skipped, visible);
}

TEST_F(PlaneTrace, MatchOutsideTheImageIsOob) {
  // Move 60 cm to the right: the scene shifts ~60 px left; points near the left border leave.
  const SE3f T_t_h = (pose({0, 0, 0}, {0.6, 0, 0}).inverse()).cast<float>();
  int left = 0, kept = 0;
  for (const auto& s : selected) {
    const auto truth = static_cast<float>(trueIdepth(s.u, s.v));
    ImmaturePoint p(gradients(0), s.u, s.v, 0.97f * truth, 1.03f * truth);
    const TraceStatus status = p.trace(gradients(0), scene.camera(), T_t_h, {1.f, 0.f}, settings);
    if (s.u < 40) {
      ++left;
      EXPECT_EQ(status, TraceStatus::kOob) << s.u << ", " << s.v;
    } else if (s.u > 100) {
      ++kept;
      EXPECT_NE(status, TraceStatus::kOob) << s.u << ", " << s.v;
    }
  }
  EXPECT_GT(left, 10);
  EXPECT_GT(kept, 100);

  // Turned 70 degrees away: nothing of the interval is visible.
  const SE3f away = (pose({0, 1.2, 0}, {0.1, 0, 0}).inverse()).cast<float>();
  for (std::size_t i = 0; i < selected.size(); i += 10) {
    ImmaturePoint p(gradients(0), selected[i].u, selected[i].v);
    EXPECT_EQ(p.trace(gradients(0), scene.camera(), away, {1.f, 0.f}, settings), TraceStatus::kOob);
  }
}

TEST_F(PlaneTrace, RotatedPatternMatchesBetterUnderRoll) {
  // Frame rolled by 0.3 rad about the optical axis: the pattern mapped through the rotation
  // matches with a lower energy than the unrotated one, and the depths stay right.
  const SE3d T_w_r = pose({0.0, 0.0, 0.3}, {0.2, 0.02, 0.0});
  const ImagePyramid rolled = makePyramid(scene.render(T_w_r), 1);
  const SE3f T_t_h = (T_w_r.inverse() * T_w_c[0]).cast<float>();
  double energy[2] = {0, 0};
  int good[2] = {0, 0}, accurate = 0;
  for (const auto& s : selected) {
    ImmaturePoint with(gradients(0), s.u, s.v), without(gradients(0), s.u, s.v);
    TraceSettings plain = settings;
    plain.rotate_pattern = false;
    const bool ok_with = with.trace(rolled.gradients(0), scene.camera(), T_t_h, {1.f, 0.f},
                                    settings) == TraceStatus::kGood;
    const bool ok_without = without.trace(rolled.gradients(0), scene.camera(), T_t_h, {1.f, 0.f},
                                          plain) == TraceStatus::kGood;
    good[0] += ok_with;
    good[1] += ok_without;
    if (!ok_with || !ok_without) continue;
    energy[0] += with.lastEnergy();
    energy[1] += without.lastEnergy();
    accurate += relativeError(with, trueIdepth(s.u, s.v)) < 0.05;
  }
  EXPECT_GE(good[0], 0.98 * good[1]);
  EXPECT_LT(energy[0], 0.7 * energy[1]) << energy[0] / energy[1];
  EXPECT_GE(accurate, 0.85 * good[1]);
}

/// Host image varying along x only; the target is the view of a fronto-parallel plane at depth
/// kDepth after the camera moved by t: target(x, y) = host(x + f tx / Z, y + f ty / Z).
constexpr double kDepth = 2.0;
double stripes(double x, double /*y*/) {
  return 128.0 + 50.0 * std::sin(0.31 * x) + 30.0 * std::sin(0.113 * x + 1.0) +
         15.0 * std::sin(0.71 * x + 0.4);
}

struct StripeTrace {
  float width_px;  ///< new interval width converted to pixels of disparity
  TraceStatus status;
  double estimate_error;
};

StripeTrace traceStripes(double angle) {
  const PlaneScene scene;  // only for its intrinsics
  const double f = scene.intrinsics.fx;
  const Eigen::Vector3d t(0.15 * std::cos(angle), 0.15 * std::sin(angle), 0.0);
  const int w = scene.intrinsics.width, h = scene.intrinsics.height;
  const ImagePyramid host = makePyramid(test::renderImage(w, h, stripes), 1);
  const ImagePyramid target =
      makePyramid(test::renderImage(
                      w, h, [&](double x, double y) { return stripes(x + f * t.x() / kDepth, y); }),
                  1);
  // Camera moved by t: T_target_host = (translation t)^-1.
  const SE3f T_t_h(Eigen::Matrix3f::Identity(), (-t).cast<float>());
  ImmaturePoint p(host.gradients(0), 150.f, 120.f);
  TraceSettings settings;
  const TraceStatus status =
      p.trace(target.gradients(0), scene.camera(), T_t_h, {1.f, 0.f}, settings);
  const double disparity_per_idepth = f * t.norm();
  return {static_cast<float>((p.idepthMax() - p.idepthMin()) * disparity_per_idepth), status,
          std::abs(p.idepthEstimate() * kDepth - 1.0)};
}

TEST(ImmaturePointTrace, GradientAlignedWithTheLineIsBestConstrained) {
  const TraceSettings settings;
  const StripeTrace aligned = traceStripes(0.0);
  ASSERT_EQ(aligned.status, TraceStatus::kGood);
  EXPECT_LT(aligned.estimate_error, 0.02);
  // Interval = +-(matching_error + epipolar_error / cos(angle)) pixels along the line.
  EXPECT_NEAR(aligned.width_px, 2 * (settings.matching_error + settings.epipolar_error), 0.02);
  const StripeTrace oblique = traceStripes(M_PI / 3);  // cos = 0.5
  ASSERT_EQ(oblique.status, TraceStatus::kGood);
  EXPECT_LT(oblique.estimate_error, 0.04);
  EXPECT_NEAR(oblique.width_px, 2 * (settings.matching_error + 2 * settings.epipolar_error), 0.02);
  // Line along the stripes: the image does not change along it.
  EXPECT_EQ(traceStripes(M_PI / 2).status, TraceStatus::kBadCondition);
}

TEST(ImmaturePointCreate, ReadsPatternAndWeights) {
  const ImageF img =
      test::renderImage(64, 48, [](double x, double y) { return 3.0 * x + 0.5 * y * y; });
  const ImagePyramid pyr = makePyramid(img, 1);
  ImmaturePoint p(pyr.gradients(0), 20.f, 30.5f);
  for (int k = 0; k < kPatternSize; ++k) {
    const double x = 20 + kPatternOffsets[k][0], y = 30.5 + kPatternOffsets[k][1];
    // Bilinear interpolation between rows of a quadratic: exact in x, +0.25 * 0.5 * 1 in y.
    EXPECT_NEAR(p.colors()[k], 3 * x + 0.5 * y * y + 0.125, 1e-3);
    const double gx = 3, gy = y;  // central differences of the quadratic are exact
    EXPECT_NEAR(p.weights()[k], 2500 / (2500 + gx * gx + gy * gy), 1e-4);
  }
  EXPECT_EQ(p.lastStatus(), TraceStatus::kUntraced);
  EXPECT_EQ(p.idepthMin(), 0.f);
  EXPECT_TRUE(std::isinf(p.idepthMax()));
  EXPECT_FALSE(p.isConverged(1e9f, 0.f));
}

TEST(ImmaturePointCreate, RejectsBadInput) {
  ImageF img(64, 48, 10.f);
  const ImagePyramid pyr = makePyramid(img, 1);
  EXPECT_THROW(ImmaturePoint(pyr.gradients(0), 1.f, 20.f), InputError);   // pattern leaves left
  EXPECT_THROW(ImmaturePoint(pyr.gradients(0), 30.f, 46.f), InputError);  // and bottom
  EXPECT_THROW(ImmaturePoint(pyr.gradients(0), std::nanf(""), 20.f), InputError);
  EXPECT_THROW(ImmaturePoint(pyr.gradients(0), 30.f, 20.f, -1.f), InputError);
  EXPECT_THROW(ImmaturePoint(pyr.gradients(0), 30.f, 20.f, 2.f, 1.f), InputError);
  EXPECT_THROW(ImmaturePoint(pyr.gradients(0), 30.f, 20.f, std::nanf(""), 1.f), InputError);
  img(30, 20) = std::numeric_limits<float>::quiet_NaN();
  const ImagePyramid bad = makePyramid(img, 1);
  EXPECT_THROW(ImmaturePoint(bad.gradients(0), 30.f, 20.f), InputError);
  EXPECT_NO_THROW(ImmaturePoint(pyr.gradients(0), 30.f, 20.f, 0.5f, 0.5f));
}

}  // namespace
}  // namespace ldsm
