// When a frame tracked against the kept window after a loss resumes tracking there
// (TrackingStage::resumesAfterLoss, resumesWhereTheMapFoundIt, plausibleAfterLoss, posesAgree),
// and which of two disagreeing tracks goes on (betterResumption).
#include "pipeline/tracking_stage.h"

#include <gtest/gtest.h>

namespace ldsm {
namespace {

FrameTrackingOutcome tracked(double rmse, double inliers) {
  FrameTrackingOutcome o;
  o.success = true;
  o.rmse = rmse;
  o.inlier_fraction = inliers;
  return o;
}

TEST(TrackingStageResume, WithinTwiceTheResidualBeforeTheLossAndSeventyPercentInliers) {
  EXPECT_TRUE(TrackingStage::resumesAfterLoss(tracked(5.0, 0.7), 2.5));
  EXPECT_FALSE(TrackingStage::resumesAfterLoss(tracked(5.1, 0.89), 2.5));
  EXPECT_FALSE(TrackingStage::resumesAfterLoss(tracked(2.0, 0.69), 2.5));
}

TEST(TrackingStageResume, AFarViewResumesWithinThreeTimesTheResidualAndNinetyPercentInliers) {
  // The rendered corridor 1.5 m on after a gap: 6.0 against 2.6 before, 96 % inliers.
  EXPECT_TRUE(TrackingStage::resumesAfterLoss(tracked(6.0, 0.96), 2.6));
  EXPECT_TRUE(TrackingStage::resumesAfterLoss(tracked(7.5, 0.9), 2.5));
  EXPECT_FALSE(TrackingStage::resumesAfterLoss(tracked(7.6, 0.99), 2.5));
  // A wrong pose: about the residual of the scene's texture, a third of the points outliers.
  EXPECT_FALSE(TrackingStage::resumesAfterLoss(tracked(6.0, 0.71), 2.6));
}

TEST(TrackingStageResume, WithoutAResidualBeforeTheInliersDecide) {
  EXPECT_TRUE(TrackingStage::resumesAfterLoss(tracked(50.0, 0.7), 0.0));
  EXPECT_FALSE(TrackingStage::resumesAfterLoss(tracked(1.0, 0.6), 0.0));
}

TEST(TrackingStageResume, WhereTheMapFoundItSixtyPercentInliersWithinTwiceTheResidual) {
  // Live vamr_desk_loop after 40 frames of noise: the first clean frame tracked against the window
  // from where the map found it, 69 % inliers at 11.3 against 6.97 before (its pose right: the
  // runs that resumed at 70-82 % agree with it); a new window on the map's pose, 3.4 degrees off,
  // drifted to 0.016-0.029 m.
  EXPECT_TRUE(TrackingStage::resumesWhereTheMapFoundIt(tracked(11.33, 0.69), 6.97));
  EXPECT_TRUE(TrackingStage::resumesWhereTheMapFoundIt(tracked(5.0, 0.6), 2.5));
  EXPECT_FALSE(TrackingStage::resumesWhereTheMapFoundIt(tracked(5.0, 0.59), 2.5));
  EXPECT_FALSE(TrackingStage::resumesWhereTheMapFoundIt(tracked(5.1, 0.95), 2.5));
  EXPECT_TRUE(TrackingStage::resumesWhereTheMapFoundIt(tracked(50.0, 0.6), 0.0));
  // Without the map's word the window alone needs its usual fit.
  EXPECT_FALSE(TrackingStage::resumesAfterLoss(tracked(11.33, 0.69), 6.97));
  FrameTrackingOutcome failed = tracked(1.0, 1.0);
  failed.success = false;
  EXPECT_FALSE(TrackingStage::resumesWhereTheMapFoundIt(failed, 2.5));
}

TEST(TrackingStageResume, WhenTheMapConfirmsTheTrackHalfTheInliersWithinThreeTimesTheResidual) {
  // vamr_desk_loop after 40 black frames: 2.1 times the residual before at 62 % inliers; after
  // 80, 55-59 %.
  EXPECT_TRUE(TrackingStage::plausibleAfterLoss(tracked(11.71, 0.62), 5.55));
  EXPECT_TRUE(TrackingStage::plausibleAfterLoss(tracked(12.4, 0.55), 5.55));
  EXPECT_TRUE(TrackingStage::plausibleAfterLoss(tracked(7.5, 0.5), 2.5));
  EXPECT_FALSE(TrackingStage::plausibleAfterLoss(tracked(7.6, 0.9), 2.5));
  EXPECT_FALSE(TrackingStage::plausibleAfterLoss(tracked(5.0, 0.49), 2.5));
  EXPECT_TRUE(TrackingStage::plausibleAfterLoss(tracked(50.0, 0.5), 0.0));
  FrameTrackingOutcome failed = tracked(1.0, 1.0);
  failed.success = false;
  EXPECT_FALSE(TrackingStage::plausibleAfterLoss(failed, 2.5));
}

TEST(TrackingStageResume, TwoPosesAgreeWithinTwoHundredthsOfTheMedianDepthAndOneDegree) {
  const SE3d a(SO3d::exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(1.0, 2.0, 3.0));
  const auto moved = [&](double dx, double deg) {
    return SE3d(SO3d::exp(Eigen::Vector3d(0.0, deg * 3.14159265358979323846 / 180.0, 0.0)),
                Eigen::Vector3d(dx, 0.0, 0.0)) *
           a;
  };
  EXPECT_TRUE(TrackingStage::posesAgree(a, a, 2.0));
  EXPECT_TRUE(TrackingStage::posesAgree(moved(0.039, 0.0), a, 2.0));
  EXPECT_FALSE(TrackingStage::posesAgree(moved(0.041, 0.0), a, 2.0));
  EXPECT_TRUE(TrackingStage::posesAgree(a, moved(0.0, 0.99), 2.0));
  // The map's pose 3.55 degrees from the window's track (a worse minimum of its fit): no agreement.
  EXPECT_FALSE(TrackingStage::posesAgree(moved(0.0, 3.55), a, 2.0));
  EXPECT_FALSE(TrackingStage::posesAgree(moved(0.0, 1.01), a, 2.0));
  // Consecutive frames' tracks (the steady fit after a loss): both bounds twice as wide.
  EXPECT_TRUE(TrackingStage::posesAgree(moved(0.079, 0.0), a, 2.0, 2.0));
  EXPECT_FALSE(TrackingStage::posesAgree(moved(0.081, 0.0), a, 2.0, 2.0));
  EXPECT_TRUE(TrackingStage::posesAgree(moved(0.0, 1.99), a, 2.0, 2.0));
  EXPECT_FALSE(TrackingStage::posesAgree(moved(0.0, 2.01), a, 2.0, 2.0));
}

TEST(TrackingStageResume, AFailedTrackNeverResumes) {
  FrameTrackingOutcome o = tracked(1.0, 1.0);
  o.success = false;
  EXPECT_FALSE(TrackingStage::resumesAfterLoss(o, 2.5));
}

TEST(TrackingStageResume, OfTwoDisagreeingTracksTheOneWithSmallerResidualsPerInlierShareGoesOn) {
  // vamr_desk_loop after 40 black frames, the map's pose put 0.2-0.3 median depths off (as a
  // checkerboard period can): the track from it 13.39 at 50 % inliers, 12.64 at 55 %, 12.95 at
  // 47 %; from the last pose 10.72 at 74 % (right to 1 mm).
  const FrameTrackingOutcome right = tracked(10.72, 0.74);
  for (const FrameTrackingOutcome& wrong :
       {tracked(13.39, 0.50), tracked(12.64, 0.55), tracked(12.95, 0.47)}) {
    EXPECT_TRUE(TrackingStage::betterResumption(right, wrong));
    EXPECT_FALSE(TrackingStage::betterResumption(wrong, right));
  }
  // Fewer inliers are worth smaller residuals only in proportion.
  EXPECT_TRUE(TrackingStage::betterResumption(tracked(6.0, 0.6), tracked(10.0, 0.9)));
  EXPECT_FALSE(TrackingStage::betterResumption(tracked(6.0, 0.5), tracked(10.0, 0.9)));
  // A track that failed is never better, and any track is better than a failed one.
  FrameTrackingOutcome failed = tracked(1.0, 1.0);
  failed.success = false;
  EXPECT_FALSE(TrackingStage::betterResumption(failed, right));
  EXPECT_TRUE(TrackingStage::betterResumption(right, failed));
  EXPECT_FALSE(TrackingStage::betterResumption(right, right));
}

}  // namespace
}  // namespace ldsm
