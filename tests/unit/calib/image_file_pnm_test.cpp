// Binary PGM/PPM decoding: header syntax, 8/16-bit samples and maxval scaling, colour to grey,
// and malformed files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "encoded_images.h"
#include "ldsm/calib/image_file.h"

namespace ldsm::calib {
namespace {

using test::Bytes;
using test::inputErrorOf;
using ::testing::HasSubstr;

Bytes pnm(const std::string& header, const std::vector<std::uint16_t>& samples, bool wide) {
  Bytes b(header.begin(), header.end());
  for (const std::uint16_t v : samples) {
    if (wide) b.push_back(static_cast<unsigned char>(v >> 8));
    b.push_back(static_cast<unsigned char>(v & 0xff));
  }
  return b;
}

TEST(PnmFile, EightBitGreyWithComments) {
  // The first sample is 10, a newline byte: exactly one whitespace byte ends the header.
  const Bytes b =
      pnm("P5\n# made by hand\n4 # width\n2\n255\n", {10, 10, 20, 30, 40, 50, 255, 128}, false);
  ImageU8 out;
  const ImageFileInfo info = decodeImage(b.data(), b.size(), "a.pgm", out);
  EXPECT_EQ(info.format, ImageFileFormat::Pnm);
  EXPECT_EQ(info.channels, 1);
  EXPECT_EQ(info.bit_depth, 8);
  ASSERT_EQ(out.width(), 4);
  ASSERT_EQ(out.height(), 2);
  EXPECT_EQ(out(0, 0), 10);
  EXPECT_EQ(out(1, 0), 10);
  EXPECT_EQ(out(2, 1), 255);
  EXPECT_EQ(out(3, 1), 128);
}

TEST(PnmFile, SixteenBitSamplesAreBigEndianAndScaledByMaxval) {
  const std::vector<std::uint16_t> s = {0, 1, 512, 1023, 700, 300};
  const Bytes b = pnm("P5 3 2 1023 ", s, true);
  ImageU16 g16;
  ImageU8 g8;
  const ImageFileInfo info = decodeImage(b.data(), b.size(), "a.pgm", g16);
  decodeImage(b.data(), b.size(), "a.pgm", g8);
  EXPECT_EQ(info.bit_depth, 10);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(g16(i % 3, i / 3), std::lround(s[i] * 65535.0 / 1023.0)) << i;
    EXPECT_EQ(g8(i % 3, i / 3), std::lround(s[i] * 65535.0 / 1023.0) / 256) << i;
  }
  const Bytes full = pnm("P5 2 1 65535\n", {65535, 258}, true);
  decodeImage(full.data(), full.size(), "b.pgm", g16);
  EXPECT_EQ(g16(0, 0), 65535);
  EXPECT_EQ(g16(1, 0), 258);
}

TEST(PnmFile, ColourIsConvertedToLuma) {
  const Bytes b = pnm("P6 3 1 255\n", {255, 0, 0, 0, 255, 0, 10, 200, 90}, false);
  ImageU8 out;
  const ImageFileInfo info = decodeImage(b.data(), b.size(), "c.ppm", out);
  EXPECT_EQ(info.channels, 3);
  EXPECT_EQ(out(0, 0), 76);
  EXPECT_EQ(out(1, 0), 150);
  EXPECT_NEAR(out(2, 0), 0.299 * 10 + 0.587 * 200 + 0.114 * 90, 0.501);
}

std::string decodeError(const Bytes& bytes) {
  ImageU8 out;
  return inputErrorOf([&] { decodeImage(bytes.data(), bytes.size(), "bad.pgm", out); });
}

std::string decodeError(const std::string& text) {
  return decodeError(Bytes(text.begin(), text.end()));
}

TEST(PnmFileErrors, EveryMalformedHeaderAndBody) {
  EXPECT_THAT(decodeError("P2 2 2 255\n1 2 3 4\n"), HasSubstr("P2 (ASCII) is not supported"));
  EXPECT_THAT(decodeError("P3 1 1 255\n1 2 3\n"), HasSubstr("P3 (ASCII)"));
  EXPECT_THAT(decodeError("P4 8 1\n\x0f"), HasSubstr("P4 (bitmap)"));
  EXPECT_THAT(decodeError("P1 1 1\n1"), HasSubstr("P1 (bitmap)"));
  EXPECT_THAT(decodeError("P5 4"), HasSubstr("header ends before the height"));
  EXPECT_THAT(decodeError("P5 4 # comment to the end"), HasSubstr("before the height"));
  EXPECT_THAT(decodeError("P5 x 4 255\n"), HasSubstr("width is not a number"));
  EXPECT_THAT(decodeError("P5 99999999999 4 255\n"), HasSubstr("width too large"));
  EXPECT_THAT(decodeError("P5 0 4 255\n"), HasSubstr("image size 0 x 4"));
  EXPECT_THAT(decodeError("P5 40000 1 255\n"), HasSubstr("outside 1..32768"));
  EXPECT_THAT(decodeError("P5 1 1 0\n\x01"), HasSubstr("maxval 0 is outside 1..65535"));
  EXPECT_THAT(decodeError("P5 1 1 65536\n\x01\x01"), HasSubstr("maxval 65536"));
  EXPECT_THAT(decodeError("P5 1 1 255"), HasSubstr("no whitespace after the header"));
  EXPECT_THAT(decodeError("P5 2 2 255\n\x01\x02\x03"), HasSubstr("truncated data (3 of 4 bytes)"));
  EXPECT_THAT(decodeError(pnm("P6 2 1 255\n", {1, 2, 3, 4, 5}, false)),
              HasSubstr("truncated data (5 of 6 bytes)"));
  EXPECT_THAT(decodeError(pnm("P5 2 1 1000\n", {5, 1001}, true)),
              HasSubstr("sample 1001 at pixel (1, 0) exceeds maxval 1000"));
  EXPECT_THAT(decodeError("P5 1 1 100\n\x65"), HasSubstr("sample 101"));
}

}  // namespace
}  // namespace ldsm::calib
