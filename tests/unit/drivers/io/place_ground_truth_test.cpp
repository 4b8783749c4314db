#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/place_ground_truth.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm {
namespace {

void put16(std::vector<std::uint8_t>& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v);
  b[at + 1] = static_cast<std::uint8_t>(v >> 8);
}
void put32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k)
    b[at + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(v >> (8 * k));
}

/// A BMP written by the book: 8-bit with a grey palette or 24-bit, rows padded to 4 bytes,
/// bottom-up when `bottom_up`. pixel(x, y) = value at column x of row y (top row y = 0).
std::vector<std::uint8_t> makeBmp(int w, int h, int bpp, bool bottom_up,
                                  const std::vector<std::vector<std::uint8_t>>& pixel) {
  const std::size_t palette = bpp == 8 ? 1024 : 0;
  const std::size_t stride =
      (static_cast<std::size_t>(w) * static_cast<std::size_t>(bpp) / 8 + 3) / 4 * 4;
  const std::size_t offset = 54 + palette;
  std::vector<std::uint8_t> b(offset + stride * static_cast<std::size_t>(h), 0);
  b[0] = 'B';
  b[1] = 'M';
  put32(b, 2, static_cast<std::uint32_t>(b.size()));
  put32(b, 10, static_cast<std::uint32_t>(offset));
  put32(b, 14, 40);
  put32(b, 18, static_cast<std::uint32_t>(w));
  put32(b, 22, static_cast<std::uint32_t>(bottom_up ? h : -h));
  put16(b, 26, 1);
  put16(b, 28, static_cast<std::uint16_t>(bpp));
  if (bpp == 8) {
    put32(b, 46, 256);
    for (int c = 0; c < 256; ++c) {
      for (int k = 0; k < 3; ++k)
        b[54 + 4 * static_cast<std::size_t>(c) + static_cast<std::size_t>(k)] =
            static_cast<std::uint8_t>(c);
    }
  }
  for (int y = 0; y < h; ++y) {
    const int row = bottom_up ? h - 1 - y : y;
    for (int x = 0; x < w; ++x) {
      const std::uint8_t v = pixel[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)];
      if (bpp == 8) {
        b[offset + stride * static_cast<std::size_t>(row) + static_cast<std::size_t>(x)] = v;
      } else {
        for (int k = 0; k < 3; ++k)
          b[offset + stride * static_cast<std::size_t>(row) + 3 * static_cast<std::size_t>(x) +
            static_cast<std::size_t>(k)] = v;
      }
    }
  }
  return b;
}

std::string writeFile(const std::string& path, const std::vector<std::uint8_t>& b) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  return path;
}

std::vector<std::vector<std::uint8_t>> pattern(int n) {
  std::vector<std::vector<std::uint8_t>> p(
      static_cast<std::size_t>(n), std::vector<std::uint8_t>(static_cast<std::size_t>(n), 0));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (j < i && (i - j) % 3 == 0)
        p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = 255;
    }
  }
  return p;
}

TEST(PlaceGroundTruth, ReadsEightAndTwentyFourBitBmpBothRowOrders) {
  const std::string dir = test::scratchDir("loop_bow_ground_truth");
  const int n = 7;  // odd: rows need padding
  const auto p = pattern(n);
  for (int bpp : {8, 24}) {
    for (bool bottom_up : {true, false}) {
      const std::string path =
          writeFile(dir + "/gt_" + std::to_string(bpp) + (bottom_up ? "b" : "t") + ".bmp",
                    makeBmp(n, n, bpp, bottom_up, p));
      const auto gt = drivers::readPlaceGroundTruth(path);
      ASSERT_EQ(gt.size(), static_cast<std::size_t>(n)) << path;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          EXPECT_EQ(gt[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)],
                    p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] ? 1 : 0)
              << path << " (" << i << ", " << j << ")";
        }
      }
    }
  }
  // A PNG works too.
  ImageU8 img(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      img(j, i) = p[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  }
  calib::writePng(dir + "/gt.png", img.view());
  EXPECT_EQ(drivers::readPlaceGroundTruth(dir + "/gt.png")[6][3], 1);
  EXPECT_EQ(drivers::readPlaceGroundTruth(dir + "/gt.png")[6][4], 0);
}

TEST(PlaceGroundTruth, BadFilesAreReportedWithTheirPath) {
  const std::string dir = test::scratchDir("loop_bow_ground_truth_bad");
  auto expectError = [](const std::string& path, const std::string& what) {
    try {
      drivers::readPlaceGroundTruth(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(path, 0), 0u) << m;
      EXPECT_NE(m.find(what), std::string::npos) << m;
    }
  };
  expectError(dir + "/missing.bmp", "no such file");
  const auto p = pattern(6);
  expectError(writeFile(dir + "/wide.bmp", makeBmp(6, 5, 8, true, p)), "must be square");
  auto b = makeBmp(6, 6, 8, true, p);
  put32(b, 30, 1);  // RLE8
  expectError(writeFile(dir + "/rle.bmp", b), "compressed");
  b = makeBmp(6, 6, 8, true, p);
  put16(b, 28, 4);
  expectError(writeFile(dir + "/4bit.bmp", b), "bits per pixel");
  b = makeBmp(6, 6, 24, true, p);
  b.resize(b.size() - 10);
  expectError(writeFile(dir + "/short.bmp", b), "truncated");
  expectError(writeFile(dir + "/tiny.bmp", {'B', 'M', 0, 0}), "truncated");
  expectError(writeFile(dir + "/text.bmp", {'h', 'e', 'l', 'l', 'o'}), "cannot decode");
}

TEST(PlaceGroundTruth, DatasetImageCountMustMatch) {
  const std::string dir = test::scratchDir("loop_bow_place_dataset");
  std::filesystem::create_directories(dir + "/samples");
  ImageU8 img(64, 48, 100);
  for (int i = 1; i <= 3; ++i)
    calib::writePng(dir + "/samples/" + std::to_string(i) + ".png", img.view());
  writeFile(dir + "/samples_GT.bmp", makeBmp(4, 4, 8, true, pattern(4)));
  try {
    drivers::readPlaceDataset(dir);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ground truth for 4 images"), std::string::npos)
        << e.what();
  }
  writeFile(dir + "/samples_GT.bmp", makeBmp(3, 3, 8, true, pattern(3)));
  const drivers::PlaceDataset d = drivers::readPlaceDataset(dir);
  EXPECT_EQ(d.images.size(), 3u);
  EXPECT_EQ(d.same_place.size(), 3u);
}

}  // namespace
}  // namespace ldsm
