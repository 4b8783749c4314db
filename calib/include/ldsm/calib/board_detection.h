// Planar calibration boards (chessboard, ChArUco): their layout, finding their inner corners in an
// image (OpenCV calib3d, aruco), how blurred the board looks, and images of them for printing or
// rendering.
//
// Board frame: origin at the outer corner of the first square (the top-left of the drawn board),
// x along the `cols` squares, y along the `rows` squares, z = 0 on the board. Inner corner
// (ix, iy), 0 <= ix < cols - 1, 0 <= iy < rows - 1, is at ((ix + 1) s, (iy + 1) s, 0).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ldsm/image.h"

namespace ldsm::calib {

enum class BoardType {
  Chessboard,  ///< black and white squares, the first (top-left) one black
  Charuco,     ///< chessboard with ArUco markers in the white squares (OpenCV 4.6 layout)
};

/// "chessboard" or "charuco".
const char* toString(BoardType type);
/// Inverse of toString(). Throws ldsm::ConfigError listing the accepted names.
BoardType parseBoardType(const std::string& name);

/// A board of cols x rows squares (not inner corners: a board of 9 x 6 squares has 8 x 5 inner
/// corners).
struct BoardSpec {
  BoardType type = BoardType::Chessboard;
  int cols = 0;           ///< squares along x
  int rows = 0;           ///< squares along y
  double square_m = 0.0;  ///< side of a square, metres
  double marker_m = 0.0;  ///< ChArUco only: side of a marker, metres (< square_m)
  /// ChArUco only: OpenCV predefined dictionary, e.g. "DICT_5X5_100" (charucoDictionaryNames()).
  std::string dictionary = "DICT_5X5_100";

  int innerCols() const { return cols - 1; }
  int innerRows() const { return rows - 1; }
};

/// Throws ldsm::ConfigError naming the option (--cols, --rows, --square, --marker,
/// --dictionary) unless: cols and rows >= 3, square_m > 0 and finite; for ChArUco 0 < marker_m <
/// square_m, a known dictionary with at least as many markers as white squares.
void validateBoardSpec(const BoardSpec& spec);

/// The dictionary names BoardSpec accepts (DICT_4X4_50 ... DICT_7X7_1000, DICT_ARUCO_ORIGINAL).
std::vector<std::string> charucoDictionaryNames();

/// Board coordinates (metres, z = 0) of inner corner (ix, iy).
Eigen::Vector3d boardCorner(const BoardSpec& spec, int ix, int iy);

/// The inner corners of a board found in one image.
struct BoardObservation {
  std::vector<Eigen::Vector2d> image_points;  ///< pixels (pixel centres at integer coordinates)
  std::vector<Eigen::Vector3d> board_points;  ///< the same corners on the board (metres, z = 0)
  std::vector<Eigen::Vector2i> grid;          ///< (ix, iy) of each corner
  /// Edge blur in pixels (see measureEdgeBlur); NaN when no edge could be measured.
  double blur_px = 0.0;
  int width = 0;  ///< size of the image it was found in
  int height = 0;
};

/// Finds the board's inner corners with sub-pixel accuracy and measures the blur. A chessboard
/// is found only when all its inner corners are; a ChArUco board when at least 6 corners that
/// are not all on one line are. Returns nullopt when the board is not found. Throws
/// ldsm::ConfigError for an invalid spec, ldsm::InputError for an empty image.
std::optional<BoardObservation> detectBoard(const BoardSpec& spec,
                                            ImageView<const std::uint8_t> image);

/// Root mean square distance (pixels) between the corners two observations share (matched by
/// grid position; two complete grids, chessboards, are also compared turned by 180 degrees, as
/// the detector may number them either way), or infinity when they share fewer than half of the
/// smaller one's corners (at least 4). Small: the board was at nearly the same place.
double cornerDistance(const BoardObservation& a, const BoardObservation& b);

/// How blurred the board's edges are: for each pair of adjacent inner corners, the grey profile
/// across the square edge between them (averaged along the edge) is compared with a Gaussian-
/// blurred step: sigma = contrast / (sqrt(2 pi) max slope). Returns the median sigma in pixels
/// over the edges (about 0.5 for a sharp, antialiased image), NaN when no edge is long enough or
/// has enough contrast.
double measureEdgeBlur(const BoardSpec& spec, ImageView<const std::uint8_t> image,
                       const BoardObservation& observation);

/// An image of the board with px_per_square pixels per square and a white margin of margin_px
/// around it (for printing, or as the texture of a rendered board: pixel (u, v) shows the board
/// point ((u + 0.5 - margin_px) / px_per_square * square_m, (v + 0.5 - margin_px) / px_per_square
/// * square_m)). Throws ldsm::ConfigError for an invalid spec or px_per_square < 8.
ImageU8 drawBoard(const BoardSpec& spec, int px_per_square, int margin_px);

}  // namespace ldsm::calib
