// The pattern kernels (sampling and accumulation), for the selected instruction set and the
// plain-C++ vector, against the scalar reference on random inputs. Tolerance: relative 1e-5 of
// the magnitude of each quantity (for sums of products, the Cauchy-Schwarz bound
// sqrt(H_ii H_jj) of the terms' absolute sum).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "kernels/pattern_accumulate.h"
#include "kernels/pattern_sampling.h"
#include "ldsm/image.h"

namespace ldsm {
namespace simd {
namespace {

constexpr double kTol = 1e-5;

template <class V>
class PatternKernelTest : public ::testing::Test {};
using VecTypes = ::testing::Types<Vec4, Vec4Scalar>;
TYPED_TEST_SUITE(PatternKernelTest, VecTypes, );

/// A smooth random texture with central-difference gradients, as a pyramid level holds it.
Image<GradientPixel> randomTexture(int w, int h, std::mt19937& rng) {
  std::uniform_real_distribution<float> U(0.f, 6.2832f);
  const float p1 = U(rng), p2 = U(rng), p3 = U(rng);
  Image<float> I(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      I(x, y) = 120.f + 60.f * std::sin(0.31f * fx + p1) * std::cos(0.23f * fy + p2) +
                40.f * std::sin(0.11f * fx - 0.37f * fy + p3);
    }
  Image<GradientPixel> g(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool in = x > 0 && y > 0 && x + 1 < w && y + 1 < h;
      g(x, y) = {I(x, y), in ? 0.5f * (I(x + 1, y) - I(x - 1, y)) : 0.f,
                 in ? 0.5f * (I(x, y + 1) - I(x, y - 1)) : 0.f};
    }
  return g;
}

struct RandomPair {
  PatternSamplingParams params;
  PatternWeighting weighting;
};

RandomPair randomPair(const Image<GradientPixel>& img, std::mt19937& rng) {
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  RandomPair rp;
  // K R K^-1 of a small rotation (a near-identity homography) and a translation.
  const float e[9] = {1.f + 0.02f * U(rng), 0.03f * U(rng),       1e-4f * U(rng),
                      0.03f * U(rng),       1.f + 0.02f * U(rng), 1e-4f * U(rng),
                      3.f * U(rng),         3.f * U(rng),         1.f + 0.01f * U(rng)};
  for (int i = 0; i < 9; ++i) rp.params.KRKi[i] = e[i];
  rp.params.Kt[0] = 5.f * U(rng);
  rp.params.Kt[1] = 5.f * U(rng);
  rp.params.Kt[2] = 0.02f * U(rng);
  rp.params.scale = 1.f + 0.2f * U(rng);
  rp.params.offset = 10.f * U(rng);
  rp.params.image = img.view();
  rp.weighting.gradient_c2 = 50.f * 50.f;
  rp.weighting.huber = 9.f;
  rp.weighting.margin = 2.f;
  return rp;
}

struct RandomPoint {
  float colors[kPatternSize];
  float grad_weights[kPatternSize];
  PatternPoint point;
};

RandomPoint randomPoint(int w, int h, std::mt19937& rng) {
  std::uniform_real_distribution<float> U(0.f, 1.f);
  RandomPoint p;
  p.point.u = -4.f + (static_cast<float>(w) + 8.f) * U(rng);  // some leave the image
  p.point.v = -4.f + (static_cast<float>(h) + 8.f) * U(rng);
  p.point.idepth = 0.05f + 2.f * U(rng);
  if (U(rng) < 0.5f) {  // half of them with a radial-correction shift of the projection
    p.point.shift_x = -3.f + 6.f * U(rng);
    p.point.shift_y = -3.f + 6.f * U(rng);
  }
  for (int k = 0; k < kPatternSize; ++k) {
    p.colors[k] = 40.f + 180.f * U(rng);
    p.grad_weights[k] = 0.3f + 0.7f * U(rng);
  }
  p.point.colors = p.colors;
  p.point.grad_weights = p.grad_weights;
  return p;
}

TYPED_TEST(PatternKernelTest, SamplingMatchesReference) {
  std::mt19937 rng(7);
  const Image<GradientPixel> img = randomTexture(97, 61, rng);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const RandomPair rp = randomPair(img, rng);
    const RandomPoint pt = randomPoint(img.width(), img.height(), rng);
    PatternSamples ref, got;
    const bool ok_ref = reference::samplePattern(rp.params, rp.weighting, pt.point, ref);
    const bool ok = samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, got);
    ASSERT_EQ(ok, ok_ref) << "trial " << trial;
    if (!ok) {
      ++outside;
      continue;
    }
    ++inside;
    const double grey = 255.0, grad = 128.0;  // magnitudes of intensities and gradients
    for (int k = 0; k < kPatternSize; ++k) {
      ASSERT_NEAR(got.gx[k], ref.gx[k], kTol * grad) << trial << " " << k;
      ASSERT_NEAR(got.gy[k], ref.gy[k], kTol * grad) << trial << " " << k;
      ASSERT_NEAR(got.r[k], ref.r[k], kTol * grey) << trial << " " << k;
      ASSERT_NEAR(got.w[k], ref.w[k], kTol) << trial << " " << k;
    }
    ASSERT_NEAR(got.energy, ref.energy, kTol * std::max(1.0, static_cast<double>(ref.energy)));
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 100);
}

// A compacted target (16-bit plane): the kernel agrees with the reference on it and with itself on
// the float plane of the decoded values (to rounding), and stays within the rounding step's reach
// of the float plane it was made from.
/// Every value of `a` and `b` the same bits (the struct's padding aside).
bool sameBits(const PatternSamples& a, const PatternSamples& b) {
  return std::memcmp(a.gx, b.gx, sizeof a.gx) == 0 && std::memcmp(a.gy, b.gy, sizeof a.gy) == 0 &&
         std::memcmp(a.r, b.r, sizeof a.r) == 0 && std::memcmp(a.w, b.w, sizeof a.w) == 0 &&
         std::memcmp(&a.energy, &b.energy, sizeof a.energy) == 0;
}

// A compacted keyframe with 16-bit images keeps its level-0 intensities in steps of 1/128 grey
// level; the kernel makes the gradients of the decoded values: the same bits as the packed plane
// of the decoded values (intensity and central differences), and within half a step of the
// float texture's samples.
TYPED_TEST(PatternKernelTest, SamplingACompactPlaneMatchesReferenceAndTheDecodedFloatPlane) {
  std::mt19937 rng(11);
  const Image<GradientPixel> img = randomTexture(97, 61, rng);
  Image<float> intensities(img.width(), img.height());
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) intensities(x, y) = img(x, y).intensity;
  CompactPlane compact;
  ASSERT_TRUE(compact.encode(intensities.view()));
  const CompactPlaneView cv = compact.view();
  EXPECT_EQ(cv.step, 1.f / 128.f);  // values within [-255, 255]
  Image<GradientPixel> decoded(img.width(), img.height());
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) decoded(x, y) = cv.at(x, y);
  int inside = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    RandomPair rp = randomPair(img, rng);
    const RandomPoint pt = randomPoint(img.width(), img.height(), rng);
    PatternSamples from_float, on_decoded, ref, got;
    const bool ok_float = samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, from_float);
    rp.params.image = decoded.view();
    const bool ok_decoded = samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, on_decoded);
    rp.params.image = ImageView<const GradientPixel>();
    rp.params.compact = cv;
    const bool ok_ref = reference::samplePattern(rp.params, rp.weighting, pt.point, ref);
    const bool ok = samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, got);
    ASSERT_EQ(ok, ok_ref) << "trial " << trial;
    ASSERT_EQ(ok, ok_decoded) << "trial " << trial;
    ASSERT_EQ(ok, ok_float) << "trial " << trial;
    if (!ok) continue;
    ++inside;
    ASSERT_TRUE(sameBits(got, on_decoded)) << "trial " << trial;
    for (int k = 0; k < kPatternSize; ++k) {
      ASSERT_NEAR(got.gx[k], ref.gx[k], kTol * 128.0) << trial << " " << k;
      ASSERT_NEAR(got.r[k], ref.r[k], kTol * 255.0) << trial << " " << k;
      ASSERT_NEAR(got.w[k], ref.w[k], kTol) << trial << " " << k;
      // Every decoded intensity is within half a step of the float one, so is every central
      // difference (half the difference of two such), and interpolation keeps that.
      ASSERT_NEAR(got.gx[k], from_float.gx[k], 0.5 * cv.step + kTol * 128.0) << trial;
      ASSERT_NEAR(got.gy[k], from_float.gy[k], 0.5 * cv.step + kTol * 128.0) << trial;
      ASSERT_NEAR(got.r[k], from_float.r[k], 0.5 * cv.step + kTol * 255.0) << trial;
    }
  }
  EXPECT_GT(inside, 1000);
}

// A compacted keyframe keeps only its level-0 intensities (image/intensity_plane.h); sampling
// them makes the gradients again and must give the packed plane's results bit for bit, at the
// residuals' margin (2) and the least one the intensity plane allows (1).
TYPED_TEST(PatternKernelTest, SamplingAnIntensityPlaneGivesThePackedPlanesBits) {
  std::mt19937 rng(17);
  const Image<GradientPixel> img = randomTexture(97, 61, rng);
  Image<float> intensities(img.width(), img.height());
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) intensities(x, y) = img(x, y).intensity;
  const IntensityPlaneView iv{intensities.view()};
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const GradientPixel a = iv.at(x, y), b = img(x, y);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << x << " " << y;
    }
  int inside = 0;
  for (const float margin : {2.f, 1.f}) {
    for (int trial = 0; trial < 3000; ++trial) {
      RandomPair rp = randomPair(img, rng);
      rp.weighting.margin = margin;
      const RandomPoint pt = randomPoint(img.width(), img.height(), rng);
      PatternSamples packed, ref_packed, got, ref;
      const bool ok_packed = samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, packed);
      const bool ok_ref_packed =
          reference::samplePattern(rp.params, rp.weighting, pt.point, ref_packed);
      rp.params.image = ImageView<const GradientPixel>();
      rp.params.intensity = iv;
      const bool ok = samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, got);
      const bool ok_ref = reference::samplePattern(rp.params, rp.weighting, pt.point, ref);
      ASSERT_EQ(ok, ok_packed) << "trial " << trial;
      ASSERT_EQ(ok_ref, ok_ref_packed) << "trial " << trial;
      if (!ok) continue;
      ++inside;
      ASSERT_TRUE(sameBits(got, packed)) << "trial " << trial;
      ASSERT_TRUE(sameBits(ref, ref_packed)) << "trial " << trial;
    }
  }
  EXPECT_GT(inside, 2000);
}

TYPED_TEST(PatternKernelTest, SamplingRejectsBehindCameraAndNonFinite) {
  std::mt19937 rng(3);
  const Image<GradientPixel> img = randomTexture(64, 48, rng);
  RandomPair rp = randomPair(img, rng);
  RandomPoint pt = randomPoint(64, 48, rng);
  pt.point.u = 32.f;
  pt.point.v = 24.f;
  PatternSamples s;
  ASSERT_TRUE(samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, s));
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    RandomPoint q = pt;
    q.point.u = bad;
    q.point.colors = q.colors;
    q.point.grad_weights = q.grad_weights;
    EXPECT_FALSE(samplePattern<TypeParam>(rp.params, rp.weighting, q.point, s));
  }
  // Mirror the image plane: every pixel lands behind the camera, at a valid-looking position.
  for (float& e : rp.params.KRKi) e = -e;
  for (float& e : rp.params.Kt) e = -e;
  EXPECT_FALSE(samplePattern<TypeParam>(rp.params, rp.weighting, pt.point, s));
  EXPECT_FALSE(reference::samplePattern(rp.params, rp.weighting, pt.point, s));
}

PatternSamples randomSamples(std::mt19937& rng) {
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  PatternSamples s;
  for (int k = 0; k < kPatternSize; ++k) {
    s.gx[k] = 60.f * U(rng);
    s.gy[k] = 60.f * U(rng);
    s.r[k] = 20.f * U(rng);
    s.w[k] = 0.5f + 0.5f * U(rng);
  }
  return s;
}

PatternJacobian randomJacobian(const float* colors, std::mt19937& rng) {
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  PatternJacobian j;
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 6; ++c) j.dpx_deps[r][c] = 400.f * U(rng);
    j.dpx_didepth[r] = 80.f * U(rng);
  }
  j.colors = colors;
  j.scale = 1.f + 0.3f * U(rng);
  j.host_b = 15.f * U(rng);
  return j;
}

/// Tolerance of the sums in `pair` (totals layout) from their diagonal.
double pairTolerance(const double* pair, int index) {
  for (int i = 0; i < kPatternBasis; ++i)
    for (int j = i; j < kPatternBasis; ++j)
      if (patternUpperIndex(i, j) == index)
        return kTol * std::sqrt(pair[patternUpperIndex(i, i)] * pair[patternUpperIndex(j, j)]);
  return -1.0;
}

TYPED_TEST(PatternKernelTest, AccumulationMatchesReference) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> U(0.f, 255.f);
  for (int n : {1, 15, 16, 17, 40, 200}) {  // around and across the float flush interval
    PatternPairSumsT<TypeParam> sums;
    double ref_pair[kPatternPairSums] = {};
    double sum_wr2 = 0.0;
    for (int i = 0; i < n; ++i) {
      float colors[kPatternSize];
      for (float& c : colors) c = U(rng);
      const PatternSamples s = randomSamples(rng);
      const PatternJacobian jac = randomJacobian(colors, rng);
      double ref_point[kPatternBasis + 2];
      reference::accumulatePattern(s, jac, ref_pair, ref_point);
      PatternPointSums got;
      sums.add(s, jac, got);
      double wr2 = 0.0;
      for (int k = 0; k < kPatternSize; ++k) wr2 += s.w[k] * s.r[k] * s.r[k];
      sum_wr2 += wr2;
      // Point terms: sum w u_i J_d <= sqrt(sum w u_i^2 * H_dd).
      double single[kPatternPairSums] = {};
      double unused[kPatternBasis + 2];
      reference::accumulatePattern(s, jac, single, unused);
      const double hdd = ref_point[kPatternBasis];
      for (int c = 0; c < kPatternBasis; ++c)
        ASSERT_NEAR(got.coupling[c], ref_point[c],
                    kTol * std::sqrt(single[patternUpperIndex(c, c)] * hdd))
            << n << " " << c;
      ASSERT_NEAR(got.H_dd, hdd, kTol * hdd);
      ASSERT_NEAR(got.b_d, ref_point[kPatternBasis + 1], kTol * std::sqrt(hdd * wr2));
    }
    EXPECT_EQ(sums.count(), n);
    double got[kPatternPairSums];
    sums.totals(got);
    for (int k = 0; k < kPatternUpper; ++k)
      ASSERT_NEAR(got[k], ref_pair[k], pairTolerance(ref_pair, k)) << n << " " << k;
    for (int i = 0; i < kPatternBasis; ++i) {
      const int k = patternGradientIndex(i);
      ASSERT_NEAR(got[k], ref_pair[k],
                  kTol * std::sqrt(ref_pair[patternUpperIndex(i, i)] * sum_wr2))
          << n << " " << i;
    }
    sums.reset();
    sums.totals(got);
    for (double g : got) EXPECT_EQ(g, 0.0);
    EXPECT_EQ(sums.count(), 0);
  }
}

TYPED_TEST(PatternKernelTest, DepthOnlyMatchesReference) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> U(0.f, 255.f);
  for (int i = 0; i < 200; ++i) {
    float colors[kPatternSize];
    for (float& c : colors) c = U(rng);
    const PatternSamples s = randomSamples(rng);
    const PatternJacobian jac = randomJacobian(colors, rng);
    double pair[kPatternPairSums] = {}, point[kPatternBasis + 2];
    reference::accumulatePattern(s, jac, pair, point);
    float H_dd, b_d;
    accumulateDepthOnly<TypeParam>(s, jac.dpx_didepth, &H_dd, &b_d);
    double wr2 = 0.0;
    for (int k = 0; k < kPatternSize; ++k) wr2 += s.w[k] * s.r[k] * s.r[k];
    ASSERT_NEAR(H_dd, point[kPatternBasis], kTol * point[kPatternBasis]);
    ASSERT_NEAR(b_d, point[kPatternBasis + 1], kTol * std::sqrt(point[kPatternBasis] * wr2));
  }
}

}  // namespace
}  // namespace simd
}  // namespace ldsm
