// The coarse tracker's warp: the SIMD kernel (selected instruction set and plain C++) against the
// per-point reference, bit for bit, on random warps of a smooth texture with points inside, near
// the border, outside, behind the camera and not finite.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "kernels/coarse_warp.h"

namespace ldsm {
namespace simd {
namespace {

template <class V>
class CoarseWarpTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(CoarseWarpTest, VecTypes, );

Image<GradientPixel> texture(int w, int h) {
  Image<GradientPixel> g(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      g(x, y) = {120.f + 60.f * std::sin(0.31f * fx) * std::cos(0.23f * fy),
                 18.f * std::cos(0.31f * fx) * std::cos(0.23f * fy),
                 -13.f * std::sin(0.31f * fx) * std::sin(0.23f * fy)};
    }
  return g;
}

CoarseWarpParams randomWarp(const Image<GradientPixel>& img, std::mt19937& rng) {
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  CoarseWarpParams w;
  const float e[9] = {1.f + 0.05f * U(rng), 0.05f * U(rng),       4.f * U(rng),
                      0.05f * U(rng),       1.f + 0.05f * U(rng), 4.f * U(rng),
                      1e-4f * U(rng),       1e-4f * U(rng),       1.f + 0.01f * U(rng)};
  for (int i = 0; i < 9; ++i) w.KRKi[i] = e[i];
  for (float& t : w.Kt) t = 6.f * U(rng);
  w.Kt[2] = 0.05f * U(rng);
  w.fx = 300.f + 50.f * U(rng);
  w.fy = 300.f + 50.f * U(rng);
  w.fxi = 1.f / w.fx;
  w.fyi = 1.f / w.fy;
  w.cx = 0.5f * img.width();
  w.cy = 0.5f * img.height();
  w.cxi = -w.cx * w.fxi;
  w.cyi = -w.cy * w.fyi;
  w.margin = 2.f;
  w.scale = 1.f + 0.2f * U(rng);
  w.b_ref = 5.f * U(rng);
  w.b = 5.f * U(rng);
  w.image = img.view();
  return w;
}

template <class V, bool kRadial>
void expectFourPointsEqualThePointByPointWarp() {
  const Image<GradientPixel> img = texture(97, 61);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> X(-8.f, 105.f), Y(-8.f, 69.f), D(0.f, 1.f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 200; ++trial) {
    CoarseWarpParams w = randomWarp(img, rng);
    // Up to 8 % distortion at the image's border (|k| <= 3, |n| <= 0.17), and points whose rays
    // lie beyond the radius where the distortion turns back for k < 0 (n = 0.5 and more).
    if (kRadial) w.radial_k = 6.f * (D(rng) - 0.5f);
    std::vector<float> x(64), y(64), idepth(64), intensity(64);
    for (int i = 0; i < 64; ++i) {
      x[i] = std::floor(X(rng));
      y[i] = std::floor(Y(rng));
      idepth[i] = D(rng);
      intensity[i] = 255.f * D(rng);
    }
    idepth[5] = -40.f;  // behind the camera
    x[9] = nan;
    idepth[13] = nan;
    x[17] = 2.f;  // at the margin
    y[17] = 2.f;
    x[21] = 0.5f * 97 + 150.f;  // far right and left of the image (n = +-0.5 and beyond)
    x[25] = -110.f;
    x[29] = 260.f;
    for (int i = 0; i < 64; i += 4) {
      CoarseWarp4 block;
      warpCoarse4<V, kRadial>(w, &x[i], &y[i], &idepth[i], &intensity[i], block);
      for (int l = 0; l < 4; ++l) {
        CoarseWarpedPoint ref;
        const bool in = reference::warpCoarsePoint<kRadial>(w, x[i + l], y[i + l], idepth[i + l],
                                                            intensity[i + l], ref);
        ASSERT_EQ(((block.inside >> l) & 1) != 0, in) << "trial " << trial << " point " << i + l;
        if (!in) {
          ++outside;
          continue;
        }
        ++inside;
        EXPECT_EQ(block.dx_fx[l], ref.dx_fx);
        EXPECT_EQ(block.dy_fy[l], ref.dy_fy);
        EXPECT_EQ(block.nx[l], ref.nx);
        EXPECT_EQ(block.ny[l], ref.ny);
        EXPECT_EQ(block.iz[l], ref.iz);
        EXPECT_EQ(block.ref_term[l], ref.ref_term);
        EXPECT_EQ(block.residual[l], ref.residual);
      }
    }
  }
  EXPECT_GT(inside, 5000);
  EXPECT_GT(outside, 1000);
}

TYPED_TEST(CoarseWarpTest, FourPointsAtOnceEqualThePointByPointWarp) {
  expectFourPointsEqualThePointByPointWarp<TypeParam, false>();
}

TYPED_TEST(CoarseWarpTest, FourPointsAtOnceEqualThePointByPointWarpThroughARadialDistortion) {
  expectFourPointsEqualThePointByPointWarp<TypeParam, true>();
}

TEST(CoarseWarp, ReferenceIsTheBilinearWarpOfThePoint) {
  const Image<GradientPixel> img = texture(97, 61);
  std::mt19937 rng(3);
  const CoarseWarpParams w = randomWarp(img, rng);
  const float x = 40.f, y = 30.f, d = 0.3f, I_ref = 100.f;
  CoarseWarpedPoint out;
  ASSERT_TRUE(reference::warpCoarsePoint(w, x, y, d, I_ref, out));
  // The same in double, from the definitions.
  const float* K = w.KRKi;
  const double px = K[0] * x + K[1] * y + K[2] + w.Kt[0] * d;
  const double py = K[3] * x + K[4] * y + K[5] + w.Kt[1] * d;
  const double pz = K[6] * x + K[7] * y + K[8] + w.Kt[2] * d;
  const double u = px / pz, v = py / pz;
  const GradientPixel g =
      interpolateBilinear(img.view(), static_cast<float>(u), static_cast<float>(v));
  EXPECT_NEAR(out.iz, d / pz, 1e-6);
  EXPECT_NEAR(out.nx, w.fxi * u + w.cxi, 1e-5);
  EXPECT_NEAR(out.ny, w.fyi * v + w.cyi, 1e-5);
  EXPECT_NEAR(out.dx_fx, g.dx * w.fx, 1e-2);
  EXPECT_NEAR(out.dy_fy, g.dy * w.fy, 1e-2);
  const double ref = w.scale * (I_ref - w.b_ref);
  EXPECT_NEAR(out.ref_term, ref, 1e-4);
  EXPECT_NEAR(out.residual, g.intensity - ref - w.b, 1e-3);
  // Behind the camera and outside: no warp.
  EXPECT_FALSE(reference::warpCoarsePoint(w, x, y, -1e3f, I_ref, out));
  EXPECT_FALSE(reference::warpCoarsePoint(w, 500.f, y, d, I_ref, out));
}

// Through a radial distortion: the frame sampled at K D(n) of the pinhole n, the gradient moved
// through D's Jacobian (from the definitions, in double).
TEST(CoarseWarp, RadialReferenceSamplesTheDistortedPixel) {
  const Image<GradientPixel> img = texture(97, 61);
  std::mt19937 rng(5);
  CoarseWarpParams w = randomWarp(img, rng);
  w.radial_k = 0.12f;
  const float x = 40.f, y = 30.f, d = 0.3f, I_ref = 100.f;
  CoarseWarpedPoint out;
  ASSERT_TRUE(reference::warpCoarsePoint<true>(w, x, y, d, I_ref, out));
  const float* K = w.KRKi;
  const double px = K[0] * x + K[1] * y + K[2] + w.Kt[0] * d;
  const double py = K[3] * x + K[4] * y + K[5] + w.Kt[1] * d;
  const double pz = K[6] * x + K[7] * y + K[8] + w.Kt[2] * d;
  const double nx = (px / pz - w.cx) / w.fx, ny = (py / pz - w.cy) / w.fy;
  const double k = w.radial_k, f = 1.0 + k * (nx * nx + ny * ny);
  const double u = w.fx * nx * f + w.cx, v = w.fy * ny * f + w.cy;
  const GradientPixel g =
      interpolateBilinear(img.view(), static_cast<float>(u), static_cast<float>(v));
  EXPECT_NEAR(out.nx, nx, 1e-5);
  EXPECT_NEAR(out.ny, ny, 1e-5);
  EXPECT_NEAR(out.iz, d / pz, 1e-6);
  const double gx = g.dx * w.fx, gy = g.dy * w.fy;
  EXPECT_NEAR(out.dx_fx, gx * (f + 2 * k * nx * nx) + gy * 2 * k * nx * ny, 2e-2);
  EXPECT_NEAR(out.dy_fy, gx * 2 * k * nx * ny + gy * (f + 2 * k * ny * ny), 2e-2);
  EXPECT_NEAR(out.residual, g.intensity - w.scale * (I_ref - w.b_ref) - w.b, 1e-3);
  // Beyond the radius where a distortion with k < 0 turns back (1 + 3 k |n|^2 <= 0) a ray has no
  // image, although D would put it inside: n = 0.5 with k = -3 lands 37 px from the centre.
  CoarseWarpParams fold;
  fold.KRKi[0] = fold.KRKi[4] = fold.KRKi[8] = 1.f;
  fold.fx = fold.fy = 300.f;
  fold.fxi = fold.fyi = 1.f / 300.f;
  fold.cx = 48.f;
  fold.cy = 30.f;
  fold.cxi = -fold.cx * fold.fxi;
  fold.cyi = -fold.cy * fold.fyi;
  fold.image = img.view();
  fold.radial_k = -3.f;
  CoarseWarpedPoint folded;
  EXPECT_FALSE(reference::warpCoarsePoint<true>(fold, 48.f + 150.f, 30.f, d, I_ref, folded));
  fold.radial_k = -1.f;  // 1 + 3 k |n|^2 = 0.25: an image, outside this one
  EXPECT_FALSE(reference::warpCoarsePoint<true>(fold, 48.f + 150.f, 30.f, d, I_ref, folded));
  fold.radial_k = -3.f;  // near the centre the same distortion has an image
  EXPECT_TRUE(reference::warpCoarsePoint<true>(fold, 48.f + 30.f, 30.f, d, I_ref, folded));
  // Without the distortion the same point samples elsewhere.
  CoarseWarpedPoint pinhole;
  ASSERT_TRUE(reference::warpCoarsePoint<false>(w, x, y, d, I_ref, pinhole));
  EXPECT_NE(pinhole.residual, out.residual);
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
