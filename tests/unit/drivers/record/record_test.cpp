// Recording a camera (the fake V4L2 device) in the TUM-Mono layout and reading it back with
// openDataset(), as `ldsm record` and `ldsm run` do; an unplugged camera keeps what was recorded.
#if defined(LDSM_HAVE_V4L2)  // the V4L2 source is built on Linux only
#include "ldsm/drivers/tum_mono_recorder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "fake_v4l2_kernel.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/v4l2_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

namespace fs = std::filesystem;
using test::fakePixel;
using test::FakeV4l2Kernel;

std::string freshDir(const std::string& name) {
  const fs::path dir = fs::path(LDSM_TEST_TMP) / "v4l2_record" / name;
  fs::remove_all(dir);
  return dir.string();
}

V4l2Options fakeOptions() {
  V4l2Options o;
  o.device = "/dev/video7";
  o.poll_timeout_ms = 50;
  return o;
}

/// Reads the recording back and checks every frame against the fake's pattern and timing.
void expectReadsBack(const std::string& dir, std::int64_t frames, bool with_exposure) {
  std::unique_ptr<FrameSource> dataset = openDataset(dir);
  EXPECT_EQ(dataset->info().frame_count, frames);
  Frame frame;
  for (std::int64_t n = 0; n < frames; ++n) {
    ASSERT_TRUE(dataset->next(frame)) << "frame " << n;
    EXPECT_NEAR(frame.timestamp, 1000.0 + n / 30.0, 1e-6);  // kernel time: microseconds
    if (with_exposure) {
      EXPECT_NEAR(frame.exposure_ms, test::fakeAutoExposureMs(n), 1e-12);
    } else {
      EXPECT_TRUE(std::isnan(frame.exposure_ms));
    }
    int wrong = 0;
    for (int y = 0; y < frame.image.height(); ++y)
      for (int x = 0; x < frame.image.width(); ++x)
        if (frame.image(x, y) != fakePixel(n, x, y)) ++wrong;
    EXPECT_EQ(wrong, 0) << "frame " << n;
  }
  EXPECT_FALSE(dataset->next(frame));
}

TEST(RecordTumMono, CameraFramesReadBackAsADataset) {
  const std::string dir = freshDir("basic");
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Source camera(fakeOptions(), kernel);
  RecordOptions options;
  options.max_frames = 12;
  std::int64_t callbacks = 0;
  const RecordSummary summary =
      recordTumMono(camera, dir, options, [&](const Frame& f, std::int64_t n) {
        ++callbacks;
        EXPECT_EQ(f.index + 1, n);
        return true;
      });
  EXPECT_EQ(summary.frames, 12);
  EXPECT_EQ(callbacks, 12);
  EXPECT_EQ(summary.gaps, 0);
  EXPECT_EQ(summary.out_of_order, 0);
  EXPECT_NEAR(summary.first_timestamp, 1000.0, 1e-6);
  EXPECT_NEAR(summary.last_timestamp, 1000.0 + 11 / 30.0, 1e-6);
  EXPECT_TRUE(fs::is_regular_file(fs::path(dir) / "images" / "000011.png"));
  expectReadsBack(dir, 12, true);
}

TEST(RecordTumMono, CallbackStopsAndUnknownExposureIsOmitted) {
  const std::string dir = freshDir("no_exposure");
  FakeV4l2Kernel::Config c;
  c.exposure_controls = false;
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  V4l2Source camera(fakeOptions(), kernel);
  const RecordSummary summary =
      recordTumMono(camera, dir, {}, [](const Frame&, std::int64_t n) { return n < 5; });
  EXPECT_EQ(summary.frames, 5);
  std::ifstream times(fs::path(dir) / "times.txt");
  std::string first;
  std::getline(times, first);
  EXPECT_EQ(first, "000000 1000");  // id and timestamp only
  expectReadsBack(dir, 5, false);
}

TEST(RecordTumMono, RefusesToOverwriteAnEarlierRecordingUnlessAsked) {
  const std::string dir = freshDir("overwrite");
  {
    auto kernel = std::make_shared<FakeV4l2Kernel>();
    V4l2Source camera(fakeOptions(), kernel);
    RecordOptions o;
    o.max_frames = 8;
    recordTumMono(camera, dir, o);
  }
  auto kernel = std::make_shared<FakeV4l2Kernel>();
  V4l2Source camera(fakeOptions(), kernel);
  RecordOptions o;
  o.max_frames = 3;
  try {
    recordTumMono(camera, dir, o);
    FAIL() << "overwrote an earlier recording";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("already holds a recording"), std::string::npos);
  }
  o.overwrite = true;
  EXPECT_EQ(recordTumMono(camera, dir, o).frames, 3);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "images" / "000005.png")) << "stale frame left";
  expectReadsBack(dir, 3, true);
}

TEST(RecordTumMono, UnpluggedCameraKeepsTheFramesRecordedSoFar) {
  const std::string dir = freshDir("unplugged");
  FakeV4l2Kernel::Config c;
  c.unplug_after = 7;
  auto kernel = std::make_shared<FakeV4l2Kernel>(c);
  V4l2Source camera(fakeOptions(), kernel);
  try {
    recordTumMono(camera, dir);
    FAIL() << "no error from an unplugged camera";
  } catch (const DeviceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unplugged"), std::string::npos) << what;
    EXPECT_NE(what.find("7 frames recorded so far are kept in " + dir), std::string::npos) << what;
  }
  EXPECT_EQ(kernel->openCount(), 0);
  expectReadsBack(dir, 7, true);
}

TEST(RecordTumMono, CountsGapsFromFramesLostUpstream) {
  // A source that skips every third frame of a 30 fps stream.
  class Skipping : public FrameSource {
   public:
    SourceInfo info() const override {
      SourceInfo i;
      i.nominal_fps = 30.0;
      i.width = 8;
      i.height = 4;
      return i;
    }
    bool next(Frame& f) override {
      if (n_ % 3 == 2) ++n_;
      if (n_ >= 9) return false;
      f.index = n_;
      f.timestamp = 5.0 + n_ / 30.0;
      f.image.resize(8, 4);
      f.image.fill(static_cast<std::uint8_t>(n_));
      ++n_;
      return true;
    }

   private:
    std::int64_t n_ = 0;
  } source;
  const RecordSummary s = recordTumMono(source, freshDir("gaps"));
  EXPECT_EQ(s.frames, 6);  // 0 1 3 4 6 7
  EXPECT_EQ(s.gaps, 2);
}

}  // namespace
}  // namespace ldsm::drivers

#endif  // LDSM_HAVE_V4L2
