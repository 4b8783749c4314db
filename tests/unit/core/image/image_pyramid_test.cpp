#include "image/image_pyramid.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <utility>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "image/pyramid_pool.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

// A w x h image stored with extra padding per row (stride > width) to exercise strided input.
struct PaddedImage {
  std::vector<float> data;
  ImageView<const float> view;
  PaddedImage(int w, int h, int pad, float (*f)(int, int)) : data((w + pad) * h, -999.f) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) data[y * (w + pad) + x] = f(x, y);
    view = ImageView<const float>(data.data(), w, h, w + pad);
  }
};

/// A level's intensity at (x, y): the packed plane's first channel.
float intensityAt(const ImagePyramid& p, int level, int x, int y) {
  return p.gradients(level)(x, y).intensity;
}

float quadratic(int x, int y) {
  return static_cast<float>(x * x + 3 * y);
}

TEST(ImagePyramid, LevelSizesHalveWithFloor) {
  const ImagePyramid p(640, 480, 5);
  ASSERT_EQ(p.levels(), 5);
  const int widths[] = {640, 320, 160, 80, 40};
  const int heights[] = {480, 240, 120, 60, 30};
  for (int l = 0; l < 5; ++l) {
    EXPECT_EQ(p.width(l), widths[l]);
    EXPECT_EQ(p.height(l), heights[l]);
    EXPECT_EQ(p.gradients(l).width, widths[l]);
    EXPECT_EQ(p.gradients(l).height, heights[l]);
    EXPECT_EQ(p.gradMagSq(l).width, widths[l]);
  }
  const ImagePyramid odd(7, 5, 3);
  EXPECT_EQ(odd.width(1), 3);
  EXPECT_EQ(odd.height(1), 2);
  EXPECT_EQ(odd.width(2), 1);
  EXPECT_EQ(odd.height(2), 1);
}

TEST(ImagePyramid, MaxLevels) {
  EXPECT_EQ(ImagePyramid::maxLevels(8, 8), 4);  // 8, 4, 2, 1
  EXPECT_EQ(ImagePyramid::maxLevels(640, 480), 9);
  EXPECT_EQ(ImagePyramid::maxLevels(1, 100), 1);
  EXPECT_EQ(ImagePyramid::maxLevels(0, 100), 0);
  EXPECT_EQ(ImagePyramid::maxLevels(1 << 20, 1 << 20), ImagePyramid::kMaxLevels);
}

TEST(ImagePyramid, Level0CopiesTheStridedInput) {
  const PaddedImage img(6, 4, 3, quadratic);
  ImagePyramid p(6, 4, 2);
  p.build(img.view);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      EXPECT_EQ(intensityAt(p, 0, x, y), quadratic(x, y));
      EXPECT_EQ(p.gradients(0)(x, y).intensity, quadratic(x, y));
    }
}

TEST(ImagePyramid, CoarserLevelsAverage2x2BlocksAndDropOddEdges) {
  // 5 x 3 image with values 10 y + x; level 1 is 2 x 1, level 2 would be 1 x 0 (not allowed).
  const PaddedImage img(5, 3, 1, [](int x, int y) { return static_cast<float>(10 * y + x); });
  ImagePyramid p(5, 3, 2);
  p.build(img.view);
  ASSERT_EQ(p.width(1), 2);
  ASSERT_EQ(p.height(1), 1);
  // (0 + 1 + 10 + 11) / 4 and (2 + 3 + 12 + 13) / 4; column 4 and row 2 are dropped.
  EXPECT_FLOAT_EQ(intensityAt(p, 1, 0, 0), 5.5f);
  EXPECT_FLOAT_EQ(intensityAt(p, 1, 1, 0), 7.5f);
}

TEST(ImagePyramid, ThreeLevelsOfRandomImageMatchDirectBlockMeans) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 255.f);
  const int w = 37;
  const int h = 22;
  std::vector<float> data(w * h);
  for (float& v : data) v = u(rng);
  ImagePyramid p(w, h, 3);
  p.build(ImageView<const float>(data.data(), w, h));
  // Level 2 pixel = mean of the 4x4 block at (4x, 4y) of the input.
  for (int y = 0; y < p.height(2); ++y) {
    for (int x = 0; x < p.width(2); ++x) {
      double sum = 0;
      for (int dy = 0; dy < 4; ++dy)
        for (int dx = 0; dx < 4; ++dx) sum += data[(4 * y + dy) * w + 4 * x + dx];
      EXPECT_NEAR(intensityAt(p, 2, x, y), sum / 16, 1e-4);
    }
  }
}

TEST(ImagePyramid, CentralDifferenceGradientsZeroOnTheBorder) {
  // I = x^2 + 3y: dx = ((x+1)^2 - (x-1)^2) / 2 = 2x, dy = 3 inside.
  const PaddedImage img(6, 5, 2, quadratic);
  ImagePyramid p(6, 5, 1);
  p.build(img.view);
  const ImageView<const GradientPixel> g = p.gradients(0);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 6; ++x) {
      const bool border = x == 0 || y == 0 || x == 5 || y == 4;
      const float dx = border ? 0.f : 2.f * x;
      const float dy = border ? 0.f : 3.f;
      EXPECT_EQ(g(x, y).dx, dx) << x << "," << y;
      EXPECT_EQ(g(x, y).dy, dy) << x << "," << y;
      EXPECT_EQ(p.gradMagSq(0)(x, y), dx * dx + dy * dy);
    }
  }
}

TEST(ImagePyramid, GradientsOnCoarserLevelsUseThatLevel) {
  // A linear ramp I = 2x + y stays linear under 2x2 averaging with doubled slopes per level.
  const PaddedImage img(16, 16, 0, [](int x, int y) { return static_cast<float>(2 * x + y); });
  ImagePyramid p(16, 16, 3);
  p.build(img.view);
  for (int l = 0; l < 3; ++l) {
    const float s = static_cast<float>(1 << l);
    EXPECT_FLOAT_EQ(p.gradients(l)(2, 2).dx, 2.f * s);
    EXPECT_FLOAT_EQ(p.gradients(l)(2, 2).dy, 1.f * s);
  }
}

TEST(ImagePyramid, EveryLevelEqualsItsDefinitionBitForBit) {
  // Reference: each level's intensities as a plane (2x2 means of the plane before, in the
  // pyramid's order of operations), then central differences, zero on the border; odd sizes.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.f, 255.f);
  const int w = 45;
  const int h = 29;
  std::vector<float> data(w * h);
  for (float& v : data) v = u(rng);
  ImagePyramid p(w, h, 4);
  p.build(ImageView<const float>(data.data(), w, h));
  ImageF plane(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) plane(x, y) = data[y * w + x];
  for (int l = 0; l < 4; ++l) {
    if (l > 0) {
      ImageF next(plane.width() / 2, plane.height() / 2);
      for (int y = 0; y < next.height(); ++y)
        for (int x = 0; x < next.width(); ++x)
          next(x, y) = 0.25f * ((plane(2 * x, 2 * y) + plane(2 * x + 1, 2 * y)) +
                                (plane(2 * x, 2 * y + 1) + plane(2 * x + 1, 2 * y + 1)));
      plane = next;
    }
    ASSERT_EQ(p.width(l), plane.width());
    ASSERT_EQ(p.height(l), plane.height());
    ImageF copied;
    p.copyIntensity(l, copied);
    for (int y = 0; y < plane.height(); ++y)
      for (int x = 0; x < plane.width(); ++x) {
        const bool border = x == 0 || y == 0 || x == plane.width() - 1 || y == plane.height() - 1;
        const GradientPixel g = p.gradients(l)(x, y);
        ASSERT_EQ(g.intensity, plane(x, y)) << l << ": " << x << ", " << y;
        ASSERT_EQ(copied(x, y), plane(x, y));
        ASSERT_EQ(g.dx, border ? 0.f : 0.5f * (plane(x + 1, y) - plane(x - 1, y)));
        ASSERT_EQ(g.dy, border ? 0.f : 0.5f * (plane(x, y + 1) - plane(x, y - 1)));
        ASSERT_EQ(p.gradMagSq(l)(x, y), g.dx * g.dx + g.dy * g.dy);
      }
  }
}

TEST(ImagePyramid, WithoutGradientMagnitude) {
  const PaddedImage img(8, 8, 0, quadratic);
  ImagePyramid p(8, 8, 2, /*with_grad_mag_sq=*/false);
  p.build(img.view);
  EXPECT_FALSE(p.hasGradMagSq());
  EXPECT_TRUE(p.gradMagSq(0).empty());
  EXPECT_EQ(p.gradients(0)(3, 3).dx, 6.f);
}

TEST(ImagePyramid, OnePixelLevelHasZeroGradient) {
  const PaddedImage img(3, 3, 0, quadratic);
  ImagePyramid p(3, 3, 2);
  p.build(img.view);
  EXPECT_EQ(p.gradients(0)(1, 1).dx, 2.f);
  ASSERT_EQ(p.width(1), 1);
  ASSERT_EQ(p.height(1), 1);
  EXPECT_FLOAT_EQ(intensityAt(p, 1, 0, 0), (0.f + 1.f + 3.f + 4.f) / 4);
  EXPECT_EQ(p.gradients(1)(0, 0).dx, 0.f);
  EXPECT_EQ(p.gradients(1)(0, 0).dy, 0.f);
  EXPECT_THROW(ImagePyramid(2, 1, 2), ConfigError);  // level 1 would be 1 x 0
}

TEST(ImagePyramid, RejectsBadConstructionArguments) {
  EXPECT_THROW(ImagePyramid(0, 10, 1), InputError);
  EXPECT_THROW(ImagePyramid(10, -1, 1), InputError);
  EXPECT_THROW(ImagePyramid(8, 8, 0), ConfigError);
  EXPECT_THROW(ImagePyramid(8, 8, 5), ConfigError);  // 8, 4, 2, 1, 0
  EXPECT_NO_THROW(ImagePyramid(8, 8, 4));
  try {
    ImagePyramid(8, 8, 5);
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[1, 4]"), std::string::npos) << e.what();
  }
}

TEST(ImagePyramid, RejectsWrongInputImages) {
  ImagePyramid p(8, 6, 2);
  std::vector<float> data(64, 1.f);
  EXPECT_THROW(p.build(ImageView<const float>(data.data(), 8, 8)), InputError);
  EXPECT_THROW(p.build(ImageView<const float>(data.data(), 6, 8)), InputError);
  EXPECT_THROW(p.build(ImageView<const float>()), InputError);
  EXPECT_THROW(p.build(ImageView<const float>(nullptr, 8, 6)), InputError);
  EXPECT_THROW(p.build(ImageView<const float>(data.data(), 8, 6, 4)), InputError);  // stride < w
  EXPECT_NO_THROW(p.build(ImageView<const float>(data.data(), 8, 6)));
  try {
    p.build(ImageView<const float>(data.data(), 8, 8));
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("8x8"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("8x6"), std::string::npos) << e.what();
  }
}

TEST(ImagePyramid, MarksClippedPixelsAndBuildClearsThem) {
  ImagePyramid pyr(8, 6, 2);
  ImageF img(8, 6, 100.f);
  pyr.build(img.view());
  ImageF raw(8, 6, 100.f);
  raw(3, 2) = 250.f;
  raw(7, 5) = 255.f;
  raw(0, 0) = 249.9f;
  pyr.markClipped(raw.view(), 250.f);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool clipped = (x == 3 && y == 2) || (x == 7 && y == 5);
      EXPECT_EQ(pyr.clipped()(x, y), clipped ? 1 : 0) << x << ", " << y;
    }
  pyr.build(img.view());  // the next frame starts without clipping
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(pyr.clipped()(x, y), 0);
  EXPECT_THROW(pyr.markClipped(ImageF(7, 6, 0.f).view(), 250.f), InputError);
}

/// A 40 x 30 image of uniformly random grey levels.
ImageF randomGreyImage(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> grey(0.f, 255.f);
  ImageF img(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) img(x, y) = grey(rng);
  return img;
}

// An image's rows through a ring of three, as the frame preprocessor hands them over; a row asked
// for out of order fails the test, and an expired row is overwritten with garbage first.
class RingRows final : public ImageRows {
 public:
  explicit RingRows(const ImageF& image)
      : image_(image), ring_(3 * static_cast<std::size_t>(image.width())) {}
  const float* row(int y) override {
    EXPECT_EQ(y, next_);
    next_ = y + 1;
    float* out = ring_.data() + static_cast<std::size_t>(y % 3) * image_.width();
    std::fill(out, out + image_.width(), std::numeric_limits<float>::quiet_NaN());
    std::copy(image_.row(y), image_.row(y) + image_.width(), out);
    return out;
  }
  int next_ = 0;

 private:
  const ImageF& image_;
  std::vector<float> ring_;
};

TEST(ImagePyramid, BuildingFromRowsGivesTheWholeImagesBits) {
  for (const auto& [w, h] : {std::pair{40, 30}, std::pair{1, 1}, std::pair{7, 2}}) {
    ImageF img(w, h);
    std::mt19937 rng(static_cast<unsigned>(w * h));
    std::uniform_real_distribution<float> grey(0.f, 255.f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) img(x, y) = grey(rng);
    const int levels = ImagePyramid::maxLevels(w, h);
    ImagePyramid whole(w, h, levels), rows(w, h, levels);
    whole.build(img.view());
    RingRows source(img);
    rows.build(source);
    EXPECT_EQ(source.next_, h);
    for (int l = 0; l < levels; ++l)
      for (int y = 0; y < whole.height(l); ++y)
        ASSERT_EQ(std::memcmp(whole.gradients(l).row(y), rows.gradients(l).row(y),
                              sizeof(GradientPixel) * static_cast<std::size_t>(whole.width(l))),
                  0)
            << w << "x" << h << " level " << l << " row " << y;
    // The clipping mask from rows, and from the intensities themselves, as from the image.
    whole.markClipped(img.view(), 128.f);
    RingRows raw(img);
    rows.markClipped(raw, 128.f);
    ImagePyramid own(w, h, levels);
    own.build(img.view());
    own.markClippedFromIntensity(128.f);
    // Built and marked in one pass over the rows: the same planes and the same mask.
    ImagePyramid fused(w, h, levels);
    RingRows fused_rows(img);
    fused.build(fused_rows, 128.f);
    for (int l = 0; l < levels; ++l)
      for (int y = 0; y < whole.height(l); ++y)
        ASSERT_EQ(std::memcmp(whole.gradients(l).row(y), fused.gradients(l).row(y),
                              sizeof(GradientPixel) * static_cast<std::size_t>(whole.width(l))),
                  0);
    int marked = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        EXPECT_EQ(rows.clipped()(x, y), whole.clipped()(x, y));
        EXPECT_EQ(own.clipped()(x, y), whole.clipped()(x, y));
        EXPECT_EQ(fused.clipped()(x, y), whole.clipped()(x, y));
        marked += whole.clipped()(x, y);
      }
    if (w * h > 100) {
      EXPECT_GT(marked, 0);
    }
    // An infinite level leaves the mask empty, also after a build that marked pixels.
    RingRows again(img);
    fused.build(again, std::numeric_limits<float>::infinity());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) ASSERT_EQ(fused.clipped()(x, y), 0);
  }
}

TEST(ImagePyramid, CompactKeepsTheLevel0IntensitiesAndFreesTheRest) {
  const ImageF img = randomGreyImage(7);
  ImagePyramid pyr(40, 30, 3);
  pyr.build(img.view());
  const Image<GradientPixel> before = [&] {
    Image<GradientPixel> g;
    g.copyFrom(pyr.gradients(0));
    return g;
  }();
  EXPECT_FALSE(pyr.level0().isIntensity());
  pyr.compact();
  EXPECT_TRUE(pyr.compacted());
  // Sizes stay; level 0 keeps its intensities alone (4 bytes per pixel), and every pixel's
  // gradients made from them are the packed plane's, bit for bit, on the border too.
  EXPECT_EQ(pyr.levels(), 3);
  EXPECT_EQ(pyr.width(2), 10);
  EXPECT_EQ(pyr.height(2), 7);
  EXPECT_EQ(pyr.bytes(), sizeof(float) * 40 * 30);
  const Level0View g = pyr.level0();
  ASSERT_TRUE(g.isIntensity());
  ASSERT_FALSE(g.isCompact());
  EXPECT_EQ(g.width, 40);
  EXPECT_EQ(g.height, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const GradientPixel a = g.intensity.at(x, y);
      EXPECT_EQ(a.intensity, before(x, y).intensity);
      EXPECT_EQ(a.dx, before(x, y).dx);
      EXPECT_EQ(a.dy, before(x, y).dy);
    }
  // So is any interpolation of them, wherever it may read.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> ux(0.f, 38.999f), uy(0.f, 28.999f);
  for (int i = 0; i < 2000; ++i) {
    const float x = ux(rng), y = uy(rng);
    const GradientPixel a = interpolateBilinear(g, x, y);
    const GradientPixel b = interpolateBilinear(before.view(), x, y);
    ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << x << " " << y;
  }
  EXPECT_THROW(pyr.gradients(0), std::logic_error);
  ImageF level0;
  pyr.copyIntensity(0, level0);
  ASSERT_EQ(level0.width(), 40);
  ASSERT_EQ(level0.height(), 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) EXPECT_EQ(level0(x, y), img(x, y));
  EXPECT_THROW(pyr.copyIntensity(1, level0), std::logic_error);
  EXPECT_THROW(pyr.gradients(1), std::logic_error);
  EXPECT_THROW(pyr.clipped(), std::logic_error);
  EXPECT_THROW(pyr.gradMagSq(0), std::logic_error);
  EXPECT_THROW(pyr.markClipped(img.view(), 250.f), std::logic_error);
  // A new build gives every plane back, filled as in a fresh pyramid.
  pyr.build(img.view());
  EXPECT_FALSE(pyr.compacted());
  ImagePyramid fresh(40, 30, 3);
  fresh.build(img.view());
  for (int l = 0; l < 3; ++l)
    for (int y = 0; y < fresh.height(l); ++y)
      for (int x = 0; x < fresh.width(l); ++x) {
        EXPECT_EQ(intensityAt(pyr, l, x, y), intensityAt(fresh, l, x, y));
        EXPECT_EQ(pyr.gradients(l)(x, y).dx, fresh.gradients(l)(x, y).dx);
        EXPECT_EQ(pyr.gradMagSq(l)(x, y), fresh.gradMagSq(l)(x, y));
      }
  EXPECT_EQ(pyr.clipped()(5, 5), 0);
}

// A keyframe leaving the window hands its image on to be described: moved out of a compacted
// pyramid (which can then no longer be sampled), copied from any other.
TEST(ImagePyramid, TakingLevel0MovesTheIntensitiesOfACompactedPyramid) {
  const ImageF img = randomGreyImage(11);
  ImagePyramid pyr(40, 30, 3);
  pyr.build(img.view());
  ImageF copied;
  pyr.takeIntensity0(copied);  // not compacted: a copy, the pyramid stays whole
  EXPECT_FALSE(pyr.compacted());
  EXPECT_EQ(pyr.gradients(0)(3, 4).intensity, img(3, 4));
  pyr.compact();
  ImageF taken;
  pyr.takeIntensity0(taken);
  EXPECT_EQ(pyr.bytes(), 0u);
  EXPECT_THROW(pyr.level0(), std::logic_error);
  ImageF again;
  EXPECT_THROW(pyr.copyIntensity(0, again), std::logic_error);
  ASSERT_EQ(taken.width(), 40);
  ASSERT_EQ(taken.height(), 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      EXPECT_EQ(taken(x, y), img(x, y));
      EXPECT_EQ(copied(x, y), img(x, y));
    }
  // A new build makes it whole again.
  pyr.build(img.view());
  EXPECT_FALSE(pyr.level0().isIntensity());
  pyr.copyIntensity(0, again);
  EXPECT_EQ(again(5, 6), img(5, 6));
  // In 16 bits the decoded values are copied.
  pyr.compact(true);
  ImageF decoded;
  pyr.takeIntensity0(decoded);
  EXPECT_NEAR(decoded(5, 6), img(5, 6), 1.f / 256.f);
  EXPECT_TRUE(pyr.level0().isCompact());
}

TEST(ImagePyramid, CompactIn16BitsKeepsLevel0WithinHalfAStep) {
  const ImageF img = randomGreyImage(9);
  ImagePyramid pyr(40, 30, 3);
  pyr.build(img.view());
  Image<GradientPixel> before;
  before.copyFrom(pyr.gradients(0));
  EXPECT_FALSE(pyr.level0().isCompact());
  pyr.compact(true);
  EXPECT_TRUE(pyr.compacted());
  // Grey levels up to 255: steps of 1/128, every intensity within half a step and so every
  // central difference too; 2 bytes per pixel; the float planes are gone.
  EXPECT_EQ(pyr.bytes(), sizeof(std::int16_t) * 40 * 30);
  const Level0View g = pyr.level0();
  ASSERT_TRUE(g.isCompact());
  ASSERT_FALSE(g.isIntensity());
  EXPECT_EQ(g.width, 40);
  EXPECT_EQ(g.height, 30);
  const float step = g.compact.step;
  EXPECT_EQ(step, 1.f / 128.f);
  ImageF decoded(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      EXPECT_NEAR(g.compact.at(x, y).intensity, before(x, y).intensity, 0.5f * step);
      EXPECT_NEAR(g.compact.at(x, y).dx, before(x, y).dx, 0.5f * step);
      EXPECT_NEAR(g.compact.at(x, y).dy, before(x, y).dy, 0.5f * step);
      decoded(x, y) = g.compact.intensity(x, y);
    }
  // It reads exactly as the float intensity plane of the decoded values.
  const IntensityPlaneView as_float{decoded.view()};
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const GradientPixel a = g.compact.at(x, y), b = as_float.at(x, y);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << x << " " << y;
    }
  ImageF level0;
  pyr.copyIntensity(0, level0);
  ASSERT_EQ(level0.width(), 40);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) EXPECT_EQ(level0(x, y), g.compact.at(x, y).intensity);
  EXPECT_THROW(pyr.gradients(0), std::logic_error);
  EXPECT_THROW(pyr.gradients(1), std::logic_error);
  // A new build gives the float planes back.
  pyr.build(img.view());
  EXPECT_FALSE(pyr.level0().isCompact());
  EXPECT_EQ(pyr.gradients(0)(7, 9).dx, before(7, 9).dx);
}

TEST(ImagePyramid, ALevel0WithANonFiniteValueKeepsItsFloatIntensitiesWhenCompactedIn16Bits) {
  ImageF img(16, 12, 100.f);
  img(5, 5) = std::numeric_limits<float>::infinity();
  ImagePyramid pyr(16, 12, 2);
  pyr.build(img.view());
  pyr.compact(true);
  EXPECT_TRUE(pyr.compacted());
  ASSERT_FALSE(pyr.level0().isCompact());
  ASSERT_TRUE(pyr.level0().isIntensity());
  EXPECT_EQ(pyr.level0().intensity.at(5, 5).intensity, std::numeric_limits<float>::infinity());
  EXPECT_EQ(pyr.bytes(), sizeof(float) * 16 * 12);
  EXPECT_THROW(pyr.gradients(0), std::logic_error);
  EXPECT_THROW(pyr.gradients(1), std::logic_error);
}

TEST(CompactPlane, TheStepIsTheFinestPowerOfTwoAtWhichTheLargestValueFits) {
  EXPECT_EQ(CompactPlane::stepFor(255.f), 1.f / 128.f);
  EXPECT_EQ(CompactPlane::stepFor(255.9f), 1.f / 128.f);
  EXPECT_EQ(CompactPlane::stepFor(256.f), 1.f / 64.f);
  EXPECT_EQ(CompactPlane::stepFor(32767.f), 1.f);
  EXPECT_EQ(CompactPlane::stepFor(32768.f), 2.f);
  EXPECT_EQ(CompactPlane::stepFor(1e6f), 32.f);
  EXPECT_EQ(CompactPlane::stepFor(0.f), 1.f / 16384.f);
  // Encoded values round to the nearest step (ties to even) and stay inside int16.
  ImageF plane(3, 3, 1000.f);
  plane(1, 0) = -1000.f;
  plane(1, 2) = 0.3f;
  plane(2, 1) = -2047.9f;  // x16: -32766.4
  plane(0, 1) = 2047.9f;
  plane(1, 1) = 3.f / 32.f;  // x16: 1.5
  CompactPlane c;
  ASSERT_TRUE(c.encode(plane.view()));
  const CompactPlaneView v = c.view();
  EXPECT_EQ(v.step, 1.f / 16.f);
  EXPECT_EQ(v.intensity(0, 0), 1000.f);
  EXPECT_EQ(v.intensity(1, 0), -1000.f);
  EXPECT_EQ(v.intensity(1, 2), 0.3125f);
  EXPECT_EQ(v.intensity(2, 1), -2047.875f);
  EXPECT_EQ(v.intensity(0, 1), 2047.875f);
  EXPECT_EQ(v.intensity(1, 1), 0.125f);
  // The inner pixel's gradients are the decoded values' central differences; the border's zero.
  EXPECT_EQ(v.at(1, 1).dx, 0.5f * (-2047.875f - 2047.875f));
  EXPECT_EQ(v.at(1, 1).dy, 0.5f * (0.3125f - -1000.f));
  EXPECT_EQ(v.at(0, 1).dx, 0.f);
  EXPECT_EQ(v.at(1, 0).dy, 0.f);
  plane(1, 0) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(c.encode(plane.view()));
  EXPECT_TRUE(c.empty());
}

TEST(PyramidPool, ACompactedPyramidComesBackWhole) {
  PyramidPool pool(32, 24, 3);
  std::unique_ptr<ImagePyramid> p = pool.acquire();
  const ImagePyramid* address = p.get();
  p->compact();
  pool.release(std::move(p));
  std::unique_ptr<ImagePyramid> again = pool.acquire();
  EXPECT_EQ(again.get(), address);
  EXPECT_FALSE(again->compacted());
  EXPECT_EQ(again->gradients(2).width, 8);
  EXPECT_EQ(again->gradients(1).height, 12);
}

TEST(PyramidPool, KeepsAtMostMaxFreePyramids) {
  PyramidPool pool(32, 24, 3, /*max_free=*/2);
  std::vector<std::unique_ptr<ImagePyramid>> taken;
  for (int i = 0; i < 4; ++i) taken.push_back(pool.acquire());
  std::vector<const ImagePyramid*> addresses;
  for (auto& p : taken) addresses.push_back(p.get());
  taken[1]->compact();
  for (auto& p : taken) pool.release(std::move(p));
  // The first two came back and are kept (the compacted one whole again); the others were freed.
  EXPECT_EQ(pool.freeCount(), 2u);
  std::unique_ptr<ImagePyramid> a = pool.acquire();
  std::unique_ptr<ImagePyramid> b = pool.acquire();
  EXPECT_EQ(pool.freeCount(), 0u);
  EXPECT_EQ(a.get(), addresses[1]);
  EXPECT_EQ(b.get(), addresses[0]);
  EXPECT_FALSE(a->compacted());
  EXPECT_EQ(a->gradients(0).width, 32);
  // An empty pool makes a new pyramid of the pool's size.
  std::unique_ptr<ImagePyramid> c = pool.acquire();
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->levels(), 3);
  EXPECT_EQ(c->width(0), 32);
  EXPECT_EQ(c->height(0), 24);
  pool.release(nullptr);
  EXPECT_EQ(pool.freeCount(), 0u);
}

TEST(PyramidPool, KeepsAtLeastOnePyramid) {
  PyramidPool pool(16, 16, 2, /*max_free=*/0);
  std::unique_ptr<ImagePyramid> p = pool.acquire();
  const ImagePyramid* address = p.get();
  pool.release(std::move(p));
  EXPECT_EQ(pool.freeCount(), 1u);
  EXPECT_EQ(pool.acquire().get(), address);
}

}  // namespace
}  // namespace ldsm
