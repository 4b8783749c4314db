// An append-only log with one writer and any number of readers that never wait: records go into
// fixed-size chunks that never move, and a record becomes visible to readers when the published
// count passes it (release on the writer's side, acquire on the readers'). The directory of chunk
// pointers is allocated at construction and never moves either, so a reader needs no lock at
// all, and the writer never waits for a reader (which a mutex around a std::vector would make it
// do while the reader copies). The writer allocates a chunk when it enters one (reserve() ahead of
// time keeps it from allocating); a record, once written, is never changed.
//
// A bounded history: releaseBefore(n) frees the chunks that hold only records before n; the
// indices of the records after them do not change. The log does not know who reads what, so its
// owner must keep readers away from the released records (MapStore takes a lock its readers take;
// the writer never touches a record again once written).
//
// Threads: push() and reserve() from one writer thread; size(), first(), operator[] and forEach()
// from any thread; releaseBefore() from any one thread at a time, with the caveat above.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <string>

#include "ldsm/error.h"

namespace ldsm::concurrency {

template <typename T, std::size_t kChunkSize = 4096>
class AppendOnlyLog {
  static_assert(kChunkSize > 0 && (kChunkSize & (kChunkSize - 1)) == 0,
                "the chunk size is a power of two");

 public:
  /// Holds up to max_chunks * kChunkSize records.
  explicit AppendOnlyLog(std::size_t max_chunks = 16384)
      : max_chunks_(max_chunks), chunks_(new std::atomic<T*>[max_chunks]) {
    for (std::size_t i = 0; i < max_chunks_; ++i) chunks_[i].store(nullptr);
  }
  ~AppendOnlyLog() {
    for (std::size_t i = 0; i < max_chunks_; ++i) delete[] chunks_[i].load();
  }
  AppendOnlyLog(const AppendOnlyLog&) = delete;
  AppendOnlyLog& operator=(const AppendOnlyLog&) = delete;

  std::size_t capacity() const { return max_chunks_ * kChunkSize; }

  /// Writer: appends a record. Throws Error (and changes nothing) when the log is full.
  void push(const T& value) {
    const std::size_t n = count_.load(std::memory_order_relaxed);
    T* chunk = ensureChunk(n / kChunkSize);
    chunk[n % kChunkSize] = value;
    count_.store(n + 1, std::memory_order_release);
  }

  /// Writer: allocates the chunks for `n` records now (no allocation in push() up to there).
  void reserve(std::size_t n) {
    if (n == 0) return;
    const std::size_t last = std::min(n - 1, capacity() - 1) / kChunkSize;
    for (std::size_t c = count_.load(std::memory_order_relaxed) / kChunkSize; c <= last; ++c)
      ensureChunk(c);
  }

  /// Records published so far (any thread).
  std::size_t size() const { return count_.load(std::memory_order_acquire); }

  /// The first record not yet released (releaseBefore); size() counts the released ones too.
  std::size_t first() const { return first_.load(std::memory_order_acquire); }

  /// Frees the chunks whose records all come before `n` and before the chunk the writer is in;
  /// returns first() after it (a multiple of the chunk size). No reader may be reading a record
  /// before that index while this runs.
  std::size_t releaseBefore(std::size_t n) {
    const std::size_t end_chunk = std::min(n, size()) / kChunkSize;
    std::size_t c = first() / kChunkSize;
    for (; c < end_chunk; ++c) delete[] chunks_[c].exchange(nullptr, std::memory_order_acq_rel);
    const std::size_t f = std::max(first(), end_chunk * kChunkSize);
    first_.store(f, std::memory_order_release);
    return f;
  }

  /// Record i, for first() <= i < a value size() returned (any thread).
  const T& operator[](std::size_t i) const {
    return chunks_[i / kChunkSize].load(std::memory_order_acquire)[i % kChunkSize];
  }

  /// Calls f(record) for every record from first() on published when it starts (any thread).
  template <typename F>
  void forEach(F&& f) const {
    const std::size_t n = size();
    for (std::size_t c = first() / kChunkSize; c * kChunkSize < n; ++c) {
      const T* chunk = chunks_[c].load(std::memory_order_acquire);
      const std::size_t end = std::min(kChunkSize, n - c * kChunkSize);
      for (std::size_t i = 0; i < end; ++i) f(chunk[i]);
    }
  }

 private:
  T* ensureChunk(std::size_t c) {
    if (c >= max_chunks_)
      throw Error("append-only log full: " + std::to_string(capacity()) + " records");
    T* chunk = chunks_[c].load(std::memory_order_relaxed);
    if (chunk == nullptr) {
      chunk = new T[kChunkSize];
      chunks_[c].store(chunk, std::memory_order_release);
    }
    return chunk;
  }

  std::size_t max_chunks_;
  std::unique_ptr<std::atomic<T*>[]> chunks_;
  std::atomic<std::size_t> count_{0};
  std::atomic<std::size_t> first_{0};
};

}  // namespace ldsm::concurrency
