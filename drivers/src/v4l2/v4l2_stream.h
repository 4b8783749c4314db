// Memory-mapped streaming I/O: a fixed set of driver buffers (VIDIOC_REQBUFS), mapped once
// (QUERYBUF + mmap), queued to the driver (QBUF), taken back when filled (poll + DQBUF) and
// returned after conversion. STREAMON starts the capture; the destructor stops it (STREAMOFF),
// unmaps and frees the buffers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "v4l2/v4l2_device.h"

namespace ldsm::drivers::v4l2 {

/// A filled buffer taken from the driver; give it back with MmapStream::requeue(index).
struct FilledBuffer {
  int index = -1;
  const unsigned char* data = nullptr;
  std::size_t bytes_used = 0;  ///< payload size (the buffer length when the driver reports 0)
  double timestamp = 0.0;      ///< seconds, the driver's clock (see monotonic)
  bool monotonic = false;      ///< the timestamp is CLOCK_MONOTONIC (not unknown / copied)
  bool corrupt = false;        ///< the driver flagged the data as bad (V4L2_BUF_FLAG_ERROR)
  std::uint32_t sequence = 0;  ///< the driver's frame counter (gaps are frames it dropped)
};

class MmapStream {
 public:
  /// Requests `count` buffers (the driver may grant a different number, at least 2), maps and
  /// queues them. Throws ldsm::DeviceError.
  MmapStream(Device& device, int count);
  ~MmapStream();
  MmapStream(const MmapStream&) = delete;
  MmapStream& operator=(const MmapStream&) = delete;

  void start();  ///< VIDIOC_STREAMON

  /// Waits at most `timeout_ms` for a filled buffer. Throws ldsm::DeviceError: "poll timeout"
  /// when nothing arrives in time, "device gone" when the camera is unplugged.
  FilledBuffer dequeue(int timeout_ms);
  /// Gives buffer `index` back to the driver. Throws ldsm::DeviceError.
  void requeue(int index);

  int count() const { return static_cast<int>(buffers_.size()); }

 private:
  struct Mapping {
    void* address = nullptr;
    std::size_t length = 0;
  };
  void release() noexcept;

  Device& device_;
  std::vector<Mapping> buffers_;
  bool streaming_ = false;
  bool requested_ = false;
};

}  // namespace ldsm::drivers::v4l2
