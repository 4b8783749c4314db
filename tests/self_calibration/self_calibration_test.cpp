// Self-calibration on a rendered scene with a known camera: the system is told a wrong focal
// length, principal point or radial distortion (each alone and all together), refines the
// camera online, and the camera it ends with (refitted in the told model, as `ldsm run` writes
// it) is compared with the truth: within 0.5 % in focal length, 1 px in principal point and 0.002
// in k1 (issue 22's targets). Measured (loop scene, 300 frames): fx within 0.05 %, cx within
// 0.8 px, k1 within 0.0011. The trajectory is not yet as good as the exactly calibrated run's
// (target: 1.5x): the first windows are tracked with the wrong camera before the estimate
// converges (40-150 frames). Measured ATE (keyframes at 0.65 of DSO's rate, DSO's while the
// camera is being corrected: docs/engine.md, "Keyframe rate") 0.0019 m exact; 0.0035 m (1.9x)
// focal, 0.0108 m (5.7x) principal point, 0.0038 m (2.0x) radial, 0.0056 m (2.9x) all three (at
// DSO's rate throughout, measured before the tracker warped through k: 0.0014; 0.0021, 0.0105,
// 0.0031, 0.0079 m); the bound below keeps that from getting worse. The principal point and
// all-three cases depend on the start: over starts 0-25 frames in (SimSource::seek) they span
// 0.0105-0.0200 m and 0.0079-0.0142 m, above the bound at 2 of 8 starts each; the exact runs stay
// below 0.0018 m over starts 0-30 (docs/engine.md, "Radial correction of the calibration").
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <string>

#include "ldsm/calib/refined_camera.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/eval/ate.h"
#include "ldsm/system.h"

namespace ldsm {
namespace {

struct TellError {
  double focal_scale = 1.0;  ///< told fx, fy = true * this
  double cx_px = 0.0;        ///< told cx = true + this
  double k1 = 0.0;           ///< told RadTan k1 (the images have none)
};

struct SelfCalibrationRun {
  double ate = 0.0;
  GeometricCalibration truth;
  calib::RefinedCameraFit camera;
  SystemStats stats;
};

SelfCalibrationRun runTold(const TellError& error) {
  if (const char* level = std::getenv("LDSM_DEBUG"))  // LDSM_DEBUG=1: debug, LDSM_DEBUG=trace
    spdlog::set_level(std::string(level) == "trace" ? spdlog::level::trace : spdlog::level::debug);
  drivers::sim::SimOptions opt;
  opt.frames = 300;
  drivers::sim::SimSource source("loop", opt);
  GeometricCalibration told = source.geometricCalibration();
  told.input.fx *= error.focal_scale;
  told.input.fy *= error.focal_scale;
  told.input.cx += error.cx_px;
  if (error.k1 != 0.0) {
    told.input.model = CameraModelType::RadTan;
    told.input.distortion = {error.k1, 0.0, 0.0, 0.0};
    told.output.mode = OutputMode::Explicit;
    told.output.relative = false;
    told.output.fx = told.input.fx;
    told.output.fy = told.input.fy;
    told.output.cx = told.input.cx;
    told.output.cy = told.input.cy;
  }
  // What `ldsm run --fov` turns on: every part of the camera refined.
  Config config;
  config.system.deterministic = true;
  config.calibration.refine_focal = true;
  config.calibration.refine_principal_point = true;
  System system(config, told, source.photometricCalibration());
  drivers::Frame frame;
  while (source.next(frame))
    system.submit({frame.image.view(), frame.timestamp, frame.exposure_ms});
  system.finish();
  SelfCalibrationRun r;
  r.truth = source.geometricCalibration();
  r.stats = system.stats();
  r.ate = eval::computeAte(source.groundTruth(), system.trajectory()).rmse;
  r.camera = calib::refitCalibration(told, r.stats.calibration, r.stats.calibration_history);
  const CameraIntrinsics& c = r.camera.calibration.input;
  std::printf(
      "told fx x%.3f cx %+.1f k1 %+.3f: refined fx %.2f (true %.2f) cx %.2f (true %.2f) cy %.2f "
      "(true %.2f) k1 %+.4f, ATE %.5f m\n",
      error.focal_scale, error.cx_px, error.k1, c.fx, r.truth.input.fx, c.cx, r.truth.input.cx,
      c.cy, r.truth.input.cy, c.distortion.empty() ? 0.0 : c.distortion[0], r.ate);
  return r;
}

void expectNearTruth(const SelfCalibrationRun& r, double focal_rel, double pp_px, double k1) {
  const CameraIntrinsics& c = r.camera.calibration.input;
  const CameraIntrinsics& t = r.truth.input;
  EXPECT_NEAR(c.fx / t.fx, 1.0, focal_rel);
  EXPECT_NEAR(c.fy / t.fy, 1.0, focal_rel);
  EXPECT_NEAR(c.cx, t.cx, pp_px);
  EXPECT_NEAR(c.cy, t.cy, pp_px);
  EXPECT_NEAR(c.distortion.empty() ? 0.0 : c.distortion[0], 0.0, k1);
}

// The run told the exact camera, made once per suite run: ctest's fixture test
// (AnExactCameraStaysUnchanged) writes its ATE to the file LDSM_SELF_CALIBRATION_EXACT_RUN names,
// the cases read it from there; run without that file (the executable alone), a case makes the
// exact run itself.
const char* exactRunFile() {
  return std::getenv("LDSM_SELF_CALIBRATION_EXACT_RUN");
}

double exactRunAte() {
  if (const char* path = exactRunFile()) {
    std::ifstream in(path);
    double ate = 0.0;
    if (in >> ate && std::isfinite(ate) && ate > 0.0) return ate;
    std::fprintf(stderr,
                 "no ATE of the exact run in %s (SelfCalibration.AnExactCameraStaysUnchanged "
                 "writes it): making the exact run here\n",
                 path);
  }
  return runTold({}).ate;
}

// Exactly calibrated: every estimate stays inside its dead band, nothing is applied.
TEST(SelfCalibration, AnExactCameraStaysUnchanged) {
  const SelfCalibrationRun exact = runTold({});
  EXPECT_FALSE(exact.camera.changed);
  expectNearTruth(exact, 1e-12, 1e-9, 1e-12);
  EXPECT_LT(exact.ate, 0.002);
  if (const char* path = exactRunFile()) {
    // Written whole, then renamed: a case never reads half a file.
    const std::string partial = std::string(path) + ".partial";
    {
      std::ofstream out(partial, std::ios::trunc);
      out << std::setprecision(17) << exact.ate << "\n";
      ASSERT_TRUE(out.good()) << "cannot write " << partial;
    }
    ASSERT_EQ(std::rename(partial.c_str(), path), 0)
        << "cannot rename " << partial << " to " << path;
  }
}

TEST(SelfCalibration, FindsAFocalLengthFivePercentShort) {
  const SelfCalibrationRun r = runTold({0.95, 0.0, 0.0});
  expectNearTruth(r, 0.005, 1.0, 0.002);
  EXPECT_LT(r.ate, 10.0 * exactRunAte());
}

TEST(SelfCalibration, FindsAPrincipalPointTenPixelsOff) {
  const SelfCalibrationRun r = runTold({1.0, 10.0, 0.0});
  expectNearTruth(r, 0.005, 1.0, 0.002);
  EXPECT_LT(r.ate, 10.0 * exactRunAte());
}

TEST(SelfCalibration, FindsARadialDistortionThatIsNotThere) {
  const SelfCalibrationRun r = runTold({1.0, 0.0, -0.02});
  expectNearTruth(r, 0.005, 1.0, 0.002);
  EXPECT_LT(r.ate, 10.0 * exactRunAte());
}

TEST(SelfCalibration, FindsAllThreeErrorsTogether) {
  const SelfCalibrationRun r = runTold({0.95, 10.0, -0.02});
  expectNearTruth(r, 0.005, 1.0, 0.002);
  EXPECT_LT(r.ate, 10.0 * exactRunAte());
}

}  // namespace
}  // namespace ldsm
