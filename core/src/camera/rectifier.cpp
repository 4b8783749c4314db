#include "ldsm/camera/rectifier.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "camera/remap_bilinear.h"
#include "camera_common.h"
#include "ldsm/error.h"

namespace ldsm {

Rectifier::Rectifier(const GeometricCalibration& calibration)
    : input_(makeCameraModel(calibration.input)),
      output_(computeOutputIntrinsics(*input_, calibration.output)) {
  const CameraIntrinsics& in = input_->intrinsics();
  identity_ = calibration.output.mode == OutputMode::None && output_.width == in.width &&
              output_.height == in.height;
  map_x_.resize(output_.width, output_.height);
  map_y_.resize(output_.width, output_.height);
  num_valid_ = 0;
  Eigen::Vector2d px;
  for (int v = 0; v < output_.height; ++v) {
    float* mx = map_x_.row(v);
    float* my = map_y_.row(v);
    const double y = (v - output_.cy) / output_.fy;
    for (int u = 0; u < output_.width; ++u) {
      if (camera_detail::sampleInput(*input_, (u - output_.cx) / output_.fx, y, &px)) {
        mx[u] = static_cast<float>(px.x());
        my[u] = static_cast<float>(px.y());
        ++num_valid_;
      } else {
        mx[u] = -1.0f;
        my[u] = -1.0f;
      }
    }
  }
  if (num_valid_ == 0)
    throw InputError("rectification: no pixel of the " + std::to_string(output_.width) + "x" +
                     std::to_string(output_.height) +
                     " output image sees a valid input pixel (check the output intrinsics)");
  keepSeparableTable();
}

void Rectifier::keepSeparableTable() {
  const int w = output_.width, h = output_.height;
  // Each column's input x and each row's input y, from the first valid pixel that has them.
  std::vector<float> column_x(static_cast<std::size_t>(w), -1.0f);
  std::vector<float> row_y(static_cast<std::size_t>(h), -1.0f);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      if (map_x_(u, v) < 0.0f) continue;
      if (column_x[u] < 0.0f) column_x[u] = map_x_(u, v);
      if (row_y[v] < 0.0f) row_y[v] = map_y_(u, v);
    }
  // Separable when every pixel is exactly what its column and row say, and a pixel sees no input
  // exactly when its column or its row sees none.
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const bool valid = column_x[u] >= 0.0f && row_y[v] >= 0.0f;
      if (valid ? (map_x_(u, v) != column_x[u] || map_y_(u, v) != row_y[v])
                : !(map_x_(u, v) < 0.0f))
        return;
    }
  separable_ = true;
  simd::SeparableColumns columns = simd::separableColumns(column_x, input_->width());
  column_x0_ = std::move(columns.x0);
  column_ax_ = std::move(columns.ax);
  column_x_ = std::move(column_x);
  row_y_ = std::move(row_y);
  map_x_ = ImageF();
  map_y_ = ImageF();
}

Eigen::Vector2f Rectifier::inputPixel(int x, int y) const {
  if (!separable_) return {map_x_(x, y), map_y_(x, y)};
  if (column_x_[x] < 0.0f || row_y_[y] < 0.0f) return {-1.0f, -1.0f};
  return {column_x_[x], row_y_[y]};
}

std::size_t Rectifier::tableBytes() const {
  return (map_x_.capacity() + map_y_.capacity() + column_x_.capacity() + row_y_.capacity() +
          column_ax_.capacity()) *
             sizeof(float) +
         column_x0_.capacity() * sizeof(std::int32_t);
}

template <typename T>
void Rectifier::checkInput(ImageView<const T> in) const {
  const int w = input_->width(), h = input_->height();
  if (in.width != w || in.height != h || in.data == nullptr)
    throw InputError("rectification: input image is " + std::to_string(in.width) + "x" +
                     std::to_string(in.height) + " but the calibration is for " +
                     std::to_string(w) + "x" + std::to_string(h));
}

template <typename T>
void Rectifier::remapRow(ImageView<const T> in, int v, float* dst, float invalid_value) const {
  if (identity_) {
    const T* src = in.row(v);
    for (int x = 0; x < output_.width; ++x) dst[x] = static_cast<float>(src[x]);
    return;
  }
  const simd::RemapInput<T> input{in.data, in.stride, in.width, in.height};
  if (separable_) {
    if (row_y_[v] < 0.0f) {
      std::fill(dst, dst + output_.width, invalid_value);
      return;
    }
    std::int32_t y0;
    float ay;
    simd::clampedCell(row_y_[v], in.height, y0, ay);
    simd::remapSeparableRow<simd::Vec4>(input, column_x0_.data(), column_ax_.data(), y0, ay,
                                        output_.width, invalid_value, dst);
    return;
  }
  simd::remapRow<simd::Vec4>(input, map_x_.row(v), map_y_.row(v), output_.width, invalid_value,
                             dst);
}

template <typename T>
void Rectifier::remap(ImageView<const T> in, ImageF& out, float invalid_value) const {
  checkInput(in);
  out.resize(output_.width, output_.height);
  for (int v = 0; v < output_.height; ++v) remapRow(in, v, out.row(v), invalid_value);
}

void Rectifier::rectify(ImageView<const std::uint8_t> in, ImageF& out, float invalid_value) const {
  remap(in, out, invalid_value);
}

void Rectifier::rectify(ImageView<const float> in, ImageF& out, float invalid_value) const {
  remap(in, out, invalid_value);
}

namespace {

void checkOutputRow(int v, int height) {
  if (v < 0 || v >= height)
    throw InputError("rectification: row " + std::to_string(v) + " is not an output row (0-" +
                     std::to_string(height - 1) + ")");
}

}  // namespace

void Rectifier::rectifyRow(ImageView<const std::uint8_t> in, int v, float* out,
                           float invalid_value) const {
  checkInput(in);
  checkOutputRow(v, output_.height);
  remapRow(in, v, out, invalid_value);
}

void Rectifier::rectifyRow(ImageView<const float> in, int v, float* out,
                           float invalid_value) const {
  checkInput(in);
  checkOutputRow(v, output_.height);
  remapRow(in, v, out, invalid_value);
}

}  // namespace ldsm
