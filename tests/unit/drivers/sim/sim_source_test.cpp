// SimSource as a FrameSource: stream behaviour, calibration it exports, image statistics, options.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"
#include "sim_test_support.h"

namespace ldsm::drivers::sim {
namespace {

TEST(SimSource, StreamsFramesWithTimestampsAndExposures) {
  SimOptions o;
  o.width = 80;
  o.height = 60;
  o.frames = 5;
  o.fps = 20.0;
  o.exposure_changes = true;
  SimSource src(test::sharedScene("short"), o);
  const SourceInfo info = src.info();
  EXPECT_EQ(info.name, "sim:short");
  EXPECT_EQ(info.width, 80);
  EXPECT_EQ(info.height, 60);
  EXPECT_EQ(info.frame_count, 5);
  EXPECT_DOUBLE_EQ(info.nominal_fps, 20.0);
  ASSERT_EQ(src.groundTruth().size(), 5u);
  Frame f;
  int n = 0;
  while (src.next(f)) {
    EXPECT_EQ(f.index, n);
    EXPECT_DOUBLE_EQ(f.timestamp, n / 20.0);
    EXPECT_DOUBLE_EQ(f.timestamp, src.groundTruth()[n].timestamp);
    EXPECT_DOUBLE_EQ(f.exposure_ms, simExposureMs(o, f.timestamp));
    EXPECT_EQ(f.image.width(), 80);
    ++n;
  }
  EXPECT_EQ(n, 5);
  EXPECT_FALSE(src.next(f));
  EXPECT_THROW(src.renderFrame(5, f), InputError);
  EXPECT_THROW(src.renderFrame(-1, f), InputError);
}

TEST(SimSource, ExportsTheTruePinholeAndPhotometricCalibration) {
  SimOptions o;
  o.width = 100;
  o.height = 50;
  o.hfov_deg = 90.0;
  SimSource src(test::sharedScene("short"), o);
  const GeometricCalibration& g = src.geometricCalibration();
  EXPECT_EQ(g.input.model, CameraModelType::Pinhole);
  EXPECT_NEAR(g.input.fx, 50.0, 1e-12);  // tan(45 deg) = 1
  EXPECT_EQ(g.input.fy, g.input.fx);
  EXPECT_EQ(g.input.cx, 49.5);
  EXPECT_EQ(g.input.cy, 24.5);
  EXPECT_EQ(g.output.mode, OutputMode::None);
  EXPECT_EQ(g.output.width, 100);
  const PhotometricCalibration& p = src.photometricCalibration();
  EXPECT_TRUE(p.has_response);
  EXPECT_EQ(p.vignette.width(), 100);
  o.focal_px = 70.0;
  EXPECT_EQ(simIntrinsics(o).fx, 70.0);
}

TEST(SimSource, ImagesHaveSaneStatistics) {
  SimOptions o;
  o.width = 320;
  o.height = 240;
  for (const auto& name : simSceneNames()) {
    SimSource src(test::sharedScene(name), o);
    Frame f;
    for (std::int64_t i : {std::int64_t{0}, src.frameCount() / 2, src.frameCount() - 1}) {
      src.renderFrame(i, f);
      double sum = 0, grad = 0;
      int black = 0, saturated = 0, textured = 0, n = 0;
      for (int y = 1; y < o.height - 1; ++y)
        for (int x = 1; x < o.width - 1; ++x) {
          const int v = f.image(x, y);
          sum += v;
          black += v == 0;
          saturated += v == 255;
          const double g = std::hypot(f.image(x + 1, y) - f.image(x - 1, y),
                                      f.image(x, y + 1) - f.image(x, y - 1));
          grad += g;
          textured += g > 16;
          ++n;
        }
      SCOPED_TRACE(name + " frame " + std::to_string(i));
      EXPECT_GT(sum / n, 50.0);
      EXPECT_LT(sum / n, 200.0);
      EXPECT_LT(black, n / 100);
      EXPECT_LT(saturated, n / 20);
      EXPECT_GT(grad / n, 4.0);     // enough gradient for direct alignment
      EXPECT_GT(textured, n / 20);  // and strong edges/corners for features
    }
  }
}

TEST(SimSource, PathLengthSumsTheSteps) {
  Trajectory t(3);
  t[1].pose.translation = Eigen::Vector3d(3, 4, 0);
  t[2].pose.translation = Eigen::Vector3d(3, 4, 2);
  EXPECT_DOUBLE_EQ(pathLength(t), 7.0);
  EXPECT_EQ(pathLength({}), 0.0);
}

TEST(SimOptions, ValidationNamesTheOption) {
  auto expectBad = [](const char* key, auto mutate) {
    SimOptions o;
    mutate(o);
    try {
      validate(o);
      ADD_FAILURE() << key << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  expectBad("width", [](SimOptions& o) { o.width = 8; });
  expectBad("height", [](SimOptions& o) { o.height = 100000; });
  expectBad("fps", [](SimOptions& o) { o.fps = 0.0; });
  expectBad("fps", [](SimOptions& o) { o.fps = std::nan(""); });
  expectBad("focal_px", [](SimOptions& o) { o.focal_px = -3.0; });
  expectBad("hfov_deg", [](SimOptions& o) { o.hfov_deg = 179.0; });
  expectBad("frames", [](SimOptions& o) { o.frames = -1; });
  expectBad("exposure_ms", [](SimOptions& o) { o.exposure_ms = 0.0; });
  expectBad("vignette", [](SimOptions& o) { o.vignette = 1.0; });
  expectBad("noise_sigma", [](SimOptions& o) { o.noise_sigma = -1.0; });
  expectBad("supersampling", [](SimOptions& o) { o.supersampling = 0; });
  expectBad("motion_blur_samples", [](SimOptions& o) { o.motion_blur_samples = 40; });
  expectBad("exposure_ms", [](SimOptions& o) {
    o.motion_blur_samples = 4;
    o.exposure_ms = 30.0;
    o.exposure_changes = true;
  });
  EXPECT_NO_THROW(validate(SimOptions{}));
  EXPECT_EQ(parseSimResponse("scurve"), SimResponse::SCurve);
  EXPECT_EQ(toString(parseSimResponse("gamma")), "gamma");
  EXPECT_THROW(parseSimResponse("log"), ConfigError);
  EXPECT_THROW(SimSource("short",
                         [] {
                           SimOptions o;
                           o.fps = -1;
                           return o;
                         }()),
               ConfigError);
}

TEST(SimSource, MotionBlurAveragesAcrossTheExposure) {
  SimOptions sharp, blurred;
  sharp.width = blurred.width = 160;
  sharp.height = blurred.height = 120;
  sharp.noise_sigma = blurred.noise_sigma = 0.0;
  blurred.motion_blur_samples = 8;
  blurred.exposure_ms = sharp.exposure_ms = 25.0;
  SimSource a(test::sharedScene("rotation"), sharp), b(test::sharedScene("rotation"), blurred);
  Frame fa, fb;
  a.renderFrame(100, fa);
  b.renderFrame(100, fb);
  double ga = 0, gb = 0, diff = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 1; x < 159; ++x) {
      ga += std::abs(fa.image(x + 1, y) - fa.image(x - 1, y));
      gb += std::abs(fb.image(x + 1, y) - fb.image(x - 1, y));
      diff += std::abs(fa.image(x, y) - fb.image(x, y));
    }
  EXPECT_LT(gb, 0.95 * ga);             // panning blurs horizontal gradients
  EXPECT_LT(diff / (120 * 158), 10.0);  // but the image is the same view
}

}  // namespace
}  // namespace ldsm::drivers::sim
