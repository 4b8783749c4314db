#include "plot_canvas.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/atomic_file.h"

namespace ldsm::app {
namespace {

constexpr int kShift = 4;  // sub-pixel bits for anti-aliased drawing

cv::Point sub(double x, double y) {
  return {static_cast<int>(std::lround(x * (1 << kShift))),
          static_cast<int>(std::lround(y * (1 << kShift)))};
}

cv::Scalar bgr(const Rgb& rgb) {
  return cv::Scalar(rgb[2], rgb[1], rgb[0]);
}

}  // namespace

double niceStep(double raw) {
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10.0 * p;
}

LinearAxis LinearAxis::make(double lo, double hi, double p0, double p1, int ticks) {
  LinearAxis a;
  if (!(hi > lo)) hi = lo + 1.0;
  a.lo = lo;
  a.hi = hi;
  a.p0 = p0;
  a.p1 = p1;
  a.step = niceStep((hi - lo) / std::max(ticks, 1));
  // niceStep rounds up (22 -> 50): step down (50 -> 20 -> 10 -> 5) while that leaves too few.
  while ((hi - lo) / a.step < 0.6 * ticks) {
    const double p = std::pow(10.0, std::floor(std::log10(a.step) + 1e-9));
    const double m = a.step / p;
    a.step = m > 4 ? 2 * p : (m > 1.5 ? p : 0.5 * p);
  }
  a.decimals = std::max(0, -static_cast<int>(std::floor(std::log10(a.step) + 1e-9)));
  return a;
}

std::vector<double> LinearAxis::ticks() const {
  std::vector<double> t;
  for (double x = std::ceil(lo / step) * step; x <= hi + 1e-9 * step; x += step)
    t.push_back(std::abs(x) < 1e-12 * step ? 0.0 : x);
  return t;
}

std::string LinearAxis::label(double v) const {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

PlotCanvas::PlotCanvas(int width, int height)
    : img_(height, width, CV_8UC3, cv::Scalar(255, 255, 255)) {}

void PlotCanvas::line(double x0, double y0, double x1, double y1, const Rgb& colour,
                      int thickness) {
  cv::line(img_, sub(x0, y0), sub(x1, y1), bgr(colour), thickness, cv::LINE_AA, kShift);
}

void PlotCanvas::polyline(const std::vector<Eigen::Vector2d>& points, const Rgb& colour,
                          int thickness) {
  std::vector<cv::Point> pts;
  for (const auto& p : points) pts.push_back(sub(p.x(), p.y()));
  cv::polylines(img_, pts, false, bgr(colour), thickness, cv::LINE_AA, kShift);
}

void PlotCanvas::rectangle(double x0, double y0, double x1, double y1, const Rgb& colour,
                           bool filled, int thickness) {
  cv::rectangle(img_, sub(x0, y0), sub(x1, y1), bgr(colour), filled ? cv::FILLED : thickness,
                cv::LINE_AA, kShift);
}

void PlotCanvas::circle(double x, double y, double radius, const Rgb& colour, bool filled) {
  cv::circle(img_, sub(x, y), static_cast<int>(std::lround(radius * (1 << kShift))), bgr(colour),
             filled ? cv::FILLED : 1, cv::LINE_AA, kShift);
}

void PlotCanvas::marker(double x, double y, bool square, const Rgb& colour) {
  if (square) {
    rectangle(x - 7, y - 7, x + 7, y + 7, kWhite, true);
    rectangle(x - 5, y - 5, x + 5, y + 5, colour, true);
  } else {
    circle(x, y, 8, kWhite, true);
    circle(x, y, 6, colour, true);
  }
}

void PlotCanvas::text(const std::string& s, double x, double y, double align, double size,
                      const Rgb& colour) {
  int baseline = 0;
  const cv::Size ts = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, size, 1, &baseline);
  cv::putText(img_, s, cv::Point(static_cast<int>(x - align * ts.width), static_cast<int>(y)),
              cv::FONT_HERSHEY_SIMPLEX, size, bgr(colour), 1, cv::LINE_AA);
}

void PlotCanvas::verticalText(const std::string& s, double x, double y, double size) {
  int baseline = 0;
  const cv::Size ts = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, size, 1, &baseline);
  cv::Mat patch(ts.height + baseline + 4, ts.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(patch, s, cv::Point(2, ts.height + 2), cv::FONT_HERSHEY_SIMPLEX, size,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(patch, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int x0 = static_cast<int>(x - turned.cols / 2.0),
            y0 = static_cast<int>(y - turned.rows / 2.0);
  const cv::Rect r =
      cv::Rect(x0, y0, turned.cols, turned.rows) & cv::Rect(0, 0, img_.cols, img_.rows);
  if (r.area() > 0) turned(cv::Rect(r.x - x0, r.y - y0, r.width, r.height)).copyTo(img_(r));
}

void PlotCanvas::image(const ImageView<const Rgb>& image, int x, int y, int w, int h) {
  if (image.empty() || w <= 0 || h <= 0) return;
  for (int v = 0; v < h; ++v) {
    const int py = y + v;
    if (py < 0 || py >= img_.rows) continue;
    const int sy = std::min(image.height - 1, v * image.height / h);
    auto* out = img_.ptr<cv::Vec3b>(py);
    for (int u = 0; u < w; ++u) {
      const int px = x + u;
      if (px < 0 || px >= img_.cols) continue;
      const Rgb& c = image(std::min(image.width - 1, u * image.width / w), sy);
      out[px] = cv::Vec3b(c[2], c[1], c[0]);
    }
  }
}

std::string PlotCanvas::encodePng() const {
  cv::Mat rgb;
  cv::cvtColor(img_, rgb, cv::COLOR_BGR2RGB);  // drawn in OpenCV's BGR order
  const ImageView<const calib::Rgb8> view(reinterpret_cast<const calib::Rgb8*>(rgb.ptr()), rgb.cols,
                                          rgb.rows, static_cast<std::ptrdiff_t>(rgb.step1() / 3));
  calib::PngWriteOptions options;
  options.compression_level = 9;  // plots are small: the smallest file is worth the time
  const std::vector<unsigned char> buf = calib::encodePng(view, options);
  return std::string(buf.begin(), buf.end());
}

void PlotCanvas::writePng(const std::string& path) const {
  drivers::writeFileAtomically(path, encodePng());
}

Rgb heatColour(double t) {
  // Dark blue, blue, teal, green, yellow: increasing lightness, readable in grey too.
  static constexpr double kStops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const double f = t - i;
  Rgb c{};
  for (int k = 0; k < 3; ++k)
    c[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(
        std::lround(kStops[i][k] + f * (kStops[i + 1][k] - kStops[i][k])));
  return c;
}

}  // namespace ldsm::app
