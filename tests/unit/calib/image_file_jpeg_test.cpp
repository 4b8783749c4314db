// JPEG decoding: grey and colour files written by libjpeg's own compressor, compared with the
// images they were made from, and broken files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "encoded_images.h"
#include "ldsm/calib/image_file.h"

namespace ldsm::calib {
namespace {

using test::Bytes;
using test::encodeJpeg;
using test::inputErrorOf;
using ::testing::HasSubstr;
using ::testing::StartsWith;

// libjpeg's J_COLOR_SPACE values.
constexpr int kGrey = 1;
constexpr int kRgb = 2;
constexpr int kYcbcr = 3;
constexpr int kCmyk = 4;

constexpr int kW = 48;
constexpr int kH = 32;

/// A smooth image (JPEG keeps it nearly exactly at quality 100): channel c of pixel (x, y).
std::uint8_t smooth(int x, int y, int c) {
  return static_cast<std::uint8_t>(
      std::lround(127.5 + 100.0 * std::sin(0.11 * x + 0.7 * c) * std::cos(0.13 * y - 0.3 * c)));
}

std::vector<std::uint8_t> smoothSamples(int channels) {
  std::vector<std::uint8_t> s;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < channels; ++c) s.push_back(smooth(x, y, c));
  return s;
}

double luma(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return 0.299 * r + 0.587 * g + 0.114 * b;
}

TEST(JpegFile, GreyDecodesToTheEncodedImage) {
  const std::vector<std::uint8_t> samples = smoothSamples(1);
  const Bytes jpeg = encodeJpeg(samples, kW, kH, 1, kGrey, 100);
  ImageU8 out;
  const ImageFileInfo info = decodeImage(jpeg.data(), jpeg.size(), "g.jpg", out);
  EXPECT_EQ(info.format, ImageFileFormat::Jpeg);
  EXPECT_EQ(info.channels, 1);
  EXPECT_EQ(info.bit_depth, 8);
  ASSERT_EQ(out.width(), kW);
  ASSERT_EQ(out.height(), kH);
  double total = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double e = std::abs(out(x, y) - samples[static_cast<std::size_t>(y) * kW + x]);
      ASSERT_LE(e, 2.0) << x << "," << y;
      total += e;
    }
  EXPECT_LT(total / (kW * kH), 0.5);
}

TEST(JpegFile, ColourDecodesToItsLumaWhateverTheStoredColourSpace) {
  const std::vector<std::uint8_t> samples = smoothSamples(3);
  for (const int stored : {kYcbcr, kRgb}) {
    const Bytes jpeg = encodeJpeg(samples, kW, kH, 3, stored, 100);
    ImageU8 out;
    const ImageFileInfo info = decodeImage(jpeg.data(), jpeg.size(), "c.jpg", out);
    EXPECT_EQ(info.channels, 3);
    double total = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const std::size_t i = (static_cast<std::size_t>(y) * kW + x) * 3;
        const double e = std::abs(out(x, y) - luma(samples[i], samples[i + 1], samples[i + 2]));
        ASSERT_LE(e, 3.0) << "stored " << stored << " at " << x << "," << y;
        total += e;
      }
    EXPECT_LT(total / (kW * kH), 1.0) << "stored " << stored;
  }
}

TEST(JpegFile, SixteenBitOutputIsTheEightBitOneScaled) {
  const Bytes jpeg = encodeJpeg(smoothSamples(3), kW, kH, 3, kYcbcr, 90);
  ImageU8 g8;
  ImageU16 g16;
  decodeImage(jpeg.data(), jpeg.size(), "c.jpg", g8);
  decodeImage(jpeg.data(), jpeg.size(), "c.jpg", g16);
  ASSERT_EQ(g16.width(), kW);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) ASSERT_EQ(g16(x, y), g8(x, y) * 257);
}

std::string decodeError(const Bytes& bytes) {
  ImageU8 out;
  return inputErrorOf([&] { decodeImage(bytes.data(), bytes.size(), "bad.jpg", out); });
}

TEST(JpegFileErrors, TruncatedFilesAreErrorsNotGreyPadding) {
  const Bytes good = encodeJpeg(smoothSamples(1), kW, kH, 1, kGrey, 95);
  for (const std::size_t cut :
       {std::size_t{3}, std::size_t{40}, good.size() / 2, good.size() - 2}) {
    const Bytes bad(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_THAT(decodeError(bad), StartsWith("bad.jpg: cannot decode image: JPEG: ")) << cut;
  }
  const Bytes half(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() / 2));
  EXPECT_THAT(decodeError(half), HasSubstr("Premature end"));
}

/// Offset of the first marker 0xFF `code` in a JPEG file.
std::size_t markerOffset(const Bytes& jpeg, unsigned char code) {
  for (std::size_t i = 0; i + 1 < jpeg.size(); ++i)
    if (jpeg[i] == 0xff && jpeg[i + 1] == code) return i;
  ADD_FAILURE() << "no marker " << int{code};
  return 0;
}

TEST(JpegFileErrors, CorruptMarkersAndData) {
  const Bytes good = encodeJpeg(smoothSamples(1), kW, kH, 1, kGrey, 95);
  const std::size_t sof = markerOffset(good, 0xc0);  // FF C0, length (2), precision, height...
  Bytes bad_precision = good;
  bad_precision[sof + 4] = 7;
  EXPECT_THAT(decodeError(bad_precision), StartsWith("bad.jpg: cannot decode image: JPEG: "));
  EXPECT_THAT(decodeError(bad_precision), HasSubstr("precision 7"));
  Bytes bad_length = good;
  bad_length[sof + 3] = 3;  // segment length too short for a frame header
  EXPECT_THAT(decodeError(bad_length), StartsWith("bad.jpg: cannot decode image: JPEG: "));
  Bytes empty_image = good;
  empty_image[sof + 5] = 0;
  empty_image[sof + 6] = 0;  // height 0
  EXPECT_THAT(decodeError(empty_image), StartsWith("bad.jpg: cannot decode image: JPEG: "));
  Bytes bad_huffman = good;
  const std::size_t dht = markerOffset(good, 0xc4);  // FF C4, length, class/id, 16 counts
  for (int i = 0; i < 16; ++i) bad_huffman[dht + 5 + i] = 0xff;
  EXPECT_THAT(decodeError(bad_huffman), StartsWith("bad.jpg: cannot decode image: JPEG: "));
  // Entropy-coded data replaced by a marker in the middle of the scan.
  Bytes bad_scan = good;
  const std::size_t mid = good.size() / 2;
  bad_scan[mid] = 0xff;
  bad_scan[mid + 1] = 0xd0 + 3;  // an out-of-sequence restart marker
  EXPECT_THAT(decodeError(bad_scan), StartsWith("bad.jpg: cannot decode image: JPEG: "));
  const Bytes soi_only = {0xff, 0xd8, 0xff, 0xd9};
  EXPECT_THAT(decodeError(soi_only), StartsWith("bad.jpg: cannot decode image: JPEG: "));
}

TEST(JpegFileErrors, CmykIsNotSupported) {
  const Bytes cmyk = encodeJpeg(smoothSamples(4), kW, kH, 4, kCmyk, 90);
  EXPECT_EQ(decodeError(cmyk),
            "bad.jpg: cannot decode image: JPEG: unsupported colour space CMYK (grey, YCbCr and "
            "RGB are supported)");
}

}  // namespace
}  // namespace ldsm::calib
