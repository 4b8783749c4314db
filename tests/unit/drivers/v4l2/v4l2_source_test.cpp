// V4l2Source against the fake device: negotiation, the frames' pixels for every pixel format,
// kernel timestamps, exposure and gain controls, and every error path (missing, busy, not a
// capture device, unsupported format, poll timeout, unplugged mid-stream, corrupt frames).
#if defined(LDSM_HAVE_V4L2)  // the V4L2 source is built on Linux only
#include "ldsm/drivers/v4l2_source.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "fake_v4l2_kernel.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

using test::fakePixel;
using test::FakeV4l2Kernel;

V4l2Options fakeOptions() {
  V4l2Options o;
  o.device = "/dev/video7";
  o.poll_timeout_ms = 50;
  return o;
}

/// Number of pixels of `image` that differ from frame n of the fake; `tolerance` allows JPEG
/// loss.
int wrongPixels(const ImageU8& image, std::int64_t n, int tolerance = 0) {
  int wrong = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (std::abs(int(image(x, y)) - int(fakePixel(n, x, y))) > tolerance) ++wrong;
  return wrong;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const DeviceError& e) {
    return e.what();
  }
  return "(no DeviceError)";
}

void expectContains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
}

TEST(V4l2Source, StreamsGreyFramesWithKernelTimestamps) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  kernel->config().row_padding = 16;  // bytesperline > width
  {
    V4l2Source source(fakeOptions(), kernel);
    EXPECT_TRUE(kernel->lastOpenWasNonBlocking());
    EXPECT_EQ(source.mode().format, V4l2PixelFormat::Grey);
    const SourceInfo info = source.info();
    EXPECT_EQ(info.name, "v4l2:/dev/video7");
    EXPECT_EQ(info.width, 64);  // the largest size when none is requested
    EXPECT_EQ(info.height, 48);
    EXPECT_EQ(info.frame_count, -1);
    EXPECT_EQ(info.nominal_fps, 30.0);
    EXPECT_EQ(source.bufferCount(), 4);
    EXPECT_TRUE(kernel->streaming());
    EXPECT_EQ(source.offeredFormats().size(), 6u);

    Frame frame;
    for (std::int64_t n = 0; n < 10; ++n) {  // more frames than buffers: requeueing works
      ASSERT_TRUE(source.next(frame));
      EXPECT_EQ(frame.index, n);
      EXPECT_NEAR(frame.timestamp, 1000.0 + n / 30.0, 1e-6);
      ASSERT_EQ(frame.image.width(), 64);
      EXPECT_EQ(wrongPixels(frame.image, n), 0) << "frame " << n;
      EXPECT_NEAR(frame.exposure_ms, test::fakeAutoExposureMs(n), 1e-9);
    }
  }
  // The destructor stops the stream, unmaps and frees the buffers and closes the device.
  EXPECT_FALSE(kernel->streaming());
  EXPECT_EQ(kernel->mappedCount(), 0);
  EXPECT_EQ(kernel->bufferCount(), 0);
  EXPECT_EQ(kernel->openCount(), 0);
}

class V4l2SourceFormat : public ::testing::TestWithParam<V4l2PixelFormat> {};

TEST_P(V4l2SourceFormat, ConvertsToTheKnownGreyPattern) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  kernel->config().row_padding = 8;
  V4l2Options o = fakeOptions();
  o.formats = {GetParam()};
  o.width = 64;
  o.height = 48;
  V4l2Source source(o, kernel);
  EXPECT_EQ(
      kernel->currentFourCc() == V4L2_PIX_FMT_JPEG ? V4L2_PIX_FMT_MJPEG : kernel->currentFourCc(),
      v4l2FourCc(GetParam()));
  Frame frame;
  const bool jpeg = GetParam() == V4l2PixelFormat::Mjpeg;
  for (std::int64_t n = 0; n < 3; ++n) {
    ASSERT_TRUE(source.next(frame));
    ASSERT_EQ(frame.image.width(), 64);
    ASSERT_EQ(frame.image.height(), 48);
    // JPEG is lossy: a few grey levels, and the pattern's wrap-around edges a little more.
    EXPECT_LE(wrongPixels(frame.image, n, jpeg ? 12 : 0), jpeg ? 64 * 48 / 50 : 0);
  }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, V4l2SourceFormat,
                         ::testing::Values(V4l2PixelFormat::Grey, V4l2PixelFormat::Y10,
                                           V4l2PixelFormat::Y16, V4l2PixelFormat::Yuyv,
                                           V4l2PixelFormat::Mjpeg),
                         [](const auto& param_info) {
                           return std::string(toString(param_info.param));
                         });

TEST(V4l2Source, RequestedSizeRateAndBufferCount) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Options o = fakeOptions();
  o.formats = {V4l2PixelFormat::Yuyv};
  o.width = 32;
  o.height = 24;
  o.fps = 14;           // closest offered: 15
  o.buffer_count = 12;  // the fake grants at most 8
  V4l2Source source(o, kernel);
  EXPECT_EQ(source.info().width, 32);
  EXPECT_EQ(source.info().nominal_fps, 15.0);
  EXPECT_EQ(kernel->currentFps(), 15.0);
  EXPECT_EQ(source.bufferCount(), 8);
  Frame frame;
  ASSERT_TRUE(source.next(frame));
  ASSERT_TRUE(source.next(frame));
  EXPECT_NEAR(frame.timestamp, 1000.0 + 1.0 / 15.0, 1e-6);
  EXPECT_EQ(wrongPixels(frame.image, 1), 0);
}

TEST(V4l2Source, ManualExposureAndGain) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Options o = fakeOptions();
  o.exposure_ms = 5.5;
  o.gain = 40;
  V4l2Source source(o, kernel);
  EXPECT_EQ(kernel->control(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
  EXPECT_EQ(kernel->control(V4L2_CID_EXPOSURE_ABSOLUTE), 55);  // 100 us units
  EXPECT_EQ(kernel->control(V4L2_CID_EXPOSURE_AUTO_PRIORITY), 0);
  EXPECT_EQ(kernel->control(V4L2_CID_GAIN), 40);
  Frame frame;
  for (int n = 0; n < 3; ++n) {
    ASSERT_TRUE(source.next(frame));
    EXPECT_DOUBLE_EQ(frame.exposure_ms, 5.5);
  }
}

TEST(V4l2Source, LockAutoExposureKeepsTheCurrentValue) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Options o = fakeOptions();
  o.lock_auto_exposure = true;
  V4l2Source source(o, kernel);
  EXPECT_EQ(kernel->control(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
  Frame frame;
  for (int n = 0; n < 5; ++n) {
    ASSERT_TRUE(source.next(frame));
    EXPECT_DOUBLE_EQ(frame.exposure_ms, 10.0);  // the fake's value at start, frozen
  }
}

TEST(V4l2Source, ExposureOutsideTheDeviceRangeOrWithoutControls) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Options o = fakeOptions();
  o.exposure_ms = 2000;  // the fake's range is 0.1..1000 ms
  const std::string e = errorOf([&] { V4l2Source s(o, kernel); });
  expectContains(e, "/dev/video7: exposure 2000 ms is outside the device's range 0.1..1000 ms");
  EXPECT_EQ(kernel->openCount(), 0) << "the device must be closed after a failed open";

  FakeV4l2Kernel::Config c;
  c.exposure_controls = false;
  c.gain_control = false;
  auto plain = std::make_shared<FakeV4l2Kernel>(c);
  o.exposure_ms = 5;
  expectContains(errorOf([&] { V4l2Source s(o, plain); }), "no manual exposure control");
  o.exposure_ms = 0;
  o.gain = 3;
  expectContains(errorOf([&] { V4l2Source s(o, plain); }), "no gain control");
  o.gain = -1;
  V4l2Source source(o, plain);  // automatic everything: exposure unknown
  Frame frame;
  ASSERT_TRUE(source.next(frame));
  EXPECT_TRUE(std::isnan(frame.exposure_ms));
}

TEST(V4l2Source, MissingDevice) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Options o = fakeOptions();
  o.device = "/dev/video0";
  const std::string e = errorOf([&] { V4l2Source s(o, kernel); });
  expectContains(e, "/dev/video0: cannot open");
  expectContains(e, "device missing");
}

TEST(V4l2Source, BusyDevice) {
  FakeV4l2Kernel::Config c;
  c.busy = true;
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  const std::string e = errorOf([&] { V4l2Source s(fakeOptions(), kernel); });
  expectContains(e, "/dev/video7");
  expectContains(e, "device busy");
  EXPECT_EQ(kernel->openCount(), 0);
}

TEST(V4l2Source, NotACaptureDevice) {
  FakeV4l2Kernel::Config c;
  c.capture = false;
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  expectContains(errorOf([&] { V4l2Source s(fakeOptions(), kernel); }),
                 "not a video capture device");
}

TEST(V4l2Source, FormatNotSupported) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Options o = fakeOptions();
  o.width = 1920;
  o.height = 1080;
  const std::string e = errorOf([&] { V4l2Source s(o, kernel); });
  expectContains(e, "/dev/video7: format not supported");
  expectContains(e, "at 1920x1080");
  expectContains(e, "GREY (8-bit Greyscale): 64x48 @ 30 15 fps, 32x24 @ 30 15 fps");
}

TEST(V4l2Source, SpuriousWakeupsAreWaitedThrough) {
  FakeV4l2Kernel::Config c;
  c.spurious_wakeups = true;  // poll says ready, DQBUF says EAGAIN
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  V4l2Source source(fakeOptions(), kernel);
  Frame frame;
  for (std::int64_t n = 0; n < 4; ++n) {
    ASSERT_TRUE(source.next(frame));
    EXPECT_EQ(wrongPixels(frame.image, n), 0);
  }
}

TEST(V4l2Source, PollTimeoutEndsTheStream) {
  FakeV4l2Kernel::Config c;
  c.stall_after = 2;
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  V4l2Options o = fakeOptions();
  o.poll_timeout_ms = 30;
  V4l2Source source(o, kernel);
  Frame frame;
  ASSERT_TRUE(source.next(frame));
  ASSERT_TRUE(source.next(frame));
  const std::string e = errorOf([&] { source.next(frame); });
  expectContains(e, "/dev/video7: poll timeout: no frame within 30 ms");
  EXPECT_FALSE(source.next(frame)) << "after an error the source is at its end";
  EXPECT_EQ(kernel->openCount(), 0) << "the device is released at once";
  EXPECT_EQ(kernel->mappedCount(), 0);
}

TEST(V4l2Source, UnpluggedMidStream) {
  FakeV4l2Kernel::Config c;
  c.unplug_after = 3;
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  V4l2Source source(fakeOptions(), kernel);
  Frame frame;
  for (int n = 0; n < 3; ++n) ASSERT_TRUE(source.next(frame));
  EXPECT_EQ(wrongPixels(frame.image, 2), 0);
  const std::string e = errorOf([&] { source.next(frame); });
  expectContains(e, "/dev/video7");
  expectContains(e, "unplugged");
  EXPECT_FALSE(source.next(frame));
  EXPECT_FALSE(source.next(frame));
  EXPECT_EQ(kernel->openCount(), 0);
  EXPECT_EQ(kernel->mappedCount(), 0);
}

TEST(V4l2Source, CorruptAndTruncatedFramesAreSkipped) {
  FakeV4l2Kernel::Config c;
  c.corrupt_frames = {1};
  c.truncated_frames = {3};
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  V4l2Source source(fakeOptions(), kernel);
  Frame frame;
  for (std::int64_t expected : {0, 2, 4, 5}) {
    ASSERT_TRUE(source.next(frame));
    EXPECT_EQ(wrongPixels(frame.image, expected), 0) << "expected device frame " << expected;
    EXPECT_NEAR(frame.timestamp, 1000.0 + expected / 30.0, 1e-6);
  }
  EXPECT_EQ(frame.index, 3) << "indices count delivered frames";
  EXPECT_EQ(source.skippedFrames(), 2);
}

TEST(V4l2Source, EndlessCorruptFramesAreAnError) {
  FakeV4l2Kernel::Config c;
  for (int n = 0; n < 100; ++n) c.corrupt_frames.insert(n);
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  V4l2Source source(fakeOptions(), kernel);
  Frame frame;
  expectContains(errorOf([&] { source.next(frame); }), "30 bad frames in a row");
  EXPECT_FALSE(source.next(frame));
}

TEST(V4l2Source, ListFormatsWithoutStreaming) {
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  const auto formats = listV4l2Formats("/dev/video7", kernel);
  ASSERT_EQ(formats.size(), 6u);
  EXPECT_EQ(formats[3].format, V4l2PixelFormat::Yuyv);
  ASSERT_EQ(formats[3].sizes.size(), 2u);
  EXPECT_EQ(formats[3].sizes[1].max_width, 32);
  EXPECT_EQ(formats[3].sizes[0].fps, (std::vector<double>{30, 15}));
  EXPECT_FALSE(formats[5].supported);
  EXPECT_EQ(kernel->openCount(), 0);
  EXPECT_FALSE(kernel->streaming());
}

}  // namespace
}  // namespace ldsm::drivers

#endif  // LDSM_HAVE_V4L2
