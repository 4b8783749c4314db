// The map store's keyframe pose records by id, in fixed-size blocks shared copy-on-write with the
// snapshots the store publishes. A run keeps a record for every keyframe it ever made (frames were
// tracked against each), so a flat copy per publish would grow with the length of the run (an
// hour of the desk soak makes 17 000 keyframes: 1.6 MB copied for every keyframe). Here a copy of
// the table copies only its block pointers, and a change copies only the block it touches: the
// memory a snapshot adds and the time to publish one stay the same however long the run.
//
// Not thread-safe for writers (the store changes its table under its mutex); a copy handed to
// readers is never changed again, and a block is changed in place only while no copy shares it.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

#include "model/map_records.h"

namespace ldsm {

class KeyframeTable {
 public:
  static constexpr std::size_t kBlockSize = 128;

  /// Ids 0 .. size() - 1 can be read; a record with id -1 is no keyframe.
  std::size_t size() const { return size_; }
  /// Records of keyframes (id >= 0).
  std::size_t count() const { return count_; }
  bool has(int id) const {
    return id >= 0 && static_cast<std::size_t>(id) < size_ && (*this)[id].id >= 0;
  }
  /// The record at `id` (0 <= id < size()).
  const KeyframeRecord& operator[](int id) const {
    const auto i = static_cast<std::size_t>(id);
    return (*blocks_[i / kBlockSize])[i % kBlockSize];
  }

  /// Stores a keyframe's record at its id, growing the table when needed; a record with a
  /// negative id (no keyframe) is not stored.
  void set(const KeyframeRecord& record) {
    if (record.id < 0) return;
    const auto i = static_cast<std::size_t>(record.id);
    if (i >= size_) grow(i + 1);
    KeyframeRecord& slot = edit(record.id);
    if (slot.id < 0) ++count_;
    slot = record;
  }
  /// The record at `id` (0 <= id < size()) to change in place, its block copied first when a copy
  /// of the table shares it. The caller keeps its id (a keyframe stays a keyframe).
  KeyframeRecord& edit(int id) {
    const auto i = static_cast<std::size_t>(id);
    std::shared_ptr<Block>& block = blocks_[i / kBlockSize];
    if (block.use_count() != 1) {
      block = std::make_shared<Block>(*block);
    } else {
      // The last copy that shared the block released it; its reads happened before.
      std::atomic_thread_fence(std::memory_order_acquire);
    }
    return (*block)[i % kBlockSize];
  }

  /// Calls f(record) for every keyframe, by increasing id.
  template <typename F>
  void forEach(F&& f) const {
    for (std::size_t i = 0; i < size_; ++i) {
      const KeyframeRecord& r = (*blocks_[i / kBlockSize])[i % kBlockSize];
      if (r.id >= 0) f(r);
    }
  }

 private:
  using Block = std::array<KeyframeRecord, kBlockSize>;

  void grow(std::size_t n) {
    while (blocks_.size() * kBlockSize < n) {
      auto block = std::make_shared<Block>();
      for (KeyframeRecord& r : *block) r.id = -1;
      blocks_.push_back(std::move(block));
    }
    size_ = n;
  }

  std::vector<std::shared_ptr<Block>> blocks_;
  std::size_t size_ = 0;
  std::size_t count_ = 0;
};

}  // namespace ldsm
