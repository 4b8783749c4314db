// Synthetic views of a planar calibration board for testing the calibration tools: the board seen
// by a camera with known intrinsics and distortion (any ldsm camera model) from a known pose,
// antialiased by supersampling, with optional Gaussian blur and reproducible noise.
//
// Board frame as in calib/board_detection.h: origin at the outer corner of the first square, x
// along the cols squares, y along the rows squares, z = 0 on the board, the printed side facing
// -z. The analytic chessboard has its first square black; any other look (a ChArUco board) is
// given as a texture image drawn by the caller.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "ldsm/camera/camera_model.h"
#include "ldsm/image.h"
#include "ldsm/types.h"

namespace ldsm::drivers::sim {

struct CalibrationTarget {
  int cols = 9;             ///< squares along x
  int rows = 6;             ///< squares along y
  double square_m = 0.03;   ///< side of a square
  double margin_m = 0.015;  ///< white border around the squares
  /// The board's look over [-margin_m, cols * square_m + margin_m] x [-margin_m, rows * square_m
  /// + margin_m], texel rows along y (e.g. calib::drawBoard(spec, px, margin_m / square_m * px)).
  /// Empty: the analytic chessboard.
  ImageU8 texture;
  double black = 0.06;       ///< irradiance of black (texture value 0)
  double white = 0.8;        ///< irradiance of white (texture value 255)
  double background = 0.35;  ///< irradiance around the board
};

struct TargetRenderOptions {
  int samples_per_axis = 4;     ///< antialiasing: n x n samples per pixel, 1..8
  double blur_sigma_px = 0.0;   ///< Gaussian blur of the rendered image (focus or motion blur)
  double noise_sigma = 1.0;     ///< additive noise of the 8-bit image, grey levels
  std::uint32_t noise_key = 0;  ///< selects the noise pattern (use one per view)
};

/// Renders the irradiance (black..white, background elsewhere) that `camera` sees from
/// `camera_to_board` (the camera's pose in the board frame) into `out` (resized to the camera
/// size). Pixels whose ray misses the printed side of the board, or that the model cannot
/// unproject, see the background. Throws ldsm::ConfigError on invalid target or options.
void renderTargetIrradiance(const CalibrationTarget& target, const CameraModel& camera,
                            const Pose& camera_to_board, const TargetRenderOptions& options,
                            ImageF& out);

/// renderTargetIrradiance() mapped to 8 bits: round(255 * irradiance + noise), clamped.
void renderTargetView(const CalibrationTarget& target, const CameraModel& camera,
                      const Pose& camera_to_board, const TargetRenderOptions& options,
                      ImageU8& out);

/// Pixel positions of the inner corners, (ix, iy) at index iy * (cols - 1) + ix; nullopt where a
/// corner is behind the camera or outside the model's domain (not checked against the image).
std::vector<std::optional<Eigen::Vector2d>> projectTargetCorners(const CalibrationTarget& target,
                                                                 const CameraModel& camera,
                                                                 const Pose& camera_to_board);

/// `count` camera poses that view the target from different directions (tilted 15-40 degrees),
/// at 0.85-1.15 times `distance` from its centre, aimed beside the centre so that the board
/// also appears near the image edges, rolled a little; only poses that keep every inner corner
/// at least `margin` px inside the image are kept. Deterministic. May return fewer poses when
/// the target does not fit the view at that distance.
std::vector<Pose> calibrationPoses(const CalibrationTarget& target, const CameraModel& camera,
                                   int count, double distance, double margin = 12.0);

/// The pose of a camera at `position` (board frame, z < 0 in front of the board) looking at
/// `look_at`, its image y axis along the board's y as far as possible, then rolled by `roll_rad`
/// about its optical axis.
Pose lookAtBoard(const Eigen::Vector3d& position, const Eigen::Vector3d& look_at,
                 double roll_rad = 0.0);

}  // namespace ldsm::drivers::sim
