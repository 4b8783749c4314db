// Images: an owning, 32-byte aligned buffer (Image<T>) and a non-owning view (ImageView<T>).
// Strides are in elements. Image::resize() reuses its buffer when the size does not grow, so a
// preallocated image never touches the heap again for frames of the same size.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>

namespace ldsm {

template <typename T>
struct ImageView {
  T* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  ///< elements between the starts of two rows

  ImageView() = default;
  ImageView(T* d, int w, int h, std::ptrdiff_t s) : data(d), width(w), height(h), stride(s) {}
  ImageView(T* d, int w, int h) : ImageView(d, w, h, w) {}

  bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
  T* row(int y) const { return data + y * stride; }
  T& operator()(int x, int y) const { return data[y * stride + x]; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  operator ImageView<const T>() const { return {data, width, height, stride}; }
};

template <typename T>
class Image {
 public:
  static constexpr std::size_t kAlignment = 32;

  Image() = default;
  Image(int width, int height) { resize(width, height); }
  Image(int width, int height, T fill) {
    resize(width, height);
    this->fill(fill);
  }
  Image(const Image& o) { copyFrom(o.view()); }
  Image& operator=(const Image& o) {
    if (this != &o) copyFrom(o.view());
    return *this;
  }
  Image(Image&& o) noexcept { swap(o); }
  Image& operator=(Image&& o) noexcept {
    swap(o);
    return *this;
  }
  ~Image() = default;

  /// Resizes to width x height (contents undefined). Allocates only when the capacity grows.
  void resize(int width, int height) {
    assert(width >= 0 && height >= 0);
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (n > capacity_) {
      const std::size_t bytes = ((n * sizeof(T) + kAlignment - 1) / kAlignment) * kAlignment;
      void* p = std::aligned_alloc(kAlignment, bytes);
      if (p == nullptr) throw std::bad_alloc();
      data_.reset(static_cast<T*>(p));
      capacity_ = n;
    }
    width_ = width;
    height_ = height;
  }
  void fill(T v) {
    for (std::size_t i = 0, n = size(); i < n; ++i) data_.get()[i] = v;
  }
  /// Copies a view of the same element type, resizing as needed (stride may differ).
  void copyFrom(ImageView<const T> v) {
    resize(v.width, v.height);
    for (int y = 0; y < v.height; ++y)
      std::memcpy(data_.get() + static_cast<std::ptrdiff_t>(y) * width_, v.row(y),
                  sizeof(T) * static_cast<std::size_t>(v.width));
  }
  void swap(Image& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(width_, o.width_);
    std::swap(height_, o.height_);
    std::swap(capacity_, o.capacity_);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t size() const { return static_cast<std::size_t>(width_) * height_; }
  std::size_t capacity() const { return capacity_; }
  bool empty() const { return size() == 0; }
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  T* row(int y) { return data_.get() + static_cast<std::ptrdiff_t>(y) * width_; }
  const T* row(int y) const { return data_.get() + static_cast<std::ptrdiff_t>(y) * width_; }
  T& operator()(int x, int y) { return row(y)[x]; }
  const T& operator()(int x, int y) const { return row(y)[x]; }

  ImageView<T> view() { return {data_.get(), width_, height_, width_}; }
  ImageView<const T> view() const { return {data_.get(), width_, height_, width_}; }

 private:
  struct FreeDeleter {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T, FreeDeleter> data_;
  int width_ = 0;
  int height_ = 0;
  std::size_t capacity_ = 0;
};

using ImageU8 = Image<std::uint8_t>;
using ImageU16 = Image<std::uint16_t>;
using ImageF = Image<float>;

}  // namespace ldsm
