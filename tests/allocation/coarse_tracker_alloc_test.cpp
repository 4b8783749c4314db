// Coarse tracking runs for every frame: once the tracker exists, setReference(), track() and
// trackWithHypotheses() must not touch the heap.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "alloc_counter.h"
#include "frontend/coarse_tracker.h"
#include "frontend/motion_hypotheses.h"

namespace ldsm {
namespace {

using test::AllocationScope;

constexpr int kW = 320;
constexpr int kH = 240;
constexpr int kLevels = 5;

// A fronto-parallel textured plane at depth 4 seen from x = shift (metres), fx = 250.
ImageF planeView(double shift) {
  ImageF image(kW, kH);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const double X = (x - 159.5) / 250.0 * 4.0 + shift;
      const double Y = (y - 119.5) / 250.0 * 4.0;
      image(x, y) = static_cast<float>(128 + 50 * std::sin(3.1 * X + 1.0) * std::cos(2.3 * Y) +
                                       30 * std::sin(7.7 * X - 5.3 * Y));
    }
  }
  return image;
}

// With a radial distortion the reference also keeps its undistorted rays (grown like the point
// lists).
void expectTrackingAllocatesNothing(float radial_k) {
  PinholeIntrinsics k;
  k.fx = k.fy = 250;
  k.cx = 159.5;
  k.cy = 119.5;
  k.width = kW;
  k.height = kH;
  const PyramidCamera camera(k, kLevels);
  const ImageF ref_image = planeView(0.0);
  const ImageF frame_image = planeView(0.03);
  ImagePyramid ref(kW, kH, kLevels);
  ImagePyramid frame(kW, kH, kLevels);
  ref.build(ref_image.view());
  frame.build(frame_image.view());
  std::vector<DepthPoint> points;
  for (int y = 4; y < kH - 4; y += 3) {
    for (int x = 4; x < kW - 4; x += 3) {
      points.push_back({static_cast<float>(x), static_cast<float>(y), 0.25f, 1.f});
    }
  }
  CoarseTracker tracker(kW, kH, kLevels, CoarseTrackerSettings());
  MotionHistory history;
  history.last_rmse = 0.0;  // unreachable: every hypothesis is tried
  HypothesisSettings settings;
  settings.rotation_angle_count = 1;

  // The first reference sizes the point lists and residual buffers (they grow to the largest
  // reference seen); after that, neither a new reference of that size nor tracking allocates.
  tracker.setReference(ref, camera, points, 1.0, AffineLight(), nullptr, radial_k);
  const AllocationScope scope;
  tracker.setReference(ref, camera, points, 1.0, AffineLight(), nullptr, radial_k);
  SE3d T;
  AffineLight affine;
  CoarseTrackingResult result;
  const bool ok = tracker.track(frame, 1.0, T, affine, kLevels - 1, noAbortThresholds(), result);
  const HypothesisTrackingResult hypotheses =
      trackWithHypotheses(tracker, frame, 1.0, history, settings);
  const std::size_t allocations = scope.count();

  EXPECT_TRUE(ok) << toString(result.failure);
  // The camera moved right: points move left (the images have no distortion).
  if (radial_k == 0.f) {
    EXPECT_NEAR(T.translation().x(), -0.03, 1e-3);
  }
  EXPECT_TRUE(hypotheses.success);
  // 1..4 equal hypothesis 0; the rotated ones are screened, the best few tracked in full.
  EXPECT_EQ(hypotheses.screened, motionHypothesisCount(settings) - 5);
  EXPECT_GE(hypotheses.tried, 1);
  EXPECT_LE(hypotheses.tried, 1 + settings.screened_rotations);
  EXPECT_EQ(allocations, 0u);
}

TEST(CoarseTrackerAllocation, TrackingAllocatesNothing) {
  expectTrackingAllocatesNothing(0.f);
}

TEST(CoarseTrackerAllocation, TrackingThroughARadialDistortionAllocatesNothing) {
  expectTrackingAllocatesNothing(0.01f);
}

}  // namespace
}  // namespace ldsm
