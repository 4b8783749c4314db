// Small dataset folders written by the dataset tests themselves: tiny PNG images with a known
// pattern per frame, timestamp files, zip archives.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "ldsm/image.h"
#include "test_paths.h"

namespace ldsm::test {

inline constexpr int kFixtureWidth = 24;
inline constexpr int kFixtureHeight = 16;

/// A fresh scratch folder named after the running test (tests may run in parallel processes).
inline std::string testDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return scratchDir(std::string("datasets/") + info->test_suite_name() + "." + info->name());
}

/// The grey value of pixel (x, y) of fixture frame `k`: distinct per frame and per pixel.
inline unsigned char patternValue(int k, int x, int y) {
  return static_cast<unsigned char>((7 * x + 13 * y + 29 * k) % 256);
}

inline cv::Mat patternImage(int k, int width = kFixtureWidth, int height = kFixtureHeight) {
  cv::Mat m(height, width, CV_8U);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) m.at<unsigned char>(y, x) = patternValue(k, x, y);
  return m;
}

/// Number of pixels of `image` that differ from fixture frame `k`.
inline int countPatternMismatches(const ImageU8& image, int k) {
  int bad = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) bad += image(x, y) != patternValue(k, x, y) ? 1 : 0;
  return bad;
}

inline void writeImage(const std::string& path, const cv::Mat& image) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  ASSERT_TRUE(cv::imwrite(path, image)) << path;
}

inline void writeText(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

inline std::vector<unsigned char> encodePng(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  cv::imencode(".png", image, bytes);
  return bytes;
}

/// A zip archive of (entry name, bytes) pairs, written with libzip; a name ending in '/' adds a
/// folder entry.
void writeZip(const std::string& path,
              const std::vector<std::pair<std::string, std::vector<unsigned char>>>& entries);

/// TUM-Mono folder: times.txt "id t exposure" with t = 0.05 k and exposure = 10 + k, images/
/// (or images.zip when `zipped`) holding frames 0..n-1, camera.txt, pcalib.txt (identity
/// response), vignette.png (flat) and groundtruth.txt.
void writeTumMonoFixture(const std::string& root, int n, bool zipped);

/// EuRoC folder: mav0/cam0/data.csv (t = 1403715273.0 s + 0.05 k, in ns), data/<ns>.png and a
/// sensor.yaml (radial-tangential, fx 20, fy 21).
void writeEurocFixture(const std::string& root, int n);

/// KITTI folder: sequences/04/{image_0/NNNNNN.png, times.txt (0.1 k), calib.txt}, poses/04.txt.
void writeKittiFixture(const std::string& root, int n);

/// TUM RGB-D folder: rgb.txt "t rgb/<t>.png" with t = 1305031102.0 + 0.033 k, colour images.
void writeTumRgbdFixture(const std::string& root, int n);

}  // namespace ldsm::test
