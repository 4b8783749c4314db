// The libcamera source without a camera: pixel format names and codes, conversion of every
// supported layout to grey against a known pattern, the option -> control mapping, and the
// error when no camera is present (this machine has none).
#include "ldsm/drivers/libcamera_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

constexpr int kW = 10;  // not a multiple of 4: CSI-2 packing has a partial last group
constexpr int kH = 3;

std::uint8_t pattern(int x, int y) {
  return static_cast<std::uint8_t>(17 * x + 61 * y + 5);
}

/// Plane 0 of a kW x kH frame in `format`, rows `stride` bytes apart (padding 0xEE), with
/// pattern() as the 8 most significant bits and other bits set to noise.
std::vector<unsigned char> makePlane(LibcameraPixelFormat format, int stride) {
  std::vector<unsigned char> d(static_cast<std::size_t>(stride) * kH, 0xEE);
  for (int y = 0; y < kH; ++y) {
    unsigned char* row = d.data() + static_cast<std::size_t>(y) * stride;
    for (int x = 0; x < kW; ++x) {
      const unsigned g = pattern(x, y);
      const unsigned noise = static_cast<unsigned>(x * 7 + y);
      switch (format) {
        case LibcameraPixelFormat::R10:
        case LibcameraPixelFormat::R12: {
          const int low = format == LibcameraPixelFormat::R10 ? 2 : 4;
          const unsigned v = (g << low) | (noise & ((1u << low) - 1));
          row[2 * x] = static_cast<unsigned char>(v & 0xFF);
          row[2 * x + 1] = static_cast<unsigned char>(v >> 8);
          break;
        }
        case LibcameraPixelFormat::R10Csi2p:
          row[(x / 4) * 5 + x % 4] = static_cast<unsigned char>(g);
          row[(x / 4) * 5 + 4] = static_cast<unsigned char>(noise);  // the LSB byte
          break;
        case LibcameraPixelFormat::R12Csi2p:
          row[(x / 2) * 3 + x % 2] = static_cast<unsigned char>(g);
          row[(x / 2) * 3 + 2] = static_cast<unsigned char>(noise);
          break;
        case LibcameraPixelFormat::Yuyv:
          row[2 * x] = static_cast<unsigned char>(g);
          row[2 * x + 1] = 0x80;
          break;
        case LibcameraPixelFormat::Uyvy:
          row[2 * x + 1] = static_cast<unsigned char>(g);
          row[2 * x] = 0x80;
          break;
        default:  // R8, NV12, NV21, YUV420 plane 0
          row[x] = static_cast<unsigned char>(g);
      }
    }
  }
  return d;
}

int minimumStride(LibcameraPixelFormat f) {
  switch (f) {
    case LibcameraPixelFormat::R10:
    case LibcameraPixelFormat::R12:
    case LibcameraPixelFormat::Yuyv:
    case LibcameraPixelFormat::Uyvy:
      return 2 * kW;
    case LibcameraPixelFormat::R10Csi2p:
      return (kW + 3) / 4 * 5;
    case LibcameraPixelFormat::R12Csi2p:
      return (kW + 1) / 2 * 3;
    default:
      return kW;
  }
}

const std::vector<LibcameraPixelFormat> kAll = {
    LibcameraPixelFormat::R8,       LibcameraPixelFormat::R10,      LibcameraPixelFormat::R12,
    LibcameraPixelFormat::R10Csi2p, LibcameraPixelFormat::R12Csi2p, LibcameraPixelFormat::Yuyv,
    LibcameraPixelFormat::Uyvy,     LibcameraPixelFormat::Nv12,     LibcameraPixelFormat::Nv21,
    LibcameraPixelFormat::Yuv420};

TEST(LibcameraFormat, NamesAndCodesRoundTrip) {
  for (LibcameraPixelFormat f : kAll) {
    EXPECT_EQ(parseLibcameraPixelFormat(toString(f)), f);
    const LibcameraFourCc code = libcameraFourCc(f);
    EXPECT_EQ(classifyLibcameraFormat(code.fourcc, code.modifier), f) << toString(f);
  }
  EXPECT_EQ(parseLibcameraPixelFormat("r10_csi2p"), LibcameraPixelFormat::R10Csi2p);
  EXPECT_THROW(parseLibcameraPixelFormat("SBGGR10"), ConfigError);
  // libcamera's formats.h: R8 = fourcc 'R8  ', R10_CSI2P = 'R10 ' with modifier MIPI (11) / 1.
  EXPECT_EQ(libcameraFourCc(LibcameraPixelFormat::R8).fourcc, 0x20203852u);
  EXPECT_EQ(libcameraFourCc(LibcameraPixelFormat::R10Csi2p).fourcc, 0x20303152u);
  EXPECT_EQ(libcameraFourCc(LibcameraPixelFormat::R10Csi2p).modifier, 0x0b00000000000001ull);
  EXPECT_EQ(libcameraFourCc(LibcameraPixelFormat::Yuv420).fourcc, 0x32315559u);  // 'YU12'
  // A Bayer format (SBGGR10 = 'BG10') is not converted.
  EXPECT_EQ(classifyLibcameraFormat(0x30314742u, 0), LibcameraPixelFormat::Unsupported);
}

TEST(LibcameraFormat, EveryLayoutConvertsToThePatternWithAndWithoutPadding) {
  for (LibcameraPixelFormat f : kAll) {
    for (int padding : {0, 6}) {
      const int stride = minimumStride(f) + padding;
      const std::vector<unsigned char> plane = makePlane(f, stride);
      ImageU8 out;
      std::string problem;
      ASSERT_TRUE(
          convertLibcameraPlane(f, plane.data(), plane.size(), kW, kH, stride, out, problem))
          << toString(f) << ": " << problem;
      ASSERT_EQ(out.width(), kW);
      ASSERT_EQ(out.height(), kH);
      int wrong = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          if (out(x, y) != pattern(x, y)) ++wrong;
      EXPECT_EQ(wrong, 0) << toString(f) << " padding " << padding;
    }
  }
}

TEST(LibcameraFormat, TruncatedOrUnsupportedFramesAreRefused) {
  const std::vector<unsigned char> plane = makePlane(LibcameraPixelFormat::R10, 2 * kW);
  ImageU8 out;
  std::string problem;
  EXPECT_FALSE(convertLibcameraPlane(LibcameraPixelFormat::R10, plane.data(), plane.size() - 1, kW,
                                     kH, 2 * kW, out, problem));
  EXPECT_NE(problem.find("truncated"), std::string::npos) << problem;
  EXPECT_FALSE(convertLibcameraPlane(LibcameraPixelFormat::Unsupported, plane.data(), plane.size(),
                                     kW, kH, 2 * kW, out, problem));
}

TEST(LibcameraControls, MappingFromOptions) {
  LibcameraOptions o;
  LibcameraControls c = mapLibcameraControls(o);
  EXPECT_TRUE(c.ae_enable);
  EXPECT_EQ(c.exposure_time_us, 0);
  EXPECT_EQ(c.analogue_gain, 0.0f);
  EXPECT_EQ(c.frame_duration_us, 0);

  o.exposure_ms = 8.25;
  o.fps = 30;
  c = mapLibcameraControls(o);
  EXPECT_FALSE(c.ae_enable);
  EXPECT_EQ(c.exposure_time_us, 8250);
  EXPECT_EQ(c.frame_duration_us, 33333);

  o = {};
  o.analogue_gain = 2.5;
  c = mapLibcameraControls(o);
  EXPECT_FALSE(c.ae_enable);
  EXPECT_FLOAT_EQ(c.analogue_gain, 2.5f);

  o = {};
  o.lock_auto_exposure = true;
  EXPECT_FALSE(mapLibcameraControls(o).ae_enable);

  EXPECT_DOUBLE_EQ(exposureMsFromLibcamera(12500), 12.5);
  EXPECT_TRUE(std::isnan(exposureMsFromLibcamera(0)));
}

TEST(LibcameraControls, OptionValidation) {
  LibcameraOptions o;
  EXPECT_NO_THROW(validate(o));
  o.analogue_gain = 0.5;  // gains are multipliers >= 1
  EXPECT_THROW(validate(o), ConfigError);
  o = {};
  o.width = 640;
  EXPECT_THROW(validate(o), ConfigError);
  o = {};
  o.buffer_count = 0;
  EXPECT_THROW(validate(o), ConfigError);
  o = {};
  o.formats = {LibcameraPixelFormat::Unsupported};
  EXPECT_THROW(validate(o), ConfigError);
  o = {};
  o.timeout_ms = 0;
  EXPECT_THROW(openLibcameraSource(o), ConfigError);  // options checked before any camera
}

TEST(LibcameraSource, NoCameraIsAClearDeviceError) {
  if (!libcameraAvailable()) {
    // Built without libcamera: opening says so.
    try {
      openLibcameraSource({});
      FAIL() << "opened a libcamera camera without libcamera";
    } catch (const DeviceError& e) {
      EXPECT_NE(std::string(e.what()).find("libcamera"), std::string::npos) << e.what();
    }
    GTEST_SKIP() << "ldsm built without the libcamera plugin";
  }
  const std::vector<std::string> cameras = listLibcameraCameras();
  if (!cameras.empty()) GTEST_SKIP() << "a camera is present (" << cameras.front() << ")";
  try {
    openLibcameraSource({});
    FAIL() << "opened a camera that does not exist";
  } catch (const DeviceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("libcamera: no camera found"), std::string::npos) << what;
    EXPECT_NE(what.find("V4L2"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace ldsm::drivers
