// Image files on disk and buffer reuse: readImage/writePng, the errors of missing or unreadable
// files, and decoding into a preallocated image without reallocating.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "encoded_images.h"
#include "ldsm/calib/image_file.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm::calib {
namespace {

using test::Bytes;
using test::inputErrorOf;
using ::testing::HasSubstr;
using ::testing::StartsWith;

ImageU8 ramp(int w, int h, int seed) {
  ImageU8 image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image(x, y) = static_cast<std::uint8_t>(seed + 3 * x + 5 * y);
  return image;
}

void expectSame(const ImageU8& a, const ImageU8& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) ASSERT_EQ(a(x, y), b(x, y)) << x << "," << y;
}

TEST(ImageFileIo, WriteThenReadFiles) {
  const std::string dir = test::scratchDir("imageio/files");
  const ImageU8 grey = ramp(30, 20, 7);
  writePng(dir + "/grey.png", grey.view());
  ImageU8 back;
  const ImageFileInfo info = readImage(dir + "/grey.png", back);
  EXPECT_EQ(info.format, ImageFileFormat::Png);
  expectSame(grey, back);

  ImageU16 deep(5, 4, 40000);
  writePng(dir + "/deep.png", deep.view());
  ImageU16 deep_back;
  readImage(dir + "/deep.png", deep_back);
  EXPECT_EQ(deep_back(4, 3), 40000);

  Image<Rgb8> colour(3, 2, Rgb8{255, 255, 255});
  writePng(dir + "/colour.png", colour.view());
  ImageU8 colour_back;
  EXPECT_EQ(readImage(dir + "/colour.png", colour_back).channels, 3);
  EXPECT_EQ(colour_back(2, 1), 255);

  // The bytes on disk are the encoder's.
  Bytes on_disk;
  readFileBytes(dir + "/grey.png", on_disk);
  EXPECT_EQ(on_disk, encodePng(grey.view()));
}

TEST(ImageFileIo, FileErrorsNameTheFile) {
  const std::string dir = test::scratchDir("imageio/file_errors");
  ImageU8 out;
  EXPECT_THAT(inputErrorOf([&] { readImage(dir + "/absent.png", out); }),
              StartsWith(dir + "/absent.png: cannot open"));
  EXPECT_THAT(inputErrorOf([&] { readImage(dir, out); }), StartsWith(dir + ": "));
  std::ofstream(dir + "/empty.png").close();
  EXPECT_EQ(inputErrorOf([&] { readImage(dir + "/empty.png", out); }),
            dir + "/empty.png: cannot decode image: the file is empty");
  std::ofstream(dir + "/text.jpg") << "hello";
  EXPECT_EQ(inputErrorOf([&] { readImage(dir + "/text.jpg", out); }),
            dir + "/text.jpg: cannot decode image: not a PNG, JPEG or PGM/PPM file");
  const ImageU8 grey = ramp(4, 4, 0);
  try {
    writePng(dir + "/no/such/folder/x.png", grey.view());
    ADD_FAILURE() << "writing into a missing folder succeeded";
  } catch (const InputError& e) {
    ADD_FAILURE() << "an output failure is not an input error: " << e.what();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), StartsWith(dir + "/no/such/folder/x.png: cannot open for writing"));
  }
}

TEST(ImageFileIo, DecodingReusesTheOutputBuffer) {
  const Bytes big = encodePng(ramp(64, 48, 1).view());
  const Bytes same = encodePng(ramp(64, 48, 9).view());
  const Bytes small = encodePng(ramp(16, 8, 3).view());
  const std::string pgm_header = "P5 64 48 255\n";
  Bytes pgm(pgm_header.begin(), pgm_header.end());
  pgm.resize(pgm.size() + 64 * 48, 77);
  const Bytes jpeg = test::encodeJpeg(std::vector<std::uint8_t>(64 * 48, 77), 64, 48, 1, 1, 90);

  ImageU8 out;
  decodeImage(big.data(), big.size(), "big", out);
  const std::uint8_t* buffer = out.data();
  const std::size_t capacity = out.capacity();
  for (const Bytes* b : std::initializer_list<const Bytes*>{&same, &small, &pgm, &jpeg, &big}) {
    decodeImage(b->data(), b->size(), "again", out);
    EXPECT_EQ(out.data(), buffer);
    EXPECT_EQ(out.capacity(), capacity);
  }
  expectSame(out, ramp(64, 48, 1));
  decodeImage(small.data(), small.size(), "small", out);
  expectSame(out, ramp(16, 8, 3));

  // 16-bit output too, including a conversion from 8 bits.
  ImageU16 deep;
  decodeImage(big.data(), big.size(), "big", deep);
  const std::uint16_t* deep_buffer = deep.data();
  decodeImage(jpeg.data(), jpeg.size(), "jpeg", deep);
  decodeImage(small.data(), small.size(), "small", deep);
  EXPECT_EQ(deep.data(), deep_buffer);
}

TEST(ImageFileIo, DetectsFormatsFromTheirSignature) {
  const Bytes png = encodePng(ramp(2, 2, 0).view());
  EXPECT_EQ(detectImageFileFormat(png.data(), png.size()), ImageFileFormat::Png);
  const unsigned char jpeg[] = {0xff, 0xd8, 0xff, 0xe0};
  EXPECT_EQ(detectImageFileFormat(jpeg, sizeof jpeg), ImageFileFormat::Jpeg);
  const unsigned char pgm[] = {'P', '5', '\n'};
  EXPECT_EQ(detectImageFileFormat(pgm, sizeof pgm), ImageFileFormat::Pnm);
  EXPECT_EQ(detectImageFileFormat(png.data(), 7), ImageFileFormat::Unknown);
  EXPECT_EQ(detectImageFileFormat(nullptr, 0), ImageFileFormat::Unknown);
  EXPECT_STREQ(toString(ImageFileFormat::Jpeg), "JPEG");
}

}  // namespace
}  // namespace ldsm::calib
