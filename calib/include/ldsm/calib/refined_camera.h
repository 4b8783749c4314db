// The camera a run ended with, as a calibration file can hold it. The engine works in the
// rectified pinhole K0 of the given calibration and refines it online (CalibrationStats): a focal
// scale and principal point shift (the applied pinhole Ka) and a residual radial distortion k in
// Ka's normalized coordinates. refitCalibration() composes the given input model with that
// refinement - for each input pixel the ray the engine ended up assigning to it - and fits the
// input model's parameters to those rays, so that the result can be written as a camera.txt or a
// Kalibr YAML and used by ldsm, DSO or any other tool on the next run.
#pragma once

#include <string>
#include <vector>

#include "ldsm/camera/calibration.h"
#include "ldsm/system.h"

namespace ldsm::calib {

struct RefinedCameraFit {
  /// The input model refitted (a Pinhole input becomes RadTan when a radial correction was
  /// applied; other models keep their type) and the output: the given one, except that an input
  /// that gained distortion under output mode `none` gets the explicit output pinhole Ka.
  GeometricCalibration calibration;
  /// Reprojection error of the fitted model against the refined rays over the part of the input
  /// image the engine sees (pixels of the input image): how well the model type holds the
  /// refinement. 0 when nothing was applied (the given calibration is returned unchanged).
  double rms_px = 0.0;
  double max_px = 0.0;
  int samples = 0;
  bool changed = false;  ///< false: nothing applied, `calibration` is the given one
  /// 1-sigma of the rectified pinhole's fx, fy, cx, cy (pixels) and of k, from the refinement's
  /// formal sigmas (0 for parameters not refined).
  double sigma_fx = 0.0, sigma_fy = 0.0, sigma_cx = 0.0, sigma_cy = 0.0, sigma_k = 0.0;
  /// The same from the refinement's realistic sigmas (CalibrationStats::realistic_*): the
  /// uncertainty to quote.
  double realistic_sigma_fx = 0.0, realistic_sigma_fy = 0.0, realistic_sigma_cx = 0.0;
  double realistic_sigma_cy = 0.0, realistic_sigma_k = 0.0;
  /// Standard deviation of the same over the last `spread_windows` window estimates of the
  /// history (0 without one): how much the estimate still moves from window to window. The
  /// formal sigmas treat every residual as independent and are far smaller; this is the
  /// realistic figure.
  double spread_fx = 0.0, spread_fy = 0.0, spread_cx = 0.0, spread_cy = 0.0, spread_k = 0.0;
  int spread_windows = 0;
};

/// Window estimates the spread is taken over (the newest ones).
constexpr int kSpreadWindows = 20;

/// Composes `given` with the refinement of `refined` (its configured pinhole must be the output
/// pinhole of `given`) and refits the input model; `history` (SystemStats::calibration_history)
/// gives the spread. Throws ldsm::InputError when `given` is not a
/// valid calibration or does not match `refined.configured`.
RefinedCameraFit refitCalibration(const GeometricCalibration& given,
                                  const CalibrationStats& refined,
                                  const std::vector<CalibrationSample>& history = {});

/// camera.txt text of a fit: comment lines (what it was refined from, the sigmas, the fit error)
/// followed by formatDsoCameraFile(fit.calibration). Reads back with readDsoCameraFile().
std::string formatRefinedDsoCameraFile(const RefinedCameraFit& fit, const std::string& source);

/// Kalibr camchain text of a fit, with the same comment lines (YAML comments).
std::string formatRefinedKalibrYaml(const RefinedCameraFit& fit, const std::string& source);

}  // namespace ldsm::calib
