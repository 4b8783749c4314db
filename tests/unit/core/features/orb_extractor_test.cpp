#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "features/orb_extractor.h"
#include "ldsm/error.h"

namespace ldsm::loop {
namespace {

constexpr int kW = 400;
constexpr int kH = 300;

/// A textured 8-bit image: smoothed noise at two scales (corners everywhere).
cv::Mat texture(int seed) {
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  cv::Mat coarse(kH / 8, kW / 8, CV_32F), fine(kH, kW, CV_32F);
  rng.fill(coarse, cv::RNG::UNIFORM, 0.f, 255.f);
  rng.fill(fine, cv::RNG::UNIFORM, 0.f, 255.f);
  cv::resize(coarse, coarse, cv::Size(kW, kH), 0, 0, cv::INTER_CUBIC);
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 2.0);
  cv::Mat sum = 0.6 * coarse + 0.8 * (fine - 127.f) + 40.f;
  cv::Mat out;
  sum.convertTo(out, CV_8U);
  return out;
}

ImageView<const std::uint8_t> viewOf(const cv::Mat& m) {
  return {m.ptr<std::uint8_t>(), m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step)};
}

std::vector<Eigen::Vector2f> corners(const cv::Mat& img, int border) {
  std::vector<cv::Point2f> pts;
  cv::goodFeaturesToTrack(img, pts, 150, 0.01, 10);
  std::vector<Eigen::Vector2f> out;
  for (const auto& p : pts) {
    if (p.x >= border && p.y >= border && p.x < kW - border && p.y < kH - border)
      out.emplace_back(p.x, p.y);
  }
  return out;
}

int median(std::vector<int> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(OrbExtractor, DescriptorsSurviveSmallRotationAndBrightnessChange) {
  const cv::Mat img = texture(1);
  const std::vector<Eigen::Vector2f> pts = corners(img, 40);
  ASSERT_GE(pts.size(), 40u);
  // Rotate by 10 degrees about the centre, then brighten: I' = 1.15 I + 12.
  const cv::Mat rot = cv::getRotationMatrix2D(cv::Point2f(kW / 2.f, kH / 2.f), 10.0, 1.0);
  cv::Mat warped;
  cv::warpAffine(img, warped, rot, img.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  warped.convertTo(warped, CV_8U, 1.15, 12.0);
  std::vector<Eigen::Vector2f> moved;
  for (const auto& p : pts) {
    moved.emplace_back(static_cast<float>(rot.at<double>(0, 0) * p.x() +
                                          rot.at<double>(0, 1) * p.y() + rot.at<double>(0, 2)),
                       static_cast<float>(rot.at<double>(1, 0) * p.x() +
                                          rot.at<double>(1, 1) * p.y() + rot.at<double>(1, 2)));
  }
  OrbExtractor orb(kW, kH);
  std::vector<OrbDescriptor> a, b;
  std::vector<std::uint32_t> ka, kb;
  orb.compute(viewOf(img), pts, a, ka);
  orb.compute(viewOf(warped), moved, b, kb);
  ASSERT_EQ(ka.size(), pts.size());
  ASSERT_EQ(kb.size(), pts.size());
  std::vector<int> same, other;
  for (std::size_t i = 0; i < a.size(); ++i) {
    same.push_back(hammingDistance(a[i], b[i]));
    other.push_back(hammingDistance(a[i], b[(i + 7) % b.size()]));
  }
  // Matching descriptors are close, unrelated ones about 128 bits apart.
  EXPECT_LT(median(same), 40);
  EXPECT_GT(median(other), 95);
  // Nearest-neighbour matching recovers most correspondences.
  int correct = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < b.size(); ++j) {
      if (hammingDistance(a[i], b[j]) < hammingDistance(a[i], b[best])) best = j;
    }
    correct += best == i ? 1 : 0;
  }
  EXPECT_GE(correct, static_cast<int>(0.85 * static_cast<double>(a.size())));
}

TEST(OrbExtractor, CoarseLevelMatchesTheDownscaledImage) {
  // A keypoint described on level 1 (scale 1.2) of the image sees what level 0 of the image
  // downscaled by 1.2 sees.
  const cv::Mat img = texture(2);
  const std::vector<Eigen::Vector2f> pts = corners(img, 50);
  ASSERT_GE(pts.size(), 30u);
  cv::Mat small;
  cv::resize(img, small, cv::Size(cvRound(kW / 1.2), cvRound(kH / 1.2)), 0, 0,
             cv::INTER_LINEAR_EXACT);
  std::vector<Eigen::Vector2f> scaled;
  for (const auto& p : pts) scaled.push_back(p / 1.2f);
  const std::vector<int> level1(pts.size(), 1);
  OrbExtractor big(kW, kH), little(small.cols, small.rows);
  std::vector<OrbDescriptor> a, b, a0;
  std::vector<std::uint32_t> ka, kb, ka0;
  big.compute(viewOf(img), pts, a, ka, &level1);
  little.compute(viewOf(small), scaled, b, kb);
  big.compute(viewOf(img), pts, a0, ka0);
  ASSERT_EQ(a.size(), pts.size());
  ASSERT_EQ(b.size(), pts.size());
  std::vector<int> across, level0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    across.push_back(hammingDistance(a[i], b[i]));
    level0.push_back(hammingDistance(a0[i], b[i]));
  }
  EXPECT_LT(median(across), 25);
  // Without the pyramid (level 0 against the downscaled image) they agree much less.
  EXPECT_GT(median(level0), median(across) + 10);
}

TEST(OrbExtractor, DropsKeypointsWhosePatchDoesNotFit) {
  const cv::Mat img = texture(3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector2f> pts{{5.f, 100.f},       {14.9f, 100.f},     {15.f, 100.f},
                                         {kW - 16.f, 100.f}, {kW - 15.4f, 50.f}, {100.f, kH - 16.f},
                                         {nan, 100.f},       {100.f, 100.f},     {100.f, 14.f}};
  OrbExtractor orb(kW, kH);
  std::vector<OrbDescriptor> d;
  std::vector<std::uint32_t> kept;
  EXPECT_EQ(orb.compute(viewOf(img), pts, d, kept), 4);
  EXPECT_EQ(kept, (std::vector<std::uint32_t>{2, 3, 5, 7}));
  EXPECT_EQ(d.size(), 4u);
}

TEST(OrbExtractor, FallsBackToAFinerLevelNearTheBorder) {
  const cv::Mat img = texture(4);
  // At level 2 (scale 1.44) x = 20 maps to 13.9: the patch does not fit; at level 1 (16.7) it
  // does. Far from the border, level 2 is used as asked.
  const std::vector<Eigen::Vector2f> pts{{20.f, 150.f}, {200.f, 150.f}};
  OrbExtractor orb(kW, kH);
  auto describe = [&](int level) {
    std::vector<OrbDescriptor> d;
    std::vector<std::uint32_t> k;
    const std::vector<int> levels(pts.size(), level);
    orb.compute(viewOf(img), pts, d, k, &levels);
    EXPECT_EQ(k.size(), 2u);
    return d;
  };
  const auto l0 = describe(0), l1 = describe(1), l2 = describe(2), l9 = describe(9);
  EXPECT_EQ(l2[0], l1[0]);
  EXPECT_NE(l1[0], l0[0]);
  EXPECT_NE(l2[1], l1[1]);
  EXPECT_EQ(l9[1], l2[1]);  // clamped to the top level
}

TEST(OrbExtractor, FloatAndByteImagesGiveTheSameDescriptors) {
  const cv::Mat img = texture(5);
  cv::Mat f;
  img.convertTo(f, CV_32F);
  const auto pts = corners(img, 20);
  OrbExtractor orb(kW, kH);
  std::vector<OrbDescriptor> a, b;
  std::vector<std::uint32_t> ka, kb;
  orb.compute(viewOf(img), pts, a, ka);
  orb.compute(ImageView<const float>(f.ptr<float>(), kW, kH,
                                     static_cast<std::ptrdiff_t>(f.step / sizeof(float))),
              pts, b, kb);
  EXPECT_EQ(a, b);
  EXPECT_EQ(ka, kb);
  // The intensities of a packed pyramid level too (with fractional and out-of-range values,
  // which the float path rounds and clamps the same way).
  std::vector<GradientPixel> packed(static_cast<std::size_t>(kW) * kH);
  std::vector<float> plain(packed.size());
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float v = 1.3f * f.at<float>(y, x) - 20.25f;
      plain[static_cast<std::size_t>(y) * kW + x] = v;
      packed[static_cast<std::size_t>(y) * kW + x] = {v, 1.f, -1.f};
    }
  orb.compute(ImageView<const float>(plain.data(), kW, kH), pts, a, ka);
  orb.compute(ImageView<const GradientPixel>(packed.data(), kW, kH), pts, b, kb);
  EXPECT_EQ(a, b);
  EXPECT_EQ(ka, kb);
  EXPECT_THROW(orb.compute(ImageView<const GradientPixel>(packed.data(), kW - 1, kH), pts, b, kb),
               InputError);
  // A uniform image gives well-defined (all-equal) descriptors, not garbage.
  cv::Mat flat(kH, kW, CV_8U, cv::Scalar(90));
  orb.compute(viewOf(flat), pts, a, ka);
  for (const auto& d : a) EXPECT_EQ(d, a.front());
}

TEST(OrbExtractor, RejectsBadInput) {
  EXPECT_THROW(OrbExtractor(0, 10), InputError);
  OrbExtractorSettings s;
  s.levels = 0;
  EXPECT_THROW(OrbExtractor(100, 100, s), ConfigError);
  s.levels = 3;
  s.scale_factor = 1.f;
  EXPECT_THROW(OrbExtractor(100, 100, s), ConfigError);
  OrbExtractor orb(kW, kH);
  const cv::Mat img = texture(6);
  cv::Mat wrong(kH - 1, kW, CV_8U, cv::Scalar(0));
  std::vector<OrbDescriptor> d;
  std::vector<std::uint32_t> k;
  const std::vector<Eigen::Vector2f> pts{{100.f, 100.f}};
  EXPECT_THROW(orb.compute(viewOf(wrong), pts, d, k), InputError);
  const std::vector<int> levels{0, 1};
  EXPECT_THROW(orb.compute(viewOf(img), pts, d, k, &levels), InputError);
}

}  // namespace
}  // namespace ldsm::loop
