#include "calibration_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plot_canvas.h"
#include "plot_xy.h"

namespace ldsm::app {
namespace {

const Rgb kBlue{31, 119, 180};
const Rgb kOrange{255, 127, 14};
const Rgb kRed{214, 39, 40};
const Rgb kGrey{150, 150, 150};

std::string fmt(const char* format, double v) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

/// A vertical colour bar for heat maps, labelled lo at the bottom and hi at the top.
void colourBar(PlotCanvas& c, int x, int y, int h, double lo, double hi, const char* format) {
  for (int v = 0; v < h; ++v) {
    const Rgb col = heatColour(1.0 - static_cast<double>(v) / (h - 1));
    c.line(x, y + v + 0.5, x + 16, y + v + 0.5, col);
  }
  c.rectangle(x, y, x + 16, y + h, kBlack, false);
  c.text(fmt(format, hi), x + 22, y + 6, 0.0, 0.42);
  c.text(fmt(format, lo), x + 22, y + h, 0.0, 0.42);
}

}  // namespace

void writeResponsePlot(const std::string& path, const calib::ResponseCalibrationResult& r,
                       const std::array<float, 256>* reference) {
  // Top: the curves.
  XYChart chart;
  chart.title = "Inverse response from " + std::to_string(r.images_used) + " images";
  chart.x_label = "pixel value";
  chart.y_label = "irradiance x exposure";
  chart.x_lo = 0;
  chart.x_hi = 255;
  chart.y_lo = 0;
  chart.y_hi = 260;
  if (reference) {
    XYSeries ref{"reference", {}, kOrange, XYSeries::Style::Line, 5};
    for (int k = 0; k < 256; ++k)
      ref.points.emplace_back(k, (*reference)[static_cast<std::size_t>(k)]);
    chart.series.push_back(ref);
  }
  XYSeries curve{"written to pcalib.txt", {}, kBlue, XYSeries::Style::Line, 2};
  for (int k = 0; k < 256; ++k)
    curve.points.emplace_back(k, r.inverse_response[static_cast<std::size_t>(k)]);
  chart.series.push_back(curve);
  chart.notes.push_back("values " + std::to_string(r.first_observed) + ".." +
                        std::to_string(r.last_observed) + " observed");
  chart.notes.push_back(r.non_monotonic.empty()
                            ? std::string("estimate is monotonic")
                            : std::to_string(r.non_monotonic.size()) + " values decrease (red)");
  chart.notes.push_back(fmt("fit residual %.2f", r.rms_residual));

  // Bottom: the raw estimate per value and the reference against the written curve.
  XYChart diff;
  diff.title = "Difference to the written curve";
  diff.x_label = "pixel value";
  diff.y_label = "difference";
  diff.x_lo = 0;
  diff.x_hi = 255;
  diff.legend = XYChart::Legend::TopLeft;
  XYSeries raw{"estimate per value", {}, kGrey, XYSeries::Style::Dots, 2.0};
  XYSeries bad{"decreasing", {}, kRed, XYSeries::Style::Dots, 3.0};
  double span = 0.5;
  for (int k = 0; k < 256; ++k) {
    const double d =
        r.estimate[static_cast<std::size_t>(k)] - r.inverse_response[static_cast<std::size_t>(k)];
    raw.points.emplace_back(k, d);
    if (std::isfinite(d)) span = std::max(span, std::abs(d));
  }
  for (const int k : r.non_monotonic)
    bad.points.emplace_back(k, r.estimate[static_cast<std::size_t>(k)] -
                                   r.inverse_response[static_cast<std::size_t>(k)]);
  if (reference) {
    XYSeries ref{"reference", {}, kOrange, XYSeries::Style::Line, 2};
    for (int k = 0; k < 256; ++k) {
      const double d = (*reference)[static_cast<std::size_t>(k)] -
                       r.inverse_response[static_cast<std::size_t>(k)];
      ref.points.emplace_back(k, d);
      span = std::max(span, std::abs(d));
    }
    diff.series.push_back(ref);
  }
  diff.series.push_back(raw);
  if (!bad.points.empty()) diff.series.push_back(bad);
  diff.y_lo = -1.1 * span;
  diff.y_hi = 1.1 * span;

  PlotCanvas c(820, 860);
  drawXYChart(c, chart, 0, 0, c.width(), 580);
  drawXYChart(c, diff, 0, 580, c.width(), 280);
  c.writePng(path);
}

void writeVignettePlot(const std::string& path, const calib::VignetteCalibrationResult& r) {
  const ImageF& v = r.vignette;
  const int W = v.width(), H = v.height();
  // Left: the vignette as a heat map, scaled to 480 pixels wide.
  const int map_w = 480, map_h = std::max(1, static_cast<int>(std::lround(480.0 * H / W)));
  PlotCanvas c(map_w + 120 + 560, std::max(map_h + 110, 460));
  Image<Rgb> heat(W, H);
  const double lo = r.min_value;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) heat(x, y) = heatColour((v(x, y) - lo) / std::max(1.0 - lo, 1e-6));
  const int mx = 20, my = 50;
  c.image(heat.view(), mx, my, map_w, map_h);
  c.rectangle(mx, my, mx + map_w, my + map_h, kBlack, false);
  const double cx = mx + (r.centre.x() + 0.5) * map_w / W,
               cy = my + (r.centre.y() + 0.5) * map_h / H;
  c.line(cx - 8, cy, cx + 8, cy, kWhite, 2);
  c.line(cx, cy - 8, cx, cy + 8, kWhite, 2);
  c.text("Vignette V (" + std::to_string(W) + "x" + std::to_string(H) + "), + centre",
         mx + map_w / 2.0, 32, 0.5, 0.55);
  c.text(fmt("centre (%.1f, ", r.centre.x()) + fmt("%.1f)", r.centre.y()) +
             fmt(", min %.3f", r.min_value),
         mx + map_w / 2.0, my + map_h + 28, 0.5, 0.45);
  colourBar(c, mx + map_w + 15, my, map_h, lo, 1.0, "%.2f");

  // Right: radial profile, measured pixels (subsampled) against the model.
  XYChart chart;
  chart.title = "Radial profile";
  chart.x_label = "distance from the centre [px]";
  chart.y_label = "V";
  chart.y_hi = 1.05;
  chart.y_lo = std::max(0.0, lo - 0.1);
  chart.x_lo = 0;
  double rmax = 0;
  for (const double x : {0.0, W - 1.0})
    for (const double y : {0.0, H - 1.0})
      rmax = std::max(rmax, std::hypot(x - r.centre.x(), y - r.centre.y()));
  chart.x_hi = rmax * 1.02;
  XYSeries measured{"measured", {}, kGrey, XYSeries::Style::Dots, 1.2};
  const int step = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(W) * H / 4000.0)));
  for (int y = step / 2; y < H; y += step)
    for (int x = step / 2; x < W; x += step)
      measured.points.emplace_back(std::hypot(x - r.centre.x(), y - r.centre.y()),
                                   r.measured(x, y));
  XYSeries model{"fitted model", {}, kBlue, XYSeries::Style::Line, 2};
  for (int i = 0; i <= 200; ++i) {
    const double rad = rmax * i / 200.0, q = rad / r.radius_px, q2 = q * q;
    model.points.emplace_back(
        rad, r.scale * (1 + q2 * (r.coefficients[0] +
                                  q2 * (r.coefficients[1] + q2 * r.coefficients[2]))));
  }
  chart.series = {measured, model};
  chart.notes.push_back(fmt("fit residual %.2f %%", 100 * r.fit_rms));
  chart.notes.push_back(std::to_string(r.images_used) + " images");
  chart.legend = XYChart::Legend::BottomLeft;
  drawXYChart(c, chart, map_w + 120, 0, 560, c.height());
  c.writePng(path);
}

void writeCoveragePlot(const std::string& path, const calib::CameraCalibrationResult& r, int width,
                       int height) {
  const double scale = 640.0 / width;
  const int pw = 640, ph = std::max(1, static_cast<int>(std::lround(height * scale)));
  PlotCanvas c(pw + 130, ph + 90);
  const int ox = 20, oy = 45;
  c.rectangle(ox, oy, ox + pw, oy + ph, Rgb{245, 245, 245}, true);
  c.rectangle(ox, oy, ox + pw, oy + ph, kBlack, false);
  const double top = std::max(0.5, 3.0 * r.rms_px);
  for (std::size_t k = 0; k < r.corners.size(); ++k) {
    const double e = r.corner_errors_px[k];
    c.circle(ox + (r.corners[k].x() + 0.5) * scale, oy + (r.corners[k].y() + 0.5) * scale, 2.5,
             std::isfinite(e) ? heatColour(e / top) : kRed, true);
  }
  c.text("Corners of the " + std::to_string(r.used_views) + " used views (" +
             std::to_string(width) + "x" + std::to_string(height) + fmt("), RMS %.3f px", r.rms_px),
         ox + pw / 2.0, 30, 0.5, 0.55);
  c.text("colour: reprojection error [px]", ox + pw / 2.0, oy + ph + 30, 0.5, 0.45);
  colourBar(c, ox + pw + 15, oy, ph, 0.0, top, "%.2f");
  c.writePng(path);
}

}  // namespace ldsm::app
