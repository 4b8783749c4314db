// Raster drawing for the tool's PNG plots (trajectories, calibration curves): an anti-aliased RGB
// canvas drawn with OpenCV imgproc and written with ldsm's PNG encoder, and linear axes with
// "nice" tick steps.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ldsm/image.h"

namespace ldsm::app {

using Rgb = std::array<std::uint8_t, 3>;

inline constexpr Rgb kBlack{0, 0, 0};
inline constexpr Rgb kWhite{255, 255, 255};
inline constexpr Rgb kGrid{225, 225, 225};

/// 1, 2 or 5 times a power of ten, at least `raw` (> 0).
double niceStep(double raw);

/// A linear axis mapping data values [lo, hi] onto pixels [p0, p1] (p1 < p0 for an upward axis).
struct LinearAxis {
  double lo = 0.0, hi = 1.0;
  double p0 = 0.0, p1 = 1.0;
  double step = 0.1;  ///< tick spacing
  int decimals = 1;   ///< decimals of the tick labels

  /// An axis over [lo, hi] with about `ticks` nice ticks.
  static LinearAxis make(double lo, double hi, double p0, double p1, int ticks = 8);
  double toPx(double v) const { return p0 + (v - lo) / (hi - lo) * (p1 - p0); }
  std::vector<double> ticks() const;
  std::string label(double v) const;
};

/// A white RGB canvas. Coordinates are pixels with sub-pixel precision, y down.
class PlotCanvas {
 public:
  PlotCanvas(int width, int height);

  int width() const { return img_.cols; }
  int height() const { return img_.rows; }

  void line(double x0, double y0, double x1, double y1, const Rgb& colour, int thickness = 1);
  void polyline(const std::vector<Eigen::Vector2d>& points, const Rgb& colour, int thickness);
  void rectangle(double x0, double y0, double x1, double y1, const Rgb& colour, bool filled,
                 int thickness = 1);
  void circle(double x, double y, double radius, const Rgb& colour, bool filled);
  /// A filled circle or square in `colour` with a white rim (start / end markers).
  void marker(double x, double y, bool square, const Rgb& colour);
  /// Text with its baseline at y; `align` 0 puts x at its left end, 0.5 centred, 1 right.
  void text(const std::string& s, double x, double y, double align, double size = 0.45,
            const Rgb& colour = kBlack);
  /// Text turned 90 degrees counter-clockwise, centred on (x, y) (vertical axis labels).
  void verticalText(const std::string& s, double x, double y, double size = 0.5);
  /// Draws `image` scaled (nearest neighbour) into the rectangle at (x, y) of size w x h.
  void image(const ImageView<const Rgb>& image, int x, int y, int w, int h);

  /// The canvas as a PNG file's bytes.
  std::string encodePng() const;
  /// Writes the PNG atomically. Throws ldsm::Error when it cannot be written.
  void writePng(const std::string& path) const;

 private:
  cv::Mat img_;  // 8-bit BGR
};

/// Colour of t in [0, 1] on a perceptually ordered dark-blue -> yellow scale (for heat maps).
Rgb heatColour(double t);

}  // namespace ldsm::app
