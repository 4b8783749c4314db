#include "ldsm/calib/board_detection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "ldsm/error.h"

namespace ldsm::calib {
namespace {

constexpr int kMinCharucoCorners = 6;
constexpr double kPi = 3.14159265358979323846;

struct DictionaryName {
  const char* name;
  cv::aruco::PREDEFINED_DICTIONARY_NAME id;
};

const DictionaryName kDictionaries[] = {
    {"DICT_4X4_50", cv::aruco::DICT_4X4_50},
    {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
    {"DICT_4X4_250", cv::aruco::DICT_4X4_250},
    {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
    {"DICT_5X5_50", cv::aruco::DICT_5X5_50},
    {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
    {"DICT_5X5_250", cv::aruco::DICT_5X5_250},
    {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
    {"DICT_6X6_50", cv::aruco::DICT_6X6_50},
    {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
    {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
    {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
    {"DICT_7X7_50", cv::aruco::DICT_7X7_50},
    {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
    {"DICT_7X7_250", cv::aruco::DICT_7X7_250},
    {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
    {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
};

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

/// The dictionary of `spec` (name matched case-insensitively, "DICT_" optional).
cv::Ptr<cv::aruco::Dictionary> dictionaryOf(const BoardSpec& spec) {
  std::string name = upper(spec.dictionary);
  if (name.rfind("DICT_", 0) != 0) name = "DICT_" + name;
  for (const auto& d : kDictionaries)
    if (name == d.name) return cv::aruco::getPredefinedDictionary(d.id);
  std::string list;
  for (const auto& d : kDictionaries) list += std::string(list.empty() ? "" : ", ") + d.name;
  throw ConfigError("--dictionary '" + spec.dictionary + "' is not an ArUco dictionary (" + list +
                    ")");
}

cv::Ptr<cv::aruco::CharucoBoard> charucoBoardOf(const BoardSpec& spec) {
  return cv::aruco::CharucoBoard::create(spec.cols, spec.rows, static_cast<float>(spec.square_m),
                                         static_cast<float>(spec.marker_m), dictionaryOf(spec));
}

cv::Mat wrap(ImageView<const std::uint8_t> image) {
  if (image.empty()) throw InputError("board detection: empty image");
  return cv::Mat(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.data),
                 static_cast<std::size_t>(image.stride));
}

std::optional<BoardObservation> detectChessboard(const BoardSpec& spec, const cv::Mat& img) {
  const cv::Size pattern(spec.innerCols(), spec.innerRows());
  std::vector<cv::Point2f> corners;
  // The classic detector is fast; the sector-based one finds boards it misses (blur, strong
  // perspective). Both are refined by refineCorners() afterwards.
  bool found = cv::findChessboardCorners(
      img, pattern, corners,
      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
  if (!found)
    found = cv::findChessboardCornersSB(img, pattern, corners,
                                        cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE);
  if (!found) return std::nullopt;
  BoardObservation obs;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const int ix = static_cast<int>(k) % spec.innerCols();
    const int iy = static_cast<int>(k) / spec.innerCols();
    obs.image_points.emplace_back(corners[k].x, corners[k].y);
    obs.board_points.push_back(boardCorner(spec, ix, iy));
    obs.grid.emplace_back(ix, iy);
  }
  return obs;
}

/// Refines the corners with cornerSubPix in a window that stays clear of the neighbouring corners
/// and markers. For chessboards this is more accurate than the sector-based detector alone on
/// strongly tilted boards. OpenCV's ChArUco interpolation up to 4.12 returns the corners shifted
/// by half a pixel (its refinement works on coordinates shifted by -0.5 and shifts the result
/// back); refining its output in absolute coordinates removes the shift, and is harmless where it
/// was fixed.
void refineCorners(const BoardSpec& spec, const cv::Mat& img, BoardObservation& obs) {
  std::map<std::pair<int, int>, std::size_t> at;
  for (std::size_t k = 0; k < obs.grid.size(); ++k) at[{obs.grid[k].x(), obs.grid[k].y()}] = k;
  const double clear =
      spec.type == BoardType::Charuco ? 0.5 * (1.0 - spec.marker_m / spec.square_m) : 0.5;
  for (std::size_t k = 0; k < obs.grid.size(); ++k) {
    // Corner spacing here: the distance to the nearest detected grid neighbour.
    double spacing = std::numeric_limits<double>::infinity();
    for (const auto& d : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
      const auto it = at.find({obs.grid[k].x() + d.first, obs.grid[k].y() + d.second});
      if (it != at.end())
        spacing = std::min(spacing, (obs.image_points[it->second] - obs.image_points[k]).norm());
    }
    if (!std::isfinite(spacing)) continue;
    const int half = std::clamp(static_cast<int>(std::floor(0.8 * clear * spacing)), 2, 10);
    std::vector<cv::Point2f> p{cv::Point2f(static_cast<float>(obs.image_points[k].x()),
                                           static_cast<float>(obs.image_points[k].y()))};
    cv::cornerSubPix(img, p, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
    obs.image_points[k] = Eigen::Vector2d(p[0].x, p[0].y);
  }
}

std::optional<BoardObservation> detectCharuco(const BoardSpec& spec, const cv::Mat& img) {
  const auto board = charucoBoardOf(spec);
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(img, board->dictionary, marker_corners, marker_ids);
  if (marker_ids.empty()) return std::nullopt;
  std::vector<cv::Point2f> corners;
  std::vector<int> ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, img, board, corners, ids);
  if (static_cast<int>(ids.size()) < kMinCharucoCorners) return std::nullopt;
  if (cv::aruco::testCharucoCornersCollinear(board, ids)) return std::nullopt;
  BoardObservation obs;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const int ix = ids[k] % spec.innerCols();
    const int iy = ids[k] / spec.innerCols();
    obs.image_points.emplace_back(corners[k].x, corners[k].y);
    obs.board_points.push_back(boardCorner(spec, ix, iy));
    obs.grid.emplace_back(ix, iy);
  }
  return obs;
}

double bilinear(const cv::Mat& img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= img.cols || y0 + 1 >= img.rows)
    return std::numeric_limits<double>::quiet_NaN();
  const double fx = x - x0, fy = y - y0;
  const std::uint8_t* r0 = img.ptr<std::uint8_t>(y0);
  const std::uint8_t* r1 = img.ptr<std::uint8_t>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

/// Blur sigma of the edge between corners a and b, NaN when it cannot be measured. `clear` is the
/// fraction of the corner spacing on each side of the edge that is free of other edges.
double edgeSigma(const cv::Mat& img, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                 double clear) {
  const double length = (b - a).norm();
  if (length < 8.0) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector2d d = (b - a) / length;
  const Eigen::Vector2d n(-d.y(), d.x());
  const double half = std::min(clear * length, 15.0);
  if (half < 2.5) return std::numeric_limits<double>::quiet_NaN();
  constexpr double kStep = 0.25;
  const int count = static_cast<int>(std::floor(half / kStep));
  std::vector<double> profile(static_cast<std::size_t>(2 * count + 1), 0.0);
  constexpr double kAlong[] = {0.3, 0.4, 0.5, 0.6, 0.7};
  for (int i = -count; i <= count; ++i) {
    double sum = 0.0;
    for (const double s : kAlong) {
      const Eigen::Vector2d p = a + s * length * d + (i * kStep) * n;
      const double v = bilinear(img, p.x(), p.y());
      if (std::isnan(v)) return v;
      sum += v;
    }
    profile[static_cast<std::size_t>(i + count)] = sum / std::size(kAlong);
  }
  // Contrast between the two ends (outer fifth of each side).
  const int tail = std::max(1, count / 5);
  double lo = 0.0, hi = 0.0;
  for (int i = 0; i < tail; ++i) {
    lo += profile[static_cast<std::size_t>(i)];
    hi += profile[profile.size() - 1 - static_cast<std::size_t>(i)];
  }
  const double contrast = std::abs(hi - lo) / tail;
  if (contrast < 20.0) return std::numeric_limits<double>::quiet_NaN();
  // Steepest slope, from differences one pixel apart (robust to the bilinear sampling).
  const int span = static_cast<int>(std::lround(0.5 / kStep));
  double slope = 0.0;
  for (int i = span; i + span < static_cast<int>(profile.size()); ++i)
    slope = std::max(slope, std::abs(profile[static_cast<std::size_t>(i + span)] -
                                     profile[static_cast<std::size_t>(i - span)]) /
                                (2 * span * kStep));
  if (slope <= 0.0) return std::numeric_limits<double>::quiet_NaN();
  return contrast / (std::sqrt(2.0 * kPi) * slope);
}

/// True when `obs` holds every corner of a grid (a chessboard, whose corner order may be
/// reversed between two views of the same pose); `nx` x `ny` receives the grid size.
bool completeGrid(const BoardObservation& obs, int& nx, int& ny) {
  nx = ny = 0;
  for (const auto& g : obs.grid) {
    nx = std::max(nx, g.x() + 1);
    ny = std::max(ny, g.y() + 1);
  }
  return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) == obs.grid.size();
}

}  // namespace

double cornerDistance(const BoardObservation& a, const BoardObservation& b) {
  std::map<std::pair<int, int>, Eigen::Vector2d> at;
  for (std::size_t k = 0; k < a.grid.size(); ++k)
    at[{a.grid[k].x(), a.grid[k].y()}] = a.image_points[k];
  int nx = 0, ny = 0, bx = 0, by = 0;
  const bool may_turn = completeGrid(a, nx, ny) && completeGrid(b, bx, by) && nx == bx && ny == by;
  double best = std::numeric_limits<double>::infinity();
  for (int turned = 0; turned < (may_turn ? 2 : 1); ++turned) {
    double sum = 0.0;
    std::size_t common = 0;
    for (std::size_t k = 0; k < b.grid.size(); ++k) {
      Eigen::Vector2i g = b.grid[k];
      if (turned) g = Eigen::Vector2i(nx - 1 - g.x(), ny - 1 - g.y());
      const auto it = at.find({g.x(), g.y()});
      if (it == at.end()) continue;
      sum += (it->second - b.image_points[k]).squaredNorm();
      ++common;
    }
    const std::size_t needed = std::max<std::size_t>(4, std::min(a.grid.size(), b.grid.size()) / 2);
    if (common >= needed) best = std::min(best, std::sqrt(sum / static_cast<double>(common)));
  }
  return best;
}

const char* toString(BoardType type) {
  return type == BoardType::Charuco ? "charuco" : "chessboard";
}

BoardType parseBoardType(const std::string& name) {
  const std::string n = upper(name);
  if (n == "CHESSBOARD" || n == "CHECKERBOARD") return BoardType::Chessboard;
  if (n == "CHARUCO") return BoardType::Charuco;
  throw ConfigError("--board '" + name + "' is not a board type (chessboard, charuco)");
}

std::vector<std::string> charucoDictionaryNames() {
  std::vector<std::string> names;
  for (const auto& d : kDictionaries) names.emplace_back(d.name);
  return names;
}

void validateBoardSpec(const BoardSpec& spec) {
  if (spec.cols < 3 || spec.rows < 3)
    throw ConfigError("--cols and --rows count the board's squares and must be at least 3 (got " +
                      std::to_string(spec.cols) + " x " + std::to_string(spec.rows) + ")");
  if (spec.cols > 200 || spec.rows > 200)
    throw ConfigError("--cols and --rows must be at most 200");
  if (!(std::isfinite(spec.square_m) && spec.square_m > 0.0))
    throw ConfigError("--square (side of a square in metres) must be positive");
  if (spec.type != BoardType::Charuco) return;
  if (!(std::isfinite(spec.marker_m) && spec.marker_m > 0.0 && spec.marker_m < spec.square_m))
    throw ConfigError(
        "--marker (side of a ChArUco marker in metres) must be positive and smaller than "
        "--square");
  const auto dict = dictionaryOf(spec);
  const int markers = spec.cols * spec.rows / 2;
  if (dict->bytesList.rows < markers)
    throw ConfigError("--dictionary " + spec.dictionary + " has " +
                      std::to_string(dict->bytesList.rows) + " markers but a " +
                      std::to_string(spec.cols) + " x " + std::to_string(spec.rows) +
                      " ChArUco board needs " + std::to_string(markers));
}

Eigen::Vector3d boardCorner(const BoardSpec& spec, int ix, int iy) {
  return {(ix + 1) * spec.square_m, (iy + 1) * spec.square_m, 0.0};
}

std::optional<BoardObservation> detectBoard(const BoardSpec& spec,
                                            ImageView<const std::uint8_t> image) {
  validateBoardSpec(spec);
  const cv::Mat img = wrap(image);
  auto obs =
      spec.type == BoardType::Charuco ? detectCharuco(spec, img) : detectChessboard(spec, img);
  if (!obs) return obs;
  refineCorners(spec, img, *obs);
  obs->width = image.width;
  obs->height = image.height;
  obs->blur_px = measureEdgeBlur(spec, image, *obs);
  return obs;
}

double measureEdgeBlur(const BoardSpec& spec, ImageView<const std::uint8_t> image,
                       const BoardObservation& observation) {
  const cv::Mat img = wrap(image);
  // Chessboard: the squares on both sides of an edge are plain; ChArUco: the marker leaves a
  // white border of (square - marker) / 2 in the white square.
  const double clear =
      spec.type == BoardType::Charuco ? 0.4 * (1.0 - spec.marker_m / spec.square_m) : 0.3;
  std::map<std::pair<int, int>, std::size_t> at;
  for (std::size_t k = 0; k < observation.grid.size(); ++k)
    at[{observation.grid[k].x(), observation.grid[k].y()}] = k;
  std::vector<double> sigmas;
  for (std::size_t k = 0; k < observation.grid.size(); ++k) {
    const Eigen::Vector2i g = observation.grid[k];
    for (const Eigen::Vector2i& step : {Eigen::Vector2i(1, 0), Eigen::Vector2i(0, 1)}) {
      const auto it = at.find({g.x() + step.x(), g.y() + step.y()});
      if (it == at.end()) continue;
      const double s =
          edgeSigma(img, observation.image_points[k], observation.image_points[it->second], clear);
      if (std::isfinite(s)) sigmas.push_back(s);
    }
  }
  if (sigmas.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = sigmas.begin() + static_cast<std::ptrdiff_t>(sigmas.size() / 2);
  std::nth_element(sigmas.begin(), mid, sigmas.end());
  return *mid;
}

ImageU8 drawBoard(const BoardSpec& spec, int px_per_square, int margin_px) {
  validateBoardSpec(spec);
  if (px_per_square < 8) throw ConfigError("board image: at least 8 pixels per square needed");
  if (margin_px < 0) throw ConfigError("board image: negative margin");
  const int w = spec.cols * px_per_square + 2 * margin_px;
  const int h = spec.rows * px_per_square + 2 * margin_px;
  ImageU8 out(w, h);
  if (spec.type == BoardType::Charuco) {
    cv::Mat drawn;
    charucoBoardOf(spec)->draw(cv::Size(w, h), drawn, margin_px, 1);
    if (drawn.cols != w || drawn.rows != h || drawn.type() != CV_8UC1)
      throw Error("board image: OpenCV drew an unexpected image");
    for (int y = 0; y < h; ++y) std::copy_n(drawn.ptr<std::uint8_t>(y), w, out.row(y));
    return out;
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int bx = x - margin_px, by = y - margin_px;
      const bool inside =
          bx >= 0 && by >= 0 && bx < spec.cols * px_per_square && by < spec.rows * px_per_square;
      const bool black = inside && ((bx / px_per_square + by / px_per_square) % 2 == 0);
      out(x, y) = black ? 0 : 255;
    }
  }
  return out;
}

}  // namespace ldsm::calib
