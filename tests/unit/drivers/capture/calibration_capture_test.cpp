#include "ldsm/drivers/calibration_capture.h"

#include <gtest/gtest.h>

#include <cmath>

#include "calibration_test_util.h"
#include "ldsm/calib/response_calibration.h"
#include "ldsm/drivers/sim/image_formation.h"
#include "ldsm/drivers/sim/photometric_sequences.h"
#include "ldsm/drivers/sim/sim_source.h"

namespace ldsm::drivers {
namespace {

/// A camera fixed on a static scene whose exposure is set when it is opened: frames formed by
/// the simulator's image formation. The first `settle` frames still have the previous exposure
/// (as real cameras do); it reports the exposure rounded to 0.1 ms like V4L2, or none.
class FixedExposureCamera : public FrameSource {
 public:
  FixedExposureCamera(const sim::ImageFormation& formation, const ImageF& irradiance,
                      double exposure_ms, int settle, bool reports, int frames = 100)
      : formation_(formation),
        irradiance_(irradiance),
        exposure_ms_(exposure_ms),
        settle_(settle),
        reports_(reports),
        frames_(frames) {}

  SourceInfo info() const override {
    return {"fake", irradiance_.width(), irradiance_.height(), -1, 30};
  }
  bool next(Frame& frame) override {
    if (index_ >= frames_) return false;
    const double formed = index_ < settle_ ? 1.0 : exposure_ms_;
    formation_.apply(irradiance_, formed, static_cast<std::uint32_t>(index_ + 1000 * exposure_ms_),
                     frame.image);
    frame.index = index_++;
    frame.timestamp = frame.index / 30.0;
    frame.exposure_ms = reports_ ? std::round(formed * 10.0) / 10.0 : std::nan("");
    return true;
  }

 private:
  const sim::ImageFormation& formation_;
  const ImageF& irradiance_;
  double exposure_ms_;
  int settle_;
  bool reports_;
  int frames_;
  std::int64_t index_ = 0;
};

TEST(CalibrationCapture, ExposureSweepGivesAUsableResponse) {
  sim::SimOptions o;
  o.width = 160;
  o.height = 120;
  o.frames = 1;
  sim::SimSource scene("loop", o);
  ImageF irradiance;
  scene.renderer().renderIrradiance(scene.groundTruth().front().pose, irradiance);
  const auto times = sim::exposureSweepTimes(0.2, 400, 30);
  int opened = 0, progress_calls = 0;
  const CapturedImages c = captureExposures(
      [&](double t) {
        ++opened;
        return std::make_unique<FixedExposureCamera>(scene.imageFormation(), irradiance, t, 3,
                                                     true);
      },
      times, 3,
      [&](int done, int total) {
        EXPECT_EQ(total, 30);
        EXPECT_EQ(done, ++progress_calls);
      });
  EXPECT_EQ(opened, 30);
  ASSERT_EQ(c.images.size(), 30u);
  for (std::size_t i = 0; i < times.size(); ++i)
    EXPECT_NEAR(c.exposures_ms[i], times[i], 0.05 + 1e-9);  // read back, rounded to 0.1 ms
  std::vector<calib::ExposedImage> in;
  for (std::size_t i = 0; i < c.images.size(); ++i)
    in.push_back({c.images[i].view(), c.exposures_ms[i], std::to_string(i)});
  const auto r = calib::calibrateResponse(in, {}, "captured");
  double s = 0;
  for (std::size_t k = 0; k < 256; ++k)
    s += std::pow(r.inverse_response[k] - scene.photometricCalibration().inverse_response[k], 2);
  EXPECT_LT(100 * std::sqrt(s / 256) / 255, 1.5);
}

TEST(CalibrationCapture, ExposureNotReportedUsesTheRequestedOne) {
  sim::SimOptions o;
  o.width = 32;
  o.height = 24;
  const sim::ImageFormation formation(o, sim::simIntrinsics(o));
  const ImageF flat(32, 24, 0.5f);
  const CapturedImages c = captureExposures(
      [&](double t) { return std::make_unique<FixedExposureCamera>(formation, flat, t, 0, false); },
      {1.25, 2.5}, 0);
  EXPECT_EQ(c.exposures_ms, (std::vector<double>{1.25, 2.5}));
}

TEST(CalibrationCapture, CameraThatStopsIsAnError) {
  sim::SimOptions o;
  o.width = 32;
  o.height = 24;
  const sim::ImageFormation formation(o, sim::simIntrinsics(o));
  const ImageF flat(32, 24, 0.5f);
  auto open = [&](double t) {
    return std::make_unique<FixedExposureCamera>(formation, flat, t, 0, true, 2);
  };
  EXPECT_THROW(captureExposures(open, {1.0}, 4), DeviceError);
  EXPECT_THROW(captureExposures(open, {}, 0), ConfigError);
  EXPECT_THROW(captureExposures(open, {-1.0}, 0), ConfigError);
}

/// A stream of board views: each entry a pose with a blur, or no board.
class BoardStream : public FrameSource {
 public:
  struct Shot {
    std::optional<Pose> pose;
    double blur = 0.0;
  };
  BoardStream(const calib::BoardSpec& spec, std::vector<Shot> shots)
      : spec_(spec),
        target_(test::targetFor(spec)),
        camera_(makeCameraModel(test::radTanCamera())),
        shots_(std::move(shots)) {}

  SourceInfo info() const override { return {"boards", test::kWidth, test::kHeight, -1, 30}; }
  bool next(Frame& frame) override {
    if (index_ >= shots_.size()) return false;
    const Shot& s = shots_[index_];
    if (s.pose) {
      sim::TargetRenderOptions o;
      o.noise_key = static_cast<std::uint32_t>(index_);
      o.blur_sigma_px = s.blur;
      sim::renderTargetView(target_, *camera_, *s.pose, o, frame.image);
    } else {
      frame.image = ImageU8(test::kWidth, test::kHeight, 90);
    }
    frame.index = static_cast<std::int64_t>(index_++);
    return true;
  }

  const CameraModel& camera() const { return *camera_; }
  const sim::CalibrationTarget& target() const { return target_; }

 private:
  calib::BoardSpec spec_;
  sim::CalibrationTarget target_;
  std::unique_ptr<CameraModel> camera_;
  std::vector<Shot> shots_;
  std::size_t index_ = 0;
};

TEST(CalibrationCapture, KeepsSharpViewsAtNewPositions) {
  const auto spec = test::boardSpec(calib::BoardType::Chessboard);
  BoardStream probe(spec, {});
  const auto poses = test::boardPoses(probe.target(), probe.camera(), 5, 0.45);
  ASSERT_EQ(poses.size(), 5u);
  Pose nudged = poses[0];
  nudged.translation.y() += 0.001;  // the board held still: the same view again
  std::vector<BoardStream::Shot> shots = {{poses[0]}, {nudged},        {std::nullopt},
                                          {poses[1]}, {poses[2], 3.0}, {poses[2]},
                                          {poses[3]}, {poses[4]},      {poses[1]}};
  BoardStream stream(spec, shots);
  BoardCaptureOptions o;
  o.views = 10;
  std::vector<std::int64_t> reads;
  const auto kept = captureBoardViews(stream, spec, o, [&](int, std::int64_t read) {
    reads.push_back(read);
    return true;
  });
  std::vector<std::int64_t> frames;
  for (const auto& v : kept) frames.push_back(v.frame_index);
  // Dropped: 1 (same place as 0), 2 (no board), 4 (blurred), 8 (same place as 3).
  EXPECT_EQ(frames, (std::vector<std::int64_t>{0, 3, 5, 6, 7}));
  EXPECT_EQ(reads.size(), shots.size());
  for (const auto& v : kept) EXPECT_EQ(v.image.width(), test::kWidth);

  // Stops at the requested number of views, or when the callback says so.
  BoardStream again(spec, shots);
  o.views = 2;
  EXPECT_EQ(captureBoardViews(again, spec, o).size(), 2u);
  BoardStream stopped(spec, shots);
  o.views = 10;
  EXPECT_EQ(
      captureBoardViews(stopped, spec, o, [](int, std::int64_t read) { return read < 4; }).size(),
      2u);
}

}  // namespace
}  // namespace ldsm::drivers
