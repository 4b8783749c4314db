// ImagePyramid::build() and the interpolation helpers must not touch the heap once the pyramid
// exists (tracking runs them for every frame).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "alloc_counter.h"
#include "image/image_pyramid.h"
#include "image/interpolation.h"
#include "ldsm/image.h"

namespace ldsm {
namespace {

using test::AllocationScope;

TEST(AllocationCounter, SeesOperatorNewAndImageBuffers) {
  // The counter must be able to fail the tests below: it sees both allocation paths.
  {
    const AllocationScope scope;
    std::vector<int> v(100);
    v[3] = 1;
    EXPECT_GE(scope.count(), 1u);
  }
  {
    const AllocationScope scope;
    ImageF img(64, 48);
    img.fill(0.f);
    EXPECT_EQ(scope.count(), 1u);
  }
  {
    const AllocationScope scope;
    ImagePyramid p(64, 48, 3);
    EXPECT_GE(scope.count(), 3u);
  }
}

TEST(ImagePyramidAllocation, BuildAllocatesNothing) {
  const int w = 320;
  const int h = 240;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.f, 255.f);
  ImageF frame_a(w, h);
  ImageF frame_b(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      frame_a(x, y) = u(rng);
      frame_b(x, y) = u(rng);
    }
  ImagePyramid pyramid(w, h, 5);
  ImagePyramid no_mag(w, h, 4, /*with_grad_mag_sq=*/false);

  const AllocationScope scope;
  float sink = 0.f;
  for (int i = 0; i < 3; ++i) {
    pyramid.build(i % 2 ? frame_a.view() : frame_b.view());
    no_mag.build(frame_a.view());
    for (int l = 0; l < pyramid.levels(); ++l) {
      const float x = 0.37f * static_cast<float>(pyramid.width(l));
      const float y = 0.61f * static_cast<float>(pyramid.height(l));
      if (isInsideForBilinear(pyramid.gradients(l), x, y)) {
        sink += interpolateBilinear(pyramid.gradients(l), x, y).dx;
        sink += interpolateIntensity(pyramid.gradients(l), x, y);
      }
    }
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_TRUE(sink == sink);  // keep the work observable
}

}  // namespace
}  // namespace ldsm
