// Pixel format names, option validation and the choice of format, size and rate.
#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <cmath>
#include <string>

#include "ldsm/drivers/v4l2_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

V4l2FrameSize discrete(int w, int h, std::vector<double> fps) {
  V4l2FrameSize s;
  s.min_width = s.max_width = w;
  s.min_height = s.max_height = h;
  s.fps = std::move(fps);
  return s;
}

V4l2FormatDescription format(V4l2PixelFormat f, std::vector<V4l2FrameSize> sizes) {
  V4l2FormatDescription d;
  d.fourcc = v4l2FourCc(f);
  d.description = toString(f);
  d.supported = true;
  d.format = f;
  d.sizes = std::move(sizes);
  return d;
}

std::vector<V4l2FormatDescription> webcam() {
  V4l2FormatDescription rgb;
  rgb.fourcc = V4L2_PIX_FMT_RGB24;
  rgb.description = "RGB";
  rgb.sizes = {discrete(1920, 1080, {30})};
  return {
      rgb, format(V4l2PixelFormat::Yuyv, {discrete(640, 480, {30, 15}), discrete(1280, 720, {10})}),
      format(V4l2PixelFormat::Mjpeg, {discrete(640, 480, {30}), discrete(1280, 720, {60, 30})})};
}

TEST(V4l2PixelFormat, NamesAndFourCcsRoundTrip) {
  for (V4l2PixelFormat f : {V4l2PixelFormat::Grey, V4l2PixelFormat::Y10, V4l2PixelFormat::Y16,
                            V4l2PixelFormat::Yuyv, V4l2PixelFormat::Mjpeg})
    EXPECT_EQ(parseV4l2PixelFormat(toString(f)), f);
  EXPECT_EQ(parseV4l2PixelFormat("gray"), V4l2PixelFormat::Grey);
  EXPECT_EQ(parseV4l2PixelFormat("mjpg"), V4l2PixelFormat::Mjpeg);
  EXPECT_THROW(parseV4l2PixelFormat("RGB3"), ConfigError);
  EXPECT_EQ(v4l2FourCc(V4l2PixelFormat::Yuyv), V4L2_PIX_FMT_YUYV);
  EXPECT_EQ(v4l2FourCc(V4l2PixelFormat::Y10), V4L2_PIX_FMT_Y10);
  EXPECT_EQ(fourCcToString(V4L2_PIX_FMT_YUYV), "YUYV");
  EXPECT_EQ(fourCcToString(V4L2_PIX_FMT_Y10), "Y10 ");
  EXPECT_EQ(fourCcToString(0x01020304u), "????");
}

TEST(V4l2Options, ValidationNamesTheOption) {
  V4l2Options o;
  EXPECT_NO_THROW(validate(o));
  auto expectBad = [](V4l2Options bad, const std::string& word) {
    try {
      validate(bad);
      ADD_FAILURE() << "accepted bad " << word;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  o = {};
  o.width = 640;  // height missing
  expectBad(o, "width and height");
  o = {};
  o.buffer_count = 1;
  expectBad(o, "buffer_count");
  o = {};
  o.fps = -5;
  expectBad(o, "fps");
  o = {};
  o.exposure_ms = std::nan("");
  expectBad(o, "exposure_ms");
  o = {};
  o.device = "";
  expectBad(o, "device");
  o = {};
  o.formats.clear();
  expectBad(o, "formats");
  o = {};
  o.poll_timeout_ms = 0;
  expectBad(o, "poll_timeout_ms");
}

TEST(ChooseV4l2Mode, FirstPreferredFormatAtTheRequestedSize) {
  V4l2Options o;
  o.width = 1280;
  o.height = 720;
  o.fps = 25;
  const V4l2Mode m = chooseV4l2Mode(webcam(), o);  // GREY, Y16, Y10 absent; YUYV has 1280x720
  EXPECT_EQ(m.format, V4l2PixelFormat::Yuyv);
  EXPECT_EQ(m.width, 1280);
  EXPECT_EQ(m.height, 720);
  EXPECT_EQ(m.fps, 10.0);  // the only rate offered there
}

TEST(ChooseV4l2Mode, PreferenceOrderAndClosestRate) {
  V4l2Options o;
  o.formats = {V4l2PixelFormat::Mjpeg, V4l2PixelFormat::Yuyv};
  o.width = 1280;
  o.height = 720;
  o.fps = 50;
  V4l2Mode m = chooseV4l2Mode(webcam(), o);
  EXPECT_EQ(m.format, V4l2PixelFormat::Mjpeg);
  EXPECT_EQ(m.fps, 60.0);
  o.fps = 0;  // the device's own rate: none requested
  m = chooseV4l2Mode(webcam(), o);
  EXPECT_EQ(m.fps, 0.0);
}

TEST(ChooseV4l2Mode, LargestSizeWhenNoneRequested) {
  V4l2Options o;
  o.formats = {V4l2PixelFormat::Yuyv};
  const V4l2Mode m = chooseV4l2Mode(webcam(), o);
  EXPECT_EQ(m.width, 1280);
  EXPECT_EQ(m.height, 720);
}

TEST(ChooseV4l2Mode, StepwiseRangesAndRateRanges) {
  V4l2FrameSize range;
  range.min_width = 16;
  range.max_width = 1920;
  range.step_width = 16;
  range.min_height = 16;
  range.max_height = 1080;
  range.step_height = 8;
  range.min_fps = 1;
  range.max_fps = 60;
  const std::vector<V4l2FormatDescription> offered = {format(V4l2PixelFormat::Grey, {range})};
  V4l2Options o;
  o.width = 640;
  o.height = 480;
  o.fps = 90;
  V4l2Mode m = chooseV4l2Mode(offered, o);
  EXPECT_EQ(m.width, 640);
  EXPECT_EQ(m.fps, 60.0);  // clamped into the range
  o.width = 641;           // not on the 16-pixel step
  EXPECT_THROW(chooseV4l2Mode(offered, o), DeviceError);
}

TEST(ChooseV4l2Mode, UnsupportedRequestListsWhatTheDeviceOffers) {
  V4l2Options o;
  o.device = "/dev/video3";
  o.formats = {V4l2PixelFormat::Grey, V4l2PixelFormat::Y16};
  try {
    chooseV4l2Mode(webcam(), o);
    FAIL() << "no GREY or Y16 offered";
  } catch (const DeviceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/dev/video3"), std::string::npos) << what;
    EXPECT_NE(what.find("format not supported"), std::string::npos) << what;
    EXPECT_NE(what.find("GREY or Y16"), std::string::npos) << what;
    EXPECT_NE(what.find("YUYV (YUYV): 640x480 @ 30 15 fps, 1280x720 @ 10 fps"), std::string::npos)
        << what;
    EXPECT_NE(what.find("RGB3 (RGB) [not supported by ldsm]"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace ldsm::drivers
