// The initializer runs for every frame until the map exists: after the reference frame, addFrame()
// must not touch the heap, up to and including the frame that completes the initialisation.
#include <gtest/gtest.h>

#include <cmath>

#include "alloc_counter.h"
#include "frontend/coarse_initializer.h"

namespace ldsm {
namespace {

using test::AllocationScope;

constexpr int kW = 320;
constexpr int kH = 240;

// A wall at depth 4 and a floor 1.2 m below the camera, seen from x = shift (metres), f = 250,
// with a smooth analytic texture.
ImageF sceneView(double shift) {
  ImageF image(kW, kH);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const double rx = (x - 159.5) / 250.0, ry = (y - 119.5) / 250.0;
      const double depth = ry > 1.2 / 4.0 ? 1.2 / ry : 4.0;  // floor below the horizon line
      const double X = rx * depth + shift;
      const double Y = ry > 1.2 / 4.0 ? depth : ry * depth;  // floor: texture along the depth
      image(x, y) = static_cast<float>(128 + 50 * std::sin(3.1 * X + 1.0) * std::cos(2.3 * Y) +
                                       30 * std::sin(7.7 * X - 5.3 * Y));
    }
  }
  return image;
}

TEST(CoarseInitializerAllocation, FramesAfterTheReferenceAllocateNothing) {
  PinholeIntrinsics k;
  k.fx = k.fy = 250;
  k.cx = 159.5;
  k.cy = 119.5;
  k.width = kW;
  k.height = kH;
  CoarseInitializer init(PyramidCamera(k, 5));
  ImagePyramid pyramid(kW, kH, 5);
  const ImageF first = sceneView(0.0);
  pyramid.build(first.view());
  ASSERT_FALSE(init.addFrame(pyramid, 1.0));  // the reference: allocations allowed
  ASSERT_EQ(init.status(), InitStatus::kWaitingForParallax);

  bool complete = false;
  for (int i = 1; i <= 40 && !complete; ++i) {
    const ImageF image = sceneView(0.015 * i);
    pyramid.build(image.view());
    const AllocationScope scope;
    complete = init.addFrame(pyramid, 1.0);
    EXPECT_EQ(scope.count(), 0u) << "frame " << i << " (" << toString(init.status()) << ")";
    ASSERT_FALSE(init.failed()) << toString(init.failure());
  }
  EXPECT_TRUE(complete) << "the sequence should initialise, so that completion is covered too";
}

}  // namespace
}  // namespace ldsm
