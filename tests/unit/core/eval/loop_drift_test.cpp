#include "ldsm/eval/loop_drift.h"

#include <gtest/gtest.h>

#include "ldsm/error.h"
#include "synthetic_trajectory.h"

namespace ldsm::eval {
namespace {

using testing::makeSim3;

constexpr std::size_t kPoses = 400;
constexpr std::size_t kSegment = 60;

// The ground truth and an estimate whose start segment is placed by g^-1 and whose end segment
// is placed by (d g)^-1: aligning the segments then gives S_s = g and S_e = d g, i.e. the
// accumulated drift S_e S_s^-1 = d. The frames in between blend the two placements.
struct DriftCase {
  Trajectory gt;
  Trajectory est;
  Alignment g;
  Alignment d;
};

DriftCase makeCase(const Alignment& d) {
  DriftCase c;
  c.gt = testing::curvedTrajectory(kPoses);
  c.g = makeSim3(0.9, {0.3, 1.0, -0.2}, {2.0, -1.0, 0.5}, 1.7);
  c.d = d;
  const Alignment start = c.g.inverse();
  const Alignment end = (c.d * c.g).inverse();
  for (std::size_t i = 0; i < kPoses; ++i) {
    const double w =
        std::clamp((static_cast<double>(i) - kSegment) / (kPoses - 2.0 * kSegment), 0.0, 1.0);
    StampedPose sp = c.gt[i];
    sp.pose.translation =
        (1.0 - w) * start.apply(sp.pose.translation) + w * end.apply(sp.pose.translation);
    c.est.push_back(sp);
  }
  return c;
}

TEST(LoopDrift, RecoversInjectedDrift) {
  const Alignment d = makeSim3(0.15, {0.1, 0.2, 1.0}, {0.3, -0.2, 0.1}, 1.08);
  const DriftCase c = makeCase(d);
  LoopDriftOptions o;
  o.segment_poses = kSegment;
  const LoopDriftResult r = computeLoopDrift(c.gt, c.est, o);

  EXPECT_EQ(r.start_poses, kSegment);
  EXPECT_EQ(r.end_poses, kSegment);
  EXPECT_NEAR(r.scale_drift, 1.08, 1e-9);
  EXPECT_NEAR(r.rotation_drift_deg, 0.15 * 180.0 / EIGEN_PI, 1e-7);
  EXPECT_NEAR(r.translation_drift, d.translation.norm(), 1e-9);
  EXPECT_NEAR(r.start_alignment.scale, c.g.scale, 1e-9);

  // e_align from its definition with the known S_s = g and S_e = d g.
  const Alignment s_e = d * c.g;
  double all = 0.0;
  for (const auto& sp : c.est) {
    all += (c.g.apply(sp.pose.translation) - s_e.apply(sp.pose.translation)).squaredNorm();
  }
  double seg = 0.0;
  for (std::size_t i = 0; i < kPoses; ++i) {
    if (i >= kSegment && i < kPoses - kSegment) continue;
    const Eigen::Vector3d& p = c.est[i].pose.translation;
    seg += (c.g.apply(p) - s_e.apply(p)).squaredNorm();
  }
  EXPECT_NEAR(r.alignment_error, std::sqrt(all / kPoses), 1e-9);
  EXPECT_NEAR(r.alignment_error_segments, std::sqrt(seg / (2.0 * kSegment)), 1e-9);
  EXPECT_GT(r.alignment_error, 0.1);
}

TEST(LoopDrift, NoDriftGivesZero) {
  const DriftCase c = makeCase(Alignment::identity());
  const LoopDriftResult r = computeLoopDrift(c.gt, c.est);  // automatic segment size
  EXPECT_EQ(r.start_poses, kPoses / 5);
  EXPECT_LT(r.alignment_error, 1e-9);
  EXPECT_LT(r.translation_drift, 1e-9);
  EXPECT_LT(r.rotation_drift_deg, 1e-7);
  EXPECT_NEAR(r.scale_drift, 1.0, 1e-12);
}

TEST(LoopDrift, ExplicitSegments) {
  const DriftCase c = makeCase(makeSim3(0.0, {0, 0, 1}, {0, 0, 0}, 0.9));
  std::vector<IndexPair> start, end;
  for (std::size_t i = 0; i < 30; ++i) start.push_back({i, i});
  for (std::size_t i = kPoses - 30; i < kPoses; ++i) end.push_back({i, i});
  const LoopDriftResult r = computeLoopDrift(c.gt, c.est, start, end);
  EXPECT_NEAR(r.scale_drift, 0.9, 1e-9);
}

TEST(LoopDrift, TooFewOrDegenerateSegments) {
  const DriftCase c = makeCase(Alignment::identity());
  LoopDriftOptions o;
  o.segment_poses = kPoses;  // two segments cannot both have all poses
  EXPECT_THROW(computeLoopDrift(c.gt, c.est, o), InputError);
  o.segment_poses = 2;
  EXPECT_THROW(computeLoopDrift(c.gt, c.est, o), InputError);

  Trajectory line = c.gt;
  for (std::size_t i = 0; i < 50; ++i) line[i].pose.translation = Eigen::Vector3d(0.1 * i, 0, 0);
  o.segment_poses = 50;
  try {
    computeLoopDrift(line, c.est, o);
    FAIL() << "collinear start segment accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("start segment"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ldsm::eval
