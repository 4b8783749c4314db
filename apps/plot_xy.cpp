#include "plot_xy.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldsm::app {
namespace {

constexpr int kLeft = 70, kRight = 20, kTop = 40, kBottom = 55;

void dataRange(const XYChart& chart, int axis, double& lo, double& hi) {
  if (hi > lo) return;
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (const auto& s : chart.series)
    for (const auto& p : s.points)
      if (p.allFinite()) {
        lo = std::min(lo, p(axis));
        hi = std::max(hi, p(axis));
      }
  if (!(hi >= lo)) lo = 0, hi = 1;
  const double margin = std::max(0.04 * (hi - lo), 1e-9);
  lo -= margin;
  hi += margin;
}

}  // namespace

void drawXYChart(PlotCanvas& c, const XYChart& chart, int x, int y, int width, int height) {
  double xlo = chart.x_lo, xhi = chart.x_hi, ylo = chart.y_lo, yhi = chart.y_hi;
  dataRange(chart, 0, xlo, xhi);
  dataRange(chart, 1, ylo, yhi);
  const double x0 = x + kLeft, x1 = x + width - kRight, y0 = y + kTop, y1 = y + height - kBottom;
  const LinearAxis ax = LinearAxis::make(xlo, xhi, x0, x1, std::max(2, (width - 90) / 70));
  const LinearAxis ay = LinearAxis::make(ylo, yhi, y1, y0, std::max(2, (height - 95) / 45));

  for (const double t : ax.ticks()) {
    const double px = ax.toPx(t);
    c.line(px, y0, px, y1, kGrid);
    c.line(px, y1, px, y1 + 5, kBlack);
    c.text(ax.label(t), px, y1 + 20, 0.5, 0.42);
  }
  for (const double t : ay.ticks()) {
    const double py = ay.toPx(t);
    c.line(x0, py, x1, py, kGrid);
    c.line(x0 - 5, py, x0, py, kBlack);
    c.text(ay.label(t), x0 - 8, py + 5, 1.0, 0.42);
  }
  c.rectangle(x0, y0, x1, y1, kBlack, false);
  c.text(chart.title, 0.5 * (x0 + x1), y + 25, 0.5, 0.55);
  c.text(chart.x_label, 0.5 * (x0 + x1), y + height - 12, 0.5, 0.5);
  c.verticalText(chart.y_label, x + 14, 0.5 * (y0 + y1), 0.5);

  auto inside = [&](const Eigen::Vector2d& p) {
    return p.allFinite() && p.x() >= xlo && p.x() <= xhi && p.y() >= ylo && p.y() <= yhi;
  };
  for (const auto& s : chart.series) {
    if (s.style == XYSeries::Style::Dots) {
      for (const auto& p : s.points)
        if (inside(p)) c.circle(ax.toPx(p.x()), ay.toPx(p.y()), s.size, s.rgb, true);
      continue;
    }
    std::vector<Eigen::Vector2d> run;
    for (std::size_t i = 0; i <= s.points.size(); ++i) {
      if (i < s.points.size() && inside(s.points[i])) {
        run.emplace_back(ax.toPx(s.points[i].x()), ay.toPx(s.points[i].y()));
        continue;
      }
      if (run.size() > 1) c.polyline(run, s.rgb, static_cast<int>(std::lround(s.size)));
      run.clear();
    }
  }

  // Legend and notes.
  int entries = 0;
  for (const auto& s : chart.series) entries += !s.label.empty();
  if (entries == 0 && chart.notes.empty()) return;
  const double lw = 230, lh = 20.0 * (entries + static_cast<double>(chart.notes.size())) + 10;
  const bool right =
      chart.legend == XYChart::Legend::TopRight || chart.legend == XYChart::Legend::BottomRight;
  const bool bottom =
      chart.legend == XYChart::Legend::BottomLeft || chart.legend == XYChart::Legend::BottomRight;
  const double lx = right ? x1 - lw - 10 : x0 + 10;
  const double ly = bottom ? y1 - lh - 10 : y0 + 10;
  c.rectangle(lx, ly, lx + lw, ly + lh, kWhite, true);
  c.rectangle(lx, ly, lx + lw, ly + lh, Rgb{160, 160, 160}, false);
  double ty = ly + 20;
  for (const auto& s : chart.series) {
    if (s.label.empty()) continue;
    if (s.style == XYSeries::Style::Dots)
      c.circle(lx + 22, ty - 5, std::max(2.5, s.size), s.rgb, true);
    else
      c.line(lx + 8, ty - 5, lx + 36, ty - 5, s.rgb, static_cast<int>(std::lround(s.size)));
    c.text(s.label, lx + 44, ty, 0.0, 0.42);
    ty += 20;
  }
  for (const auto& n : chart.notes) {
    c.text(n, lx + 8, ty, 0.0, 0.42);
    ty += 20;
  }
}

}  // namespace ldsm::app
