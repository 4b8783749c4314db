// Weighted inverse-depth sums by pixel index (y * width + x) for the levels of a depth map canvas
// (frontend/depth_map_pyramid.h), in two forms with one interface:
// - PixelSums, for the few pixels of a level that have any: a window's points cover a few
//   percent of an image, and dilation adds their neighbours (some 14 000 cells at level 0 of a
//   1232x368 image where a dense plane holds 453 000). An open-addressing hash table, linear
//   probing, at most half full; a pixel without a cell reads as zero sums. Bounded by the plane
//   it replaces: past as many slots as the level has pixels it becomes that plane.
// - DensePixelSums, a plane of every pixel, for the coarse levels that dilation makes dense.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ldsm {

class PixelSums {
 public:
  struct Cell {
    float sum = 0.f;     ///< sum of weight * inverse depth
    float weight = 0.f;  ///< sum of weights; 0: unknown
    unsigned char from_map = 0;
  };

  /// An empty table with room for `cells` cells before it grows. With `pixels` (the level's
  /// pixel count, > 0) it never takes more slots than that: a table that would becomes a plane of
  /// one slot per pixel, indexed by the pixel (a window so dense that its points and their
  /// neighbours cover a quarter of the image and more).
  explicit PixelSums(std::size_t cells = 1024, std::size_t pixels = 0) : pixels_(pixels) {
    reserve(cells);
  }

  /// Forgets every cell; keeps the memory.
  void clear() {
    for (const std::uint32_t s : used_) slots_[s].pixel = kEmpty;
    used_.clear();
  }

  /// The cell of `pixel` (>= 0), or null when it has none.
  const Cell* find(int pixel) const {
    for (std::size_t s = slotOf(pixel);; s = (s + 1) & mask_) {
      if (slots_[s].pixel == pixel) return &slots_[s].cell;
      if (slots_[s].pixel == kEmpty) return nullptr;
    }
  }
  Cell* find(int pixel) {
    return const_cast<Cell*>(static_cast<const PixelSums&>(*this).find(pixel));
  }
  /// The cell of `pixel`, a zero one when it has none.
  Cell get(int pixel) const {
    const Cell* c = find(pixel);
    return c != nullptr ? *c : Cell();
  }
  float weight(int pixel) const {
    const Cell* c = find(pixel);
    return c != nullptr ? c->weight : 0.f;
  }
  float sum(int pixel) const {
    const Cell* c = find(pixel);
    return c != nullptr ? c->sum : 0.f;
  }

  /// The cell of `pixel` (>= 0), a zero one when it had none. Growing the table (when it would
  /// be more than half full; it then allocates) invalidates earlier cell pointers.
  Cell& insert(int pixel) {
    if (!direct_ && 2 * (used_.size() + 1) > slots_.size()) reserve(2 * slots_.size());
    std::size_t s = slotOf(pixel);
    for (; slots_[s].pixel != kEmpty; s = (s + 1) & mask_)
      if (slots_[s].pixel == pixel) return slots_[s].cell;
    slots_[s].pixel = pixel;
    slots_[s].cell = Cell();
    used_.push_back(static_cast<std::uint32_t>(s));
    return slots_[s].cell;
  }

  std::size_t size() const { return used_.size(); }
  std::size_t bytes() const {
    return slots_.capacity() * sizeof(Slot) + used_.capacity() * sizeof(std::uint32_t);
  }

 private:
  static constexpr int kEmpty = -1;
  struct Slot {
    int pixel = kEmpty;
    Cell cell;
  };

  std::size_t slotOf(int pixel) const {
    if (direct_) return static_cast<std::size_t>(pixel);  // never probes further
    // Fibonacci hashing: neighbouring pixels land far apart.
    return (static_cast<std::uint32_t>(pixel) * 2654435761u >> shift_) & mask_;
  }

  /// At least `cells` cells at most half full: a power-of-two number of slots, the cells kept.
  void reserve(std::size_t cells) {
    std::size_t n = 16;
    int bits = 4;
    while (n < 2 * cells) {
      n *= 2;
      ++bits;
    }
    if (direct_ || n <= slots_.size()) return;
    std::vector<Slot> old;
    old.swap(slots_);
    std::vector<std::uint32_t> old_used;
    old_used.swap(used_);
    if (pixels_ > 0 && n >= pixels_) {
      direct_ = true;  // slot = pixel
      n = pixels_;
    }
    slots_.assign(n, Slot());
    used_.reserve(direct_ ? n / 4 : n / 2);
    mask_ = n - 1;
    shift_ = 32 - bits;
    for (const std::uint32_t s : old_used) insert(old[s].pixel) = old[s].cell;
  }

  std::vector<Slot> slots_;
  std::vector<std::uint32_t> used_;  ///< the slots in use, in insertion order
  std::size_t mask_ = 0;
  int shift_ = 32;
  std::size_t pixels_ = 0;  ///< 0: no bound
  bool direct_ = false;     ///< one slot per pixel
};

/// Every pixel's sums (8 bytes per pixel), with PixelSums' interface.
class DensePixelSums {
 public:
  struct Cell {
    float sum = 0.f;
    float weight = 0.f;
  };

  explicit DensePixelSums(std::size_t pixels = 0) : cells_(pixels) {}

  /// Zeroes the cells of `pixels` (the only ones that can be non-zero).
  void clear(const std::vector<int>& pixels) {
    for (const int p : pixels) cells_[static_cast<std::size_t>(p)] = Cell();
  }
  const Cell* find(int pixel) const { return &cells_[static_cast<std::size_t>(pixel)]; }
  Cell get(int pixel) const { return cells_[static_cast<std::size_t>(pixel)]; }
  float weight(int pixel) const { return cells_[static_cast<std::size_t>(pixel)].weight; }
  float sum(int pixel) const { return cells_[static_cast<std::size_t>(pixel)].sum; }
  Cell& insert(int pixel) { return cells_[static_cast<std::size_t>(pixel)]; }
  std::size_t bytes() const { return cells_.capacity() * sizeof(Cell); }

 private:
  std::vector<Cell> cells_;
};

}  // namespace ldsm
