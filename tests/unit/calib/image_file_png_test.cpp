// PNG decoding and encoding: round trips, every colour type and bit depth converted to grey,
// interlacing, and every way a file can be broken.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "encoded_images.h"
#include "ldsm/calib/image_file.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm::calib {
namespace {

using test::buildPng;
using test::Bytes;
using test::inputErrorOf;
using test::PngSpec;
using ::testing::HasSubstr;
using ::testing::StartsWith;

/// BT.601 luma of an RGB triple in floating point (the reference of the grey conversion).
double luma(double r, double g, double b) {
  return 0.299 * r + 0.587 * g + 0.114 * b;
}

/// A pattern covering the whole 0..max range with distinct neighbours.
std::uint16_t pattern(int x, int y, int c, std::uint32_t max) {
  return static_cast<std::uint16_t>((1237u * x + 3571u * y + 7919u * c + 17u * x * y) % (max + 1));
}

PngSpec patternSpec(int width, int height, int bit_depth, int color_type) {
  PngSpec s;
  s.width = width;
  s.height = height;
  s.bit_depth = bit_depth;
  s.color_type = color_type;
  const int channels = test::pngChannels(color_type);
  const std::uint32_t max = (1u << bit_depth) - 1;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c) s.samples.push_back(pattern(x, y, c, max));
  return s;
}

ImageU8 decode8(const Bytes& png, ImageFileInfo* info = nullptr) {
  ImageU8 out;
  const ImageFileInfo i = decodeImage(png.data(), png.size(), "test.png", out);
  if (info) *info = i;
  return out;
}

ImageU16 decode16(const Bytes& png) {
  ImageU16 out;
  decodeImage(png.data(), png.size(), "test.png", out);
  return out;
}

TEST(PngFile, EightBitGreyRoundTripIsExact) {
  ImageU8 image(37, 23);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      image(x, y) = static_cast<std::uint8_t>(pattern(x, y, 0, 255));
  for (int level : {0, 3, 9}) {
    const Bytes png = encodePng(image.view(), PngWriteOptions{level});
    ImageFileInfo info;
    const ImageU8 back = decode8(png, &info);
    EXPECT_EQ(info.format, ImageFileFormat::Png);
    EXPECT_EQ(info.channels, 1);
    EXPECT_EQ(info.bit_depth, 8);
    ASSERT_EQ(back.width(), 37);
    ASSERT_EQ(back.height(), 23);
    for (int y = 0; y < 23; ++y)
      for (int x = 0; x < 37; ++x) ASSERT_EQ(back(x, y), image(x, y)) << x << "," << y;
  }
}

TEST(PngFile, SixteenBitGreyRoundTripIsExactAndReducesToItsHighByte) {
  ImageU16 image(19, 11);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) image(x, y) = pattern(x, y, 0, 65535);
  image(0, 0) = 0;
  image(1, 0) = 65535;
  image(2, 0) = 255;    // -> 0
  image(3, 0) = 256;    // -> 1
  image(4, 0) = 65280;  // -> 255
  const Bytes png = encodePng(image.view());
  ImageU16 back16 = decode16(png);
  ImageFileInfo info;
  const ImageU8 back8 = decode8(png, &info);
  EXPECT_EQ(info.bit_depth, 16);
  ASSERT_EQ(back16.width(), 19);
  ASSERT_EQ(back8.height(), 11);
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 19; ++x) {
      ASSERT_EQ(back16(x, y), image(x, y));
      ASSERT_EQ(back8(x, y), std::floor(image(x, y) / 256.0)) << image(x, y);
    }
}

TEST(PngFile, EightBitGreyReadAsSixteenBitsIsScaledByFullRange) {
  PngSpec s = patternSpec(9, 7, 8, 0);
  s.samples[0] = 255;
  s.samples[1] = 0;
  const ImageU16 back = decode16(buildPng(s));
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 9; ++x) ASSERT_EQ(back(x, y), s.samples[y * 9 + x] * 257);
  EXPECT_EQ(back(0, 0), 65535);
}

TEST(PngFile, RgbIsConvertedToLuma) {
  PngSpec s = patternSpec(31, 17, 8, 2);
  const std::uint16_t pure[5][3] = {
      {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}, {0, 0, 0}};
  for (int i = 0; i < 5; ++i)
    for (int c = 0; c < 3; ++c) s.samples[i * 3 + c] = pure[i][c];
  const ImageU8 grey = decode8(buildPng(s));
  EXPECT_EQ(grey(0, 0), 76);   // 0.299 * 255 = 76.2
  EXPECT_EQ(grey(1, 0), 150);  // 0.587 * 255 = 149.7
  EXPECT_EQ(grey(2, 0), 29);   // 0.114 * 255 = 29.1
  EXPECT_EQ(grey(3, 0), 255);
  EXPECT_EQ(grey(4, 0), 0);
  for (int y = 0; y < 17; ++y)
    for (int x = 0; x < 31; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * 31 + x) * 3;
      const double ref = luma(s.samples[i], s.samples[i + 1], s.samples[i + 2]);
      ASSERT_NEAR(grey(x, y), ref, 0.5 + 1e-3) << x << "," << y;
    }
}

TEST(PngFile, SixteenBitRgbToGreyAtBothDepths) {
  const PngSpec s = patternSpec(13, 9, 16, 2);
  const Bytes png = buildPng(s);
  const ImageU16 g16 = decode16(png);
  const ImageU8 g8 = decode8(png);
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 13; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * 13 + x) * 3;
      const double ref = luma(s.samples[i], s.samples[i + 1], s.samples[i + 2]);
      ASSERT_NEAR(g16(x, y), ref, 1.5);
      ASSERT_NEAR(g8(x, y), std::floor(ref / 256.0), 1.0);
      ASSERT_EQ(g8(x, y), g16(x, y) >> 8);
    }
}

TEST(PngFile, AlphaIsIgnored) {
  PngSpec ga = patternSpec(8, 6, 8, 4);  // grey + alpha
  PngSpec rgba = patternSpec(8, 6, 8, 6);
  ImageFileInfo info;
  const ImageU8 a = decode8(buildPng(ga), &info);
  EXPECT_EQ(info.channels, 2);
  const ImageU8 b = decode8(buildPng(rgba), &info);
  EXPECT_EQ(info.channels, 4);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      EXPECT_EQ(a(x, y), ga.samples[(y * 8 + x) * 2]);
      const std::size_t i = (static_cast<std::size_t>(y) * 8 + x) * 4;
      EXPECT_NEAR(b(x, y), luma(rgba.samples[i], rgba.samples[i + 1], rgba.samples[i + 2]), 0.501);
    }
}

TEST(PngFile, PaletteIsExpandedThenConvertedEvenWithTransparency) {
  for (const bool with_trns : {false, true}) {
    PngSpec s;
    s.width = 10;
    s.height = 5;
    s.bit_depth = 4;
    s.color_type = 3;
    for (int i = 0; i < 16; ++i)
      s.palette.push_back({static_cast<std::uint8_t>(16 * i),
                           static_cast<std::uint8_t>(255 - 9 * i),
                           static_cast<std::uint8_t>(7 * i)});
    if (with_trns) s.transparency = {0, 128, 255};
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 10; ++x)
        s.samples.push_back(static_cast<std::uint16_t>((x + 3 * y) % 16));
    ImageFileInfo info;
    const ImageU8 grey = decode8(buildPng(s), &info);
    EXPECT_EQ(info.channels, 3);
    EXPECT_EQ(info.bit_depth, 4);
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 10; ++x) {
        const auto& c = s.palette[s.samples[y * 10 + x]];
        ASSERT_NEAR(grey(x, y), luma(c[0], c[1], c[2]), 0.501) << with_trns;
      }
  }
}

TEST(PngFile, LowBitDepthGreyIsScaledToFullRange) {
  for (int depth : {1, 2, 4}) {
    const PngSpec s = patternSpec(13, 5, depth, 0);  // odd width: padded last byte
    const int max = (1 << depth) - 1;
    const ImageU8 grey = decode8(buildPng(s));
    ASSERT_EQ(grey.width(), 13);
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 13; ++x)
        ASSERT_EQ(grey(x, y), s.samples[y * 13 + x] * 255 / max) << "depth " << depth;
  }
}

TEST(PngFile, InterlacedImagesDecodeLikeProgressiveOnes) {
  for (const int type : {0, 2}) {
    for (const int depth : {8, 16}) {
      PngSpec s = patternSpec(21, 13, depth, type);
      const ImageU16 plain = decode16(buildPng(s));
      const ImageU8 plain8 = decode8(buildPng(s));
      s.interlaced = true;
      const ImageU16 inter = decode16(buildPng(s));
      const ImageU8 inter8 = decode8(buildPng(s));
      for (int y = 0; y < 13; ++y)
        for (int x = 0; x < 21; ++x) {
          ASSERT_EQ(inter(x, y), plain(x, y)) << type << "/" << depth;
          ASSERT_EQ(inter8(x, y), plain8(x, y)) << type << "/" << depth;
        }
    }
  }
  // A tiny interlaced image has empty passes.
  PngSpec tiny = patternSpec(1, 1, 8, 0);
  tiny.interlaced = true;
  EXPECT_EQ(decode8(buildPng(tiny))(0, 0), tiny.samples[0]);
}

TEST(PngFile, RgbEncodingKeepsTheColours) {
  Image<Rgb8> image(6, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      image(x, y) = Rgb8{static_cast<std::uint8_t>(40 * x), static_cast<std::uint8_t>(60 * y),
                         static_cast<std::uint8_t>(255 - 30 * x)};
  const Bytes png = encodePng(image.view());
  // IHDR: 8-bit RGB.
  const std::size_t ihdr = test::pngChunkData(png, "IHDR");
  EXPECT_EQ(png[ihdr + 8], 8);
  EXPECT_EQ(png[ihdr + 9], 2);
  ImageFileInfo info;
  const ImageU8 grey = decode8(png, &info);
  EXPECT_EQ(info.channels, 3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      EXPECT_NEAR(grey(x, y), luma(image(x, y).r, image(x, y).g, image(x, y).b), 0.501);
}

TEST(PngFile, EncodesViewsWithAStride) {
  ImageU8 big(10, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 10; ++x) big(x, y) = static_cast<std::uint8_t>(10 * y + x);
  const ImageView<const std::uint8_t> window(big.data() + 2 * 10 + 3, 4, 5, 10);
  const ImageU8 back = decode8(encodePng(window));
  ASSERT_EQ(back.width(), 4);
  ASSERT_EQ(back.height(), 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_EQ(back(x, y), big(x + 3, y + 2));
}

TEST(PngFile, EncodingRejectsEmptyImagesAndBadLevels) {
  EXPECT_THAT(inputErrorOf([] { encodePng(ImageView<const std::uint8_t>()); }), HasSubstr("empty"));
  ImageU16 one(1, 1, 7);
  EXPECT_THAT(inputErrorOf([&] { encodePng(one.view(), PngWriteOptions{10}); }),
              HasSubstr("compression level 10"));
  EXPECT_THAT(inputErrorOf([&] { encodePng(one.view(), PngWriteOptions{-1}); }),
              HasSubstr("compression level -1"));
}

// ---- broken files ----------------------------------------------------------------------------

std::string decodeError(const Bytes& bytes) {
  ImageU8 out;
  return inputErrorOf([&] { decodeImage(bytes.data(), bytes.size(), "bad.png", out); });
}

TEST(PngFileErrors, NamesTheDataAndSaysWhatIsWrong) {
  EXPECT_EQ(decodeError({}), "bad.png: cannot decode image: the file is empty");
  const std::string text = "this is not an image";
  EXPECT_EQ(decodeError(Bytes(text.begin(), text.end())),
            "bad.png: cannot decode image: not a PNG, JPEG or PGM/PPM file");
  EXPECT_THAT(decodeError({'B', 'M', 0, 0, 0, 0}), HasSubstr("BMP images are not supported"));
  EXPECT_THAT(decodeError({'I', 'I', '*', 0, 8, 0}), HasSubstr("TIFF images are not supported"));
  EXPECT_THAT(decodeError({'G', 'I', 'F', '8', '9', 'a'}), HasSubstr("GIF"));
  EXPECT_THAT(decodeError({'R', 'I', 'F', 'F', 0, 0, 0, 0, 'W', 'E', 'B', 'P'}), HasSubstr("WebP"));
}

TEST(PngFileErrors, TruncatedAnywhere) {
  const Bytes good = buildPng(patternSpec(40, 30, 8, 2));
  const std::size_t idat = test::pngChunkData(good, "IDAT");
  // Inside IHDR, just after the IDAT header, in the middle of IDAT, just before IEND.
  for (const std::size_t cut :
       {std::size_t{8}, std::size_t{20}, idat, idat + 40, good.size() - 12, good.size() - 1}) {
    const Bytes bad(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_THAT(decodeError(bad), StartsWith("bad.png: cannot decode image: PNG: ")) << cut;
  }
  const Bytes bad(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(idat) + 40);
  EXPECT_THAT(decodeError(bad), HasSubstr("truncated"));
}

TEST(PngFileErrors, CorruptChunks) {
  const Bytes good = buildPng(patternSpec(40, 30, 8, 0));
  Bytes bad_ihdr_crc = good;
  bad_ihdr_crc[8 + 8 + 13] ^= 0x01;  // first byte of the IHDR CRC
  EXPECT_THAT(decodeError(bad_ihdr_crc), HasSubstr("CRC"));
  // IDAT data no longer matching its CRC: zlib may trip over the data before the CRC is checked.
  Bytes bad_idat = good;
  bad_idat[test::pngChunkData(good, "IDAT") + 10] ^= 0x5a;
  EXPECT_THAT(decodeError(bad_idat), StartsWith("bad.png: cannot decode image: PNG: "));
  Bytes bad_idat_crc = good;
  bad_idat_crc[test::pngChunkData(good, "IEND") - 8 - 4] ^= 0x01;  // last byte of IDAT's CRC
  EXPECT_THAT(decodeError(bad_idat_crc), HasSubstr("CRC"));
}

TEST(PngFileErrors, CorruptCompressedDataWithAValidCrc) {
  Bytes png = buildPng(patternSpec(40, 30, 8, 0));
  test::patchPngChunk(png, "IDAT", 1, 0x00);  // zlib header check bits no longer match
  EXPECT_THAT(decodeError(png), StartsWith("bad.png: cannot decode image: PNG: "));
  Bytes garbage = buildPng(patternSpec(40, 30, 8, 0));
  for (std::size_t i = 2; i < 30; ++i) test::patchPngChunk(garbage, "IDAT", i, 0xff);
  EXPECT_THAT(decodeError(garbage), StartsWith("bad.png: cannot decode image: PNG: "));
}

TEST(PngFileErrors, InvalidHeaders) {
  // IHDR data: width (4 bytes), height (4), bit depth, colour type, compression, filter, interlace
  const Bytes good = buildPng(patternSpec(4, 4, 8, 0));
  const std::pair<std::size_t, unsigned char> patches[] = {
      {3, 0},   // width 0
      {8, 3},   // bit depth 3
      {9, 5},   // colour type 5
      {10, 1},  // compression method 1
      {12, 2},  // interlace method 2
  };
  for (const auto& [offset, value] : patches) {
    Bytes bad = good;
    test::patchPngChunk(bad, "IHDR", offset, value);
    EXPECT_THAT(decodeError(bad), StartsWith("bad.png: cannot decode image: PNG: ")) << offset;
  }
  Bytes rgb4 = buildPng(patternSpec(4, 4, 4, 0));
  test::patchPngChunk(rgb4, "IHDR", 9, 2);  // RGB must be 8 or 16 bits
  EXPECT_THAT(decodeError(rgb4), HasSubstr("PNG: "));
  PngSpec no_palette = patternSpec(4, 4, 8, 3);  // palette image without PLTE
  EXPECT_THAT(decodeError(buildPng(no_palette)), HasSubstr("PNG: "));
}

TEST(PngFileErrors, AbsurdSizesAreRefusedBeforeAllocating) {
  PngSpec huge;
  huge.width = kMaxImageDimension + 1;
  huge.height = 1;
  huge.samples.assign(static_cast<std::size_t>(huge.width), 0);
  EXPECT_THAT(decodeError(buildPng(huge)), HasSubstr("PNG: "));
  PngSpec tall;
  tall.width = 1;
  tall.height = kMaxImageDimension + 1;
  tall.samples.assign(static_cast<std::size_t>(tall.height), 0);
  EXPECT_THAT(decodeError(buildPng(tall)), HasSubstr("PNG: "));
}

}  // namespace
}  // namespace ldsm::calib
