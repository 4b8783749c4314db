#include "plot_trajectory.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>

#include "ldsm/drivers/atomic_file.h"
#include "ldsm/error.h"
#include "plot_canvas.h"

namespace ldsm::app {

namespace {

const char* const kAxisNames[3] = {"x", "y", "z"};

// Everything both renderers need: which plane, where the data goes, where the ticks are.
struct Layout {
  int width = 960;
  int height = 800;
  int left = 80;
  int right = 30;
  int top = 50;
  int bottom = 60;
  int axis_h = 0;  // data axis drawn horizontally
  int axis_v = 1;  // data axis drawn vertically (upwards)
  double h_min = 0.0, h_max = 1.0, v_min = 0.0, v_max = 1.0;
  double px_per_m = 1.0;
  double tick = 1.0;
  int decimals = 0;
  double legend_x = 0.0, legend_y = 0.0;  // top-left corner of the legend box
  double legend_w = 190.0, legend_h = 0.0;

  int plotWidth() const { return width - left - right; }
  int plotHeight() const { return height - top - bottom; }
  double px(const Eigen::Vector3d& p) const { return left + (p(axis_h) - h_min) * px_per_m; }
  double py(const Eigen::Vector3d& p) const {
    return top + plotHeight() - (p(axis_v) - v_min) * px_per_m;
  }
  double hToPx(double h) const { return left + (h - h_min) * px_per_m; }
  double vToPx(double v) const { return top + plotHeight() - (v - v_min) * px_per_m; }
  std::vector<double> ticks(double lo, double hi) const {
    std::vector<double> t;
    for (double x = std::ceil(lo / tick) * tick; x <= hi + 1e-9 * tick; x += tick) {
      t.push_back(std::abs(x) < 1e-12 * tick ? 0.0 : x);
    }
    return t;
  }
  std::string label(double value) const {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.*f", decimals, value);
    return buf;
  }
};

// Puts the legend in the plot corner that hides the fewest points.
void placeLegend(Layout& L, const std::vector<PlotSeries>& series) {
  L.legend_h = 22.0 * (static_cast<double>(series.size()) + 2.0) + 8.0;
  const double x0 = L.left + 10.0, x1 = L.left + L.plotWidth() - L.legend_w - 10.0;
  const double y0 = L.top + 10.0, y1 = L.top + L.plotHeight() - L.legend_h - 10.0;
  const double corners[4][2] = {{x1, y0}, {x0, y0}, {x1, y1}, {x0, y1}};
  std::size_t best_count = std::numeric_limits<std::size_t>::max();
  for (const auto& c : corners) {
    std::size_t count = 0;
    for (const auto& s : series) {
      for (const auto& p : s.points) {
        const double x = L.px(p), y = L.py(p);
        if (x >= c[0] && x <= c[0] + L.legend_w && y >= c[1] && y <= c[1] + L.legend_h) ++count;
      }
    }
    if (count < best_count) {
      best_count = count;
      L.legend_x = c[0];
      L.legend_y = c[1];
    }
  }
}

Layout makeLayout(const std::vector<PlotSeries>& series) {
  Layout L;
  // Plane: the two axes of largest ground-truth extent, kept in x, y, z order.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : series.front().points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d extent =
      series.front().points.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(hi - lo);
  int smallest = 0;
  for (int k = 1; k < 3; ++k) {
    if (extent(k) < extent(smallest)) smallest = k;
  }
  L.axis_h = smallest == 0 ? 1 : 0;
  L.axis_v = smallest == 2 ? 1 : 2;

  // Bounds of every finite point on that plane.
  double h0 = std::numeric_limits<double>::infinity(), h1 = -h0, v0 = h0, v1 = -h0;
  for (const auto& s : series) {
    for (const auto& p : s.points) {
      if (!p.allFinite()) continue;
      h0 = std::min(h0, p(L.axis_h));
      h1 = std::max(h1, p(L.axis_h));
      v0 = std::min(v0, p(L.axis_v));
      v1 = std::max(v1, p(L.axis_v));
    }
  }
  if (!(h1 >= h0)) h0 = h1 = v0 = v1 = 0.0;
  double span = std::max({h1 - h0, v1 - v0, 1e-3});
  const double margin = 0.05 * span;
  h0 -= margin, h1 += margin, v0 -= margin, v1 += margin;
  // Equal scaling: pad the shorter range so that the data fill the plot area.
  L.px_per_m = std::min(L.plotWidth() / (h1 - h0), L.plotHeight() / (v1 - v0));
  const double hc = 0.5 * (h0 + h1), vc = 0.5 * (v0 + v1);
  L.h_min = hc - 0.5 * L.plotWidth() / L.px_per_m;
  L.h_max = hc + 0.5 * L.plotWidth() / L.px_per_m;
  L.v_min = vc - 0.5 * L.plotHeight() / L.px_per_m;
  L.v_max = vc + 0.5 * L.plotHeight() / L.px_per_m;
  span = std::max(L.h_max - L.h_min, L.v_max - L.v_min);
  L.tick = niceStep(span / 8.0);
  L.decimals = std::max(0, -static_cast<int>(std::floor(std::log10(L.tick) + 1e-9)));
  placeLegend(L, series);
  return L;
}

std::vector<Eigen::Vector3d> finitePoints(const PlotSeries& s) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : s.points) {
    if (p.allFinite()) out.push_back(p);
  }
  return out;
}

// The first series (ground truth) is drawn wider so that it shows beside a close estimate.
int lineWidth(std::size_t series_index) {
  return series_index == 0 ? 4 : 2;
}

std::string axisLabel(int axis) {
  return std::string(kAxisNames[axis]) + " [m]";
}

// ---- PNG -----------------------------------------------------------------------------------

std::string renderPng(const Layout& L, const std::vector<PlotSeries>& series,
                      const std::string& title) {
  PlotCanvas c(L.width, L.height);
  const double x0 = L.left, x1 = L.left + L.plotWidth(), y0 = L.top, y1 = L.top + L.plotHeight();
  for (double t : L.ticks(L.h_min, L.h_max)) {
    const double x = L.hToPx(t);
    c.line(x, y0, x, y1, kGrid);
    c.line(x, y1, x, y1 + 5, kBlack);
    c.text(L.label(t), x, y1 + 20, 0.5);
  }
  for (double t : L.ticks(L.v_min, L.v_max)) {
    const double y = L.vToPx(t);
    c.line(x0, y, x1, y, kGrid);
    c.line(x0 - 5, y, x0, y, kBlack);
    c.text(L.label(t), x0 - 8, y + 5, 1.0);
  }
  c.rectangle(x0, y0, x1, y1, kBlack, false);
  c.text(axisLabel(L.axis_h), 0.5 * (x0 + x1), L.height - 15, 0.5, 0.55);
  c.text(axisLabel(L.axis_v), x0, y0 - 10, 0.5, 0.55);
  c.text(title, 0.5 * (x0 + x1), 28, 0.5, 0.6);

  for (std::size_t i = 0; i < series.size(); ++i) {
    std::vector<Eigen::Vector2d> pts;
    for (const auto& p : finitePoints(series[i])) pts.emplace_back(L.px(p), L.py(p));
    c.polyline(pts, series[i].rgb, lineWidth(i));
  }
  for (const auto& s : series) {
    const auto pts = finitePoints(s);
    if (pts.empty()) continue;
    c.marker(L.px(pts.front()), L.py(pts.front()), false, s.rgb);
    c.marker(L.px(pts.back()), L.py(pts.back()), true, s.rgb);
  }

  // Legend in the corner that hides the fewest points.
  const double lx = L.legend_x, ly = L.legend_y;
  c.rectangle(lx, ly, lx + L.legend_w, ly + L.legend_h, kWhite, true);
  c.rectangle(lx, ly, lx + L.legend_w, ly + L.legend_h, Rgb{160, 160, 160}, false);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const double y = ly + 19 + 22 * static_cast<double>(i);
    c.line(lx + 10, y - 4, lx + 40, y - 4, series[i].rgb, lineWidth(i));
    c.text(series[i].label, lx + 50, y, 0.0);
  }
  const double ys = ly + 19 + 22 * static_cast<double>(series.size());
  const Rgb grey{90, 90, 90};
  c.marker(lx + 25, ys - 4, false, grey);
  c.text("start", lx + 50, ys, 0.0);
  c.marker(lx + 25, ys + 18, true, grey);
  c.text("end", lx + 50, ys + 22, 0.0);
  return c.encodePng();
}

// ---- SVG -----------------------------------------------------------------------------------

std::string escapeXml(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", v);
  return buf;
}

std::string rgbCss(const std::array<std::uint8_t, 3>& c) {
  return "rgb(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) +
         ")";
}

std::string svgText(const std::string& s, double x, double y, const char* anchor, int size = 12) {
  return "<text x=\"" + fmt(x) + "\" y=\"" + fmt(y) + "\" text-anchor=\"" + anchor +
         "\" font-size=\"" + std::to_string(size) + "\">" + escapeXml(s) + "</text>\n";
}

std::string svgMarker(double x, double y, bool square, const std::string& colour) {
  if (square) {
    return "<rect x=\"" + fmt(x - 5) + "\" y=\"" + fmt(y - 5) +
           "\" width=\"10\" height=\"10\" fill=\"" + colour +
           "\" stroke=\"white\" stroke-width=\"2\"/>\n";
  }
  return "<circle cx=\"" + fmt(x) + "\" cy=\"" + fmt(y) + "\" r=\"6\" fill=\"" + colour +
         "\" stroke=\"white\" stroke-width=\"2\"/>\n";
}

std::string line(double xa, double ya, double xb, double yb, const char* stroke) {
  return "<line x1=\"" + fmt(xa) + "\" y1=\"" + fmt(ya) + "\" x2=\"" + fmt(xb) + "\" y2=\"" +
         fmt(yb) + "\" stroke=\"" + stroke + "\"/>\n";
}

std::string renderSvg(const Layout& L, const std::vector<PlotSeries>& series,
                      const std::string& title) {
  const double x0 = L.left, x1 = L.left + L.plotWidth(), y0 = L.top, y1 = L.top + L.plotHeight();
  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  s += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(L.width) +
       "\" height=\"" + std::to_string(L.height) + "\" viewBox=\"0 0 " + std::to_string(L.width) +
       " " + std::to_string(L.height) + "\" font-family=\"sans-serif\">\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (double t : L.ticks(L.h_min, L.h_max)) {
    const double x = L.hToPx(t);
    s += line(x, y0, x, y1, "#e1e1e1") + line(x, y1, x, y1 + 5, "black");
    s += svgText(L.label(t), x, y1 + 20, "middle");
  }
  for (double t : L.ticks(L.v_min, L.v_max)) {
    const double y = L.vToPx(t);
    s += line(x0, y, x1, y, "#e1e1e1") + line(x0 - 5, y, x0, y, "black");
    s += svgText(L.label(t), x0 - 8, y + 4, "end");
  }
  s += "<rect x=\"" + fmt(x0) + "\" y=\"" + fmt(y0) + "\" width=\"" + fmt(x1 - x0) +
       "\" height=\"" + fmt(y1 - y0) + "\" fill=\"none\" stroke=\"black\"/>\n";
  s += svgText(axisLabel(L.axis_h), 0.5 * (x0 + x1), L.height - 15, "middle", 14);
  s += svgText(axisLabel(L.axis_v), x0, y0 - 10, "middle", 14);
  s += svgText(title, 0.5 * (x0 + x1), 28, "middle", 16);

  for (std::size_t i = 0; i < series.size(); ++i) {
    s += "<polyline fill=\"none\" stroke=\"" + rgbCss(series[i].rgb) + "\" stroke-width=\"" +
         std::to_string(lineWidth(i)) + "\" stroke-linejoin=\"round\" points=\"";
    for (const auto& p : finitePoints(series[i])) s += fmt(L.px(p)) + "," + fmt(L.py(p)) + " ";
    s += "\"/>\n";
  }
  for (const auto& ser : series) {
    const auto pts = finitePoints(ser);
    if (pts.empty()) continue;
    s += svgMarker(L.px(pts.front()), L.py(pts.front()), false, rgbCss(ser.rgb));
    s += svgMarker(L.px(pts.back()), L.py(pts.back()), true, rgbCss(ser.rgb));
  }

  const double lx = L.legend_x, ly = L.legend_y;
  s += "<rect x=\"" + fmt(lx) + "\" y=\"" + fmt(ly) + "\" width=\"" + fmt(L.legend_w) +
       "\" height=\"" + fmt(L.legend_h) + "\" fill=\"white\" stroke=\"#a0a0a0\"/>\n";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const double y = ly + 19 + 22 * static_cast<double>(i);
    s += "<line x1=\"" + fmt(lx + 10) + "\" y1=\"" + fmt(y - 4) + "\" x2=\"" + fmt(lx + 40) +
         "\" y2=\"" + fmt(y - 4) + "\" stroke=\"" + rgbCss(series[i].rgb) + "\" stroke-width=\"" +
         std::to_string(lineWidth(i)) + "\"/>\n";
    s += svgText(series[i].label, lx + 50, y, "start");
  }
  const double ys = ly + 19 + 22 * static_cast<double>(series.size());
  s += svgMarker(lx + 25, ys - 4, false, "rgb(90,90,90)") + svgText("start", lx + 50, ys, "start");
  s += svgMarker(lx + 25, ys + 18, true, "rgb(90,90,90)") +
       svgText("end", lx + 50, ys + 22, "start");
  s += "</svg>\n";
  return s;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == suffix;
}

}  // namespace

void writeTopViewPlot(const std::string& path, const std::vector<PlotSeries>& series,
                      const std::string& title) {
  const bool png = endsWith(path, ".png");
  if (!png && !endsWith(path, ".svg")) {
    throw ConfigError("plot file '" + path + "' must end in .png or .svg");
  }
  if (series.empty()) throw Error("plot: nothing to draw");
  const Layout layout = makeLayout(series);
  drivers::writeFileAtomically(
      path, png ? renderPng(layout, series, title) : renderSvg(layout, series, title));
}

}  // namespace ldsm::app
