// Geometric camera calibration from views of a planar board (OpenCV calib3d): selects the views
// worth using (board found, not blurred, not a near-duplicate of a better one), estimates the
// intrinsics of a pinhole, radial-tangential or equidistant (fisheye) model, and reports the
// reprojection error per view and overall.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "ldsm/calib/board_detection.h"
#include "ldsm/camera/calibration.h"

namespace ldsm::calib {

/// One image of the calibration set: its name (for reports) and the board found in it.
struct BoardView {
  std::string name;
  std::optional<BoardObservation> observation;  ///< nullopt: the board was not found
};

enum class ViewStatus {
  Used,       ///< contributes to the calibration
  NoBoard,    ///< the board was not found
  Blurred,    ///< edges much blurrier than in the other views (motion or focus blur)
  Duplicate,  ///< nearly the same board position as a sharper view that is used
  Outlier,    ///< reprojection error far above the other views' (dropped, then recalibrated)
};

/// "used", "no board", "blurred", "duplicate", "outlier".
const char* toString(ViewStatus status);

struct CameraCalibrationOptions {
  /// Pinhole (no distortion), RadTan (k1 k2 p1 p2) or Equidistant (k1..k4). Fov is not supported.
  CameraModelType model = CameraModelType::RadTan;
  /// Fewest views the calibration accepts.
  int min_views = 5;
  /// A view is blurred when its edge blur exceeds blur_ratio times the median of the views...
  double blur_ratio = 1.5;
  /// ...and also exceeds this many pixels (sharp views are never rejected).
  double min_rejected_blur_px = 1.0;
  /// Two views are duplicates when the board's corners moved by less than this fraction of the
  /// image diagonal on average (root mean square) between them.
  double duplicate_fraction = 0.02;
  /// Views with an RMS error above outlier_ratio times the median and above 0.5 px are dropped
  /// and the calibration is repeated once.
  double outlier_ratio = 3.0;
};

/// What happened to one view.
struct ViewReport {
  std::string name;
  ViewStatus status = ViewStatus::NoBoard;
  int corners = 0;       ///< corners found (0 without a board)
  double blur_px = 0.0;  ///< edge blur (NaN when unmeasured or no board)
  double rms_px = 0.0;   ///< reprojection RMS of the corners (NaN when not calibrated with)
  std::string reason;    ///< why it was not used, e.g. "duplicate of img_004.png"
};

struct CameraCalibrationResult {
  /// The input intrinsics; output mode crop at the input size when the model has distortion,
  /// none for the pinhole.
  GeometricCalibration calibration;
  double rms_px = 0.0;  ///< reprojection RMS over every corner of the used views
  int used_views = 0;
  std::vector<ViewReport> views;  ///< one per input view, in input order
  /// Hints about the result (poor coverage of the image, large error, blurred views).
  std::vector<std::string> warnings;
  /// Every corner of the used views and its reprojection error (pixels), for coverage plots.
  std::vector<Eigen::Vector2d> corners;
  std::vector<double> corner_errors_px;
};

/// Calibrates a camera of width x height from `views`. `source` names the image set in errors.
/// Throws ldsm::ConfigError for an unsupported model or invalid options, ldsm::InputError
/// "<source>: ..." when no view has the board (what to check: board type, squares not inner
/// corners, marker size, dictionary, lighting), when fewer than min_views views remain (with the
/// count of each rejection and what to do), when an observation's image size differs, or when
/// the optimisation fails.
CameraCalibrationResult calibrateCamera(const std::vector<BoardView>& views, int width, int height,
                                        const CameraCalibrationOptions& options,
                                        const std::string& source);

}  // namespace ldsm::calib
