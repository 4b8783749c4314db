// Top-view plots of trajectories (ground truth vs. aligned estimate) as PNG or SVG.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ldsm::app {

/// One polyline of the plot.
struct PlotSeries {
  std::string label;
  std::vector<Eigen::Vector3d> points;
  std::array<std::uint8_t, 3> rgb{0, 0, 0};
};

/// Draws the series seen from above: the plane spanned by the two axes along which the first
/// series (the ground truth) extends most, with equal scaling on both axes, a metre grid with
/// labelled ticks, a legend, and start (circle) and end (square) markers. The format follows the
/// extension of `path` (.png via OpenCV, .svg hand-written). Throws ldsm::ConfigError for another
/// extension, ldsm::Error when writing fails.
void writeTopViewPlot(const std::string& path, const std::vector<PlotSeries>& series,
                      const std::string& title);

}  // namespace ldsm::app
