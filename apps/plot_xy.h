// XY charts (curves and scattered points with axes, grid, legend) drawn into a rectangle of a
// PlotCanvas: the calibration tools' response and vignette plots.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "plot_canvas.h"

namespace ldsm::app {

struct XYSeries {
  enum class Style { Line, Dots };
  std::string label;                    ///< legend entry (empty: not listed)
  std::vector<Eigen::Vector2d> points;  ///< non-finite points are skipped (and break a line)
  Rgb rgb{0, 0, 0};
  Style style = Style::Line;
  double size = 2.0;  ///< line width or dot radius, pixels
};

struct XYChart {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<XYSeries> series;  ///< drawn in order, the last on top
  /// Axis ranges; when lo >= hi the range of the data (with a small margin) is used.
  double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;
  /// Lines of text below the legend.
  std::vector<std::string> notes;
  enum class Legend { TopLeft, TopRight, BottomLeft, BottomRight };
  Legend legend = Legend::TopLeft;  ///< the plot corner of the legend box
};

/// Draws `chart` into the rectangle (x, y, width, height) of `canvas`: title above, tick labels
/// and axis labels around the plot area.
void drawXYChart(PlotCanvas& canvas, const XYChart& chart, int x, int y, int width, int height);

}  // namespace ldsm::app
