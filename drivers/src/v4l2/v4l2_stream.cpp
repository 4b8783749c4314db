#include "v4l2/v4l2_stream.h"

#include <linux/videodev2.h>
#include <poll.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>

#include "ldsm/error.h"

namespace ldsm::drivers::v4l2 {
namespace {

v4l2_buffer emptyBuffer(int index = 0) {
  v4l2_buffer b;
  std::memset(&b, 0, sizeof b);
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = static_cast<std::uint32_t>(index);
  return b;
}

}  // namespace

MmapStream::MmapStream(Device& device, int count) : device_(device) {
  v4l2_requestbuffers req;
  std::memset(&req, 0, sizeof req);
  req.count = static_cast<std::uint32_t>(count);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  const int r = device_.ioctl(VIDIOC_REQBUFS, &req);
  if (r == -EINVAL)
    throw DeviceError(device_.path() +
                      ": the driver does not support memory-mapped streaming (VIDIOC_REQBUFS "
                      "with V4L2_MEMORY_MMAP failed)");
  if (r < 0) throwDeviceError(device_.path(), "requesting buffers (VIDIOC_REQBUFS)", -r);
  requested_ = true;
  try {
    if (req.count < 2)
      throw DeviceError(device_.path() + ": the driver granted " + std::to_string(req.count) +
                        " buffer(s); streaming needs at least 2");
    buffers_.reserve(req.count);
    for (std::uint32_t i = 0; i < req.count; ++i) {
      v4l2_buffer b = emptyBuffer(static_cast<int>(i));
      device_.ioctlOrThrow(VIDIOC_QUERYBUF, &b, "VIDIOC_QUERYBUF");
      int error = 0;
      void* p = device_.kernel().mmap(b.length, device_.fd(), b.m.offset, &error);
      if (p == nullptr)
        throwDeviceError(device_.path(), "mapping buffer " + std::to_string(i), error);
      buffers_.push_back({p, b.length});
    }
    for (int i = 0; i < static_cast<int>(buffers_.size()); ++i) requeue(i);
  } catch (...) {
    release();
    throw;
  }
}

MmapStream::~MmapStream() {
  release();
}

void MmapStream::release() noexcept {
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    device_.ioctl(VIDIOC_STREAMOFF, &type);
    streaming_ = false;
  }
  for (const Mapping& m : buffers_) device_.kernel().munmap(m.address, m.length);
  buffers_.clear();
  if (requested_) {
    v4l2_requestbuffers req;
    std::memset(&req, 0, sizeof req);
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    device_.ioctl(VIDIOC_REQBUFS, &req);  // count 0 frees them
    requested_ = false;
  }
}

void MmapStream::start() {
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  device_.ioctlOrThrow(VIDIOC_STREAMON, &type, "starting the stream (VIDIOC_STREAMON)");
  streaming_ = true;
}

void MmapStream::requeue(int index) {
  v4l2_buffer b = emptyBuffer(index);
  device_.ioctlOrThrow(VIDIOC_QBUF, &b, "queueing buffer " + std::to_string(index));
}

FilledBuffer MmapStream::dequeue(int timeout_ms) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    short revents = 0;
    const int p = left.count() > 0 ? device_.kernel().poll(device_.fd(),
                                                           static_cast<int>(left.count()), &revents)
                                   : 0;
    if (p == -EINTR) continue;
    if (p < 0) throwDeviceError(device_.path(), "waiting for a frame (poll)", -p);
    if (p == 0)
      throw DeviceError(device_.path() + ": poll timeout: no frame within " +
                        std::to_string(timeout_ms) +
                        " ms (is the camera still streaming? an exposure longer than the frame "
                        "interval, a USB bandwidth limit or a loose cable stop frames; lower the "
                        "frame rate or resolution, or raise the timeout)");

    v4l2_buffer b = emptyBuffer();
    const int r = device_.ioctl(VIDIOC_DQBUF, &b);
    if (r == -EAGAIN || r == -EINTR) {
      if ((revents & (POLLERR | POLLHUP)) != 0)  // error reported but nothing to dequeue
        throw DeviceError(device_.path() +
                          ": the device reported an error and stopped delivering frames "
                          "(unplugged?); reconnect it and start again");
      continue;  // woken without a frame: wait again
    }
    if (r == -EIO || r == -EPIPE)
      throw DeviceError(device_.path() + ": the device stopped streaming (" + std::strerror(-r) +
                        "): unplugged or driver error; reconnect it and "
                        "start again");
    if (r < 0) throwDeviceError(device_.path(), "taking a frame (VIDIOC_DQBUF)", -r);
    if (b.index >= buffers_.size())
      throw DeviceError(device_.path() + ": the driver returned buffer " + std::to_string(b.index) +
                        " of " + std::to_string(buffers_.size()));

    FilledBuffer f;
    f.index = static_cast<int>(b.index);
    f.data = static_cast<const unsigned char*>(buffers_[b.index].address);
    f.bytes_used = b.bytesused > 0 && b.bytesused <= buffers_[b.index].length
                       ? b.bytesused
                       : buffers_[b.index].length;
    f.timestamp =
        static_cast<double>(b.timestamp.tv_sec) + 1e-6 * static_cast<double>(b.timestamp.tv_usec);
    f.monotonic = (b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
    f.corrupt = (b.flags & V4L2_BUF_FLAG_ERROR) != 0;
    f.sequence = b.sequence;
    return f;
  }
}

}  // namespace ldsm::drivers::v4l2
