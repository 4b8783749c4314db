// The camera a run ended with, written back as a calibration file: the given model composed with
// the online refinement and refitted (calib/refined_camera.h), and the --fov starting guess.
#include "ldsm/calib/refined_camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/kalibr_yaml.h"
#include "ldsm/calib/pinhole_guess.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/camera/rectifier.h"
#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

GeometricCalibration plainPinhole() {
  GeometricCalibration c;
  c.input = {CameraModelType::Pinhole, 500.0, 500.0, 319.5, 239.5, {}, 640, 480};
  c.output.mode = OutputMode::None;
  c.output.width = 640;
  c.output.height = 480;
  return c;
}

/// A wide-angle lens like vamr_desk_loop's, rectified to an explicit pinhole.
GeometricCalibration wideRadTan() {
  GeometricCalibration c;
  c.input = {CameraModelType::RadTan,     420.5, 420.6, 355.2, 250.3,
             {-0.2967, 0.0809, 0.0, 0.0}, 752,   480};
  c.output.mode = OutputMode::Explicit;
  c.output.relative = true;
  c.output.fx = 0.6;
  c.output.fy = 0.9;
  c.output.cx = 0.5;
  c.output.cy = 0.5;
  c.output.width = 640;
  c.output.height = 480;
  return c;
}

CalibrationStats refinement(const GeometricCalibration& given, double focal_scale, double dcx,
                            double dcy, double k) {
  CalibrationStats s;
  s.configured = Rectifier(given).output();
  s.applied = s.configured;
  s.applied.fx *= focal_scale;
  s.applied.fy *= focal_scale;
  s.applied.cx += dcx;
  s.applied.cy += dcy;
  s.radial_applied = k;
  s.focal_scale_estimate = focal_scale;
  s.cx_shift_estimate = dcx;
  s.cy_shift_estimate = dcy;
  s.radial_estimate = k;
  s.focal_scale_sigma = 0.001;
  s.cx_sigma = 0.3;
  s.cy_sigma = 0.4;
  s.radial_sigma = 0.0002;
  s.realistic_focal_scale_sigma = 0.02;
  s.realistic_cx_sigma = 6.0;
  s.realistic_cy_sigma = 8.0;
  s.realistic_radial_sigma = 0.004;
  s.windows = 40;
  return s;
}

/// The ray the refined camera gives input pixel u, computed the slow way: the given model's
/// ray, its rectified pixel, the applied pinhole and the radial term undone by bisection.
bool refinedRay(const GeometricCalibration& given, const CalibrationStats& s,
                const Eigen::Vector2d& u, Eigen::Vector3d* ray) {
  const std::unique_ptr<CameraModel> model = makeCameraModel(given.input);
  Eigen::Vector3d r;
  if (!model->unproject(u, &r) || r.z() <= 0.0) return false;
  const PinholeIntrinsics& k0 = s.configured;
  const PinholeIntrinsics& ka = s.applied;
  const Eigen::Vector2d p(k0.fx * r.x() / r.z() + k0.cx, k0.fy * r.y() / r.z() + k0.cy);
  const Eigen::Vector2d y((p.x() - ka.cx) / ka.fx, (p.y() - ka.cy) / ka.fy);
  const double rho = y.norm();
  double lo = 0.0, hi = 4.0 * rho + 1e-9;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid * (1.0 + s.radial_applied * mid * mid) < rho ? lo : hi) = mid;
  }
  const Eigen::Vector2d x = rho > 0.0 ? Eigen::Vector2d(y * (lo / rho)) : y;
  *ray = Eigen::Vector3d(x.x(), x.y(), 1.0);
  return true;
}

/// Largest pixel error of `fit` against the refined rays at random pixels of the part of the
/// input image that the rectified output sees.
double worstError(const GeometricCalibration& given, const CalibrationStats& s,
                  const GeometricCalibration& fitted) {
  const std::unique_ptr<CameraModel> model = makeCameraModel(fitted.input);
  const Rectifier rect(given);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, rect.output().width - 1.0);
  std::uniform_real_distribution<double> uy(0.0, rect.output().height - 1.0);
  double worst = 0.0;
  int checked = 0;
  while (checked < 500) {
    const int ox = static_cast<int>(ux(rng)), oy = static_cast<int>(uy(rng));
    if (!rect.isValid(ox, oy)) continue;
    const Eigen::Vector2d u = rect.inputPixel(ox, oy).cast<double>();
    Eigen::Vector3d ray;
    Eigen::Vector2d px;
    if (!refinedRay(given, s, u, &ray)) continue;
    EXPECT_TRUE(model->project(ray, &px));
    worst = std::max(worst, (px - u).norm());
    ++checked;
  }
  return worst;
}

TEST(RefinedCamera, NothingAppliedGivesTheGivenCalibrationBack) {
  const GeometricCalibration given = wideRadTan();
  const RefinedCameraFit fit = refitCalibration(given, refinement(given, 1.0, 0.0, 0.0, 0.0));
  EXPECT_FALSE(fit.changed);
  EXPECT_EQ(formatDsoCameraFile(fit.calibration), formatDsoCameraFile(given));
  EXPECT_NEAR(fit.sigma_fx, 0.384, 1e-12);  // 384 px * 0.001
  EXPECT_NEAR(fit.sigma_cy, 0.4, 1e-12);
  // The realistic sigmas the same way, and both in the camera.txt comments.
  EXPECT_NEAR(fit.realistic_sigma_fx, 7.68, 1e-12);  // 384 px * 0.02
  EXPECT_NEAR(fit.realistic_sigma_cx, 6.0, 1e-12);
  EXPECT_NEAR(fit.realistic_sigma_k, 0.004, 1e-12);
  const std::string text = formatRefinedDsoCameraFile(fit, "given.txt");
  EXPECT_NE(text.find("1-sigma (formal) of the rectified pinhole: fx 0.384"), std::string::npos)
      << text;
  EXPECT_NE(text.find("1-sigma (realistic: formal x window overlap x the windows' observed "
                      "scatter): fx 7.68 fy 8.64 cx 6 cy 8 px, radial k 0.004"),
            std::string::npos)
      << text;
}

// A pinhole with a radial term in its own normalized coordinates is exactly RadTan with k1 = k:
// the fit must find it, and keep the refined pinhole as the explicit output.
TEST(RefinedCamera, APinholeWithARadialCorrectionBecomesRadTan) {
  const GeometricCalibration given = plainPinhole();
  const CalibrationStats s = refinement(given, 1.02, 3.0, -2.0, 0.012);
  const RefinedCameraFit fit = refitCalibration(given, s);
  ASSERT_TRUE(fit.changed);
  const CameraIntrinsics& in = fit.calibration.input;
  EXPECT_EQ(in.model, CameraModelType::RadTan);
  EXPECT_NEAR(in.fx, 510.0, 1e-6);
  EXPECT_NEAR(in.fy, 510.0, 1e-6);
  EXPECT_NEAR(in.cx, 322.5, 1e-6);
  EXPECT_NEAR(in.cy, 237.5, 1e-6);
  ASSERT_EQ(in.distortion.size(), 4u);
  EXPECT_NEAR(in.distortion[0], 0.012, 1e-8);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(in.distortion[static_cast<size_t>(i)], 0.0);
  EXPECT_LT(fit.rms_px, 1e-6);
  EXPECT_EQ(fit.calibration.output.mode, OutputMode::Explicit);
  EXPECT_NEAR(fit.calibration.output.fx, 510.0, 1e-9);
  EXPECT_LT(worstError(given, s, fit.calibration), 1e-5);
}

// Focal length and principal point only: the input stays a pinhole (output mode none).
TEST(RefinedCamera, APinholeWithoutDistortionStaysAPinhole) {
  const GeometricCalibration given = plainPinhole();
  const CalibrationStats s = refinement(given, 0.97, -4.0, 1.0, 0.0);
  const RefinedCameraFit fit = refitCalibration(given, s);
  EXPECT_EQ(fit.calibration.input.model, CameraModelType::Pinhole);
  EXPECT_EQ(fit.calibration.output.mode, OutputMode::None);
  EXPECT_NEAR(fit.calibration.input.fx, 485.0, 1e-6);
  EXPECT_NEAR(fit.calibration.input.cx, 315.5, 1e-6);
  EXPECT_NEAR(fit.calibration.input.cy, 240.5, 1e-6);
  EXPECT_LT(worstError(given, s, fit.calibration), 1e-5);
}

// A distorted lens with a residual radial term and a focal correction on top: not exactly a
// RadTan any more (its two radial terms cannot hold the composition), but close over the image
// the engine sees. Measured: rms 0.034 px, max 0.32 px (in the corners) over 910 grid pixels,
// worst 0.20 px at 500 random pixels.
TEST(RefinedCamera, ADistortedLensKeepsItsModelAndFitsTheRefinedRays) {
  const GeometricCalibration given = wideRadTan();
  const CalibrationStats s = refinement(given, 1.01, 1.5, 0.0, 0.02);
  const RefinedCameraFit fit = refitCalibration(given, s);
  ASSERT_TRUE(fit.changed);
  std::printf("refit: rms %.4f px, max %.4f px over %d pixels\n", fit.rms_px, fit.max_px,
              fit.samples);
  EXPECT_EQ(fit.calibration.input.model, CameraModelType::RadTan);
  EXPECT_EQ(fit.calibration.output.mode, OutputMode::Explicit);  // the given output is kept
  EXPECT_TRUE(fit.calibration.output.relative);
  EXPECT_GT(fit.samples, 800);
  EXPECT_LT(fit.rms_px, 0.05);
  EXPECT_LT(fit.max_px, 0.4);
  EXPECT_LT(worstError(given, s, fit.calibration), 0.4);
  // The focal length and the radial term moved the way the refinement says.
  EXPECT_GT(fit.calibration.input.fx, given.input.fx);
  EXPECT_GT(fit.calibration.input.distortion[0], given.input.distortion[0]);
}

TEST(RefinedCamera, WrittenFilesReadBack) {
  const GeometricCalibration given = plainPinhole();
  const RefinedCameraFit fit = refitCalibration(given, refinement(given, 1.02, 3.0, -2.0, 0.012));
  const std::string txt = formatRefinedDsoCameraFile(fit, "cam/camera.txt");
  EXPECT_EQ(txt.rfind("# camera refined online by ldsm from cam/camera.txt\n", 0), 0u) << txt;
  EXPECT_NE(txt.find("1-sigma"), std::string::npos);
  const GeometricCalibration back = parseDsoCameraFile(txt, "camera.txt");
  EXPECT_EQ(formatDsoCameraFile(back), formatDsoCameraFile(fit.calibration));
  const GeometricCalibration yaml =
      parseKalibrCameraYaml(formatRefinedKalibrYaml(fit, "cam/camera.txt"), "camchain.yaml");
  EXPECT_EQ(yaml.input.model, CameraModelType::RadTan);
  EXPECT_EQ(yaml.input.fx, fit.calibration.input.fx);
  EXPECT_EQ(yaml.input.distortion, fit.calibration.input.distortion);
}

TEST(RefinedCamera, ARefinementOfAnotherCameraIsRefused) {
  const GeometricCalibration given = plainPinhole();
  CalibrationStats s = refinement(given, 1.0, 0.0, 0.0, 0.01);
  s.configured.fx = 400.0;
  EXPECT_THROW(refitCalibration(given, s), InputError);
  s = refinement(given, 1.0, 0.0, 0.0, 0.01);
  s.configured.width = 320;
  EXPECT_THROW(refitCalibration(given, s), InputError);
}

TEST(PinholeGuess, UsesTheHorizontalFieldOfViewAndTheImageCentre) {
  const GeometricCalibration c = pinholeFromFieldOfView(640, 480, 90.0);
  EXPECT_EQ(c.input.model, CameraModelType::Pinhole);
  EXPECT_NEAR(c.input.fx, 320.0, 1e-9);
  EXPECT_NEAR(c.input.fy, 320.0, 1e-9);
  EXPECT_EQ(c.input.cx, 319.5);
  EXPECT_EQ(c.input.cy, 239.5);
  EXPECT_EQ(c.output.mode, OutputMode::None);
  EXPECT_EQ(Rectifier(c).output().fx, c.input.fx);
}

TEST(PinholeGuess, RefusesWhatIsNotAFieldOfView) {
  for (const double fov : {0.0, 5.0, -60.0, 170.0, std::nan("")}) {
    try {
      pinholeFromFieldOfView(640, 480, fov);
      ADD_FAILURE() << "no error for " << fov;
    } catch (const ConfigError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--fov: ", 0), 0u) << e.what();
    }
  }
  EXPECT_THROW(pinholeFromFieldOfView(0, 480, 60.0), InputError);
}

}  // namespace
}  // namespace ldsm::calib
