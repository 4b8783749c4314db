// An in-process fake V4L2 camera behind ldsm::drivers::V4l2Kernel, for testing the V4L2 source
// without a device. It follows the kernel's videobuf2 rules closely enough to catch a driver
// that calls things in the wrong order:
//  * formats, frame sizes and intervals are enumerated like VIDIOC_ENUM_FMT / ENUM_FRAMESIZES /
//    ENUM_FRAMEINTERVALS (EINVAL past the end); S_FMT adjusts to the nearest offered size and
//    fails with EBUSY once buffers exist;
//  * buffers: REQBUFS (MMAP only, EBUSY while streaming or mapped, count 0 frees), QUERYBUF
//    (length and mmap offset), mmap/munmap by offset, QBUF only of a buffer the application owns
//    (EINVAL otherwise), DQBUF only while streaming (EINVAL otherwise), EAGAIN when no buffer is
//    filled (the device is opened non-blocking), STREAMON needs buffers, STREAMOFF returns every
//    buffer to the application;
//  * a frame is produced when the application polls while a buffer is queued: frame n holds the
//    known pattern fakePixel(n, x, y) in the current pixel format (MJPEG encoded with OpenCV),
//    timestamp first_timestamp + n / fps (CLOCK_MONOTONIC flag) and sequence n (the frames are
//    made by fake_v4l2_frames.h);
//  * controls: exposure mode, exposure (100 us units; in automatic mode it changes with every
//    frame: 100 + n % 50), exposure priority, gain; S_CTRL out of range is ERANGE, setting the
//    exposure in automatic mode is EACCES (as UVC does for an inactive control);
//  * faults on request: busy device, unplug after N frames (ENODEV, then the node is gone),
//    stall after N frames (poll times out), corrupt (V4L2_BUF_FLAG_ERROR) or truncated frames,
//    spurious wake-ups (poll says ready, DQBUF says EAGAIN).
// Single-threaded, like the driver's use of the kernel.
#pragma once

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fake_v4l2_frames.h"
#include "ldsm/drivers/v4l2_kernel.h"

namespace ldsm::test {

/// How the fake camera behaves (faults included).
struct FakeV4l2Config {
  std::string path = "/dev/video7";
  std::vector<FakeFormat> formats = fakeDefaultFormats();
  bool capture = true;  ///< advertises video capture with streaming I/O
  bool busy = false;    ///< another process streams: S_FMT, REQBUFS, STREAMON fail with EBUSY
  std::uint32_t max_buffers = 8;
  int row_padding = 0;  ///< extra bytes per row of uncompressed formats (filled with 0xEE)
  double first_timestamp = 1000.0;
  bool exposure_controls = true;
  bool gain_control = true;
  std::int64_t unplug_after = -1;           ///< frames delivered before the camera disappears
  std::int64_t stall_after = -1;            ///< frames after which nothing arrives any more
  std::set<std::int64_t> corrupt_frames;    ///< flagged V4L2_BUF_FLAG_ERROR
  std::set<std::int64_t> truncated_frames;  ///< delivered with half their bytes
  bool spurious_wakeups = false;            ///< every other poll is ready without a frame
  int jpeg_quality = 95;
};

class FakeV4l2Kernel : public drivers::V4l2Kernel {
 public:
  static constexpr std::int64_t kOffsetStep = 1 << 20;

  using Config = FakeV4l2Config;

  FakeV4l2Kernel() : FakeV4l2Kernel(Config()) {}
  explicit FakeV4l2Kernel(Config config) : config_(std::move(config)) {
    const FakeFormat& f = config_.formats.front();
    setFormat(f, f.sizes.front());
    controls_[V4L2_CID_EXPOSURE_AUTO] = {0, 3, 1, V4L2_EXPOSURE_APERTURE_PRIORITY,
                                         V4L2_EXPOSURE_APERTURE_PRIORITY};
    controls_[V4L2_CID_EXPOSURE_AUTO_PRIORITY] = {0, 1, 1, 1, 1};
    if (config_.exposure_controls) controls_[V4L2_CID_EXPOSURE_ABSOLUTE] = {1, 10000, 1, 100, 100};
    if (config_.gain_control) controls_[V4L2_CID_GAIN] = {0, 255, 1, 32, 32};
    if (!config_.exposure_controls) controls_.erase(V4L2_CID_EXPOSURE_AUTO);
  }

  // ---- inspection --------------------------------------------------------------------------
  Config& config() { return config_; }
  int openCount() const { return static_cast<int>(open_fds_.size()); }
  int mappedCount() const {
    return static_cast<int>(
        std::count_if(buffers_.begin(), buffers_.end(), [](const Buffer& b) { return b.mapped; }));
  }
  int bufferCount() const { return static_cast<int>(buffers_.size()); }
  bool streaming() const { return streaming_; }
  std::int64_t framesProduced() const { return produced_; }
  long long control(unsigned id) const { return controls_.at(id).value; }
  bool lastOpenWasNonBlocking() const { return non_blocking_; }
  std::uint32_t currentFourCc() const { return fourcc_; }
  double currentFps() const { return fps_; }
  /// The camera disappears now (as if unplugged).
  void unplug() { unplugged_ = true; }

  // ---- V4l2Kernel --------------------------------------------------------------------------
  int open(const std::string& path, int flags) override {
    if (path != config_.path || unplugged_) return -ENOENT;
    non_blocking_ = (flags & O_NONBLOCK) != 0;
    const int fd = next_fd_++;
    open_fds_.insert(fd);
    return fd;
  }

  int close(int fd) override {
    if (open_fds_.erase(fd) == 0) return -EBADF;
    if (open_fds_.empty()) {  // the last close releases the queue (mapped memory survives)
      stopStreaming();
      if (mappedCount() == 0) buffers_.clear();
    }
    return 0;
  }

  int ioctl(int fd, unsigned long request, void* arg) override {
    if (open_fds_.count(fd) == 0) return -EBADF;
    if (unplugged_) return -ENODEV;
    switch (request) {
      case VIDIOC_QUERYCAP:
        return queryCap(static_cast<v4l2_capability*>(arg));
      case VIDIOC_ENUM_FMT:
        return enumFormat(static_cast<v4l2_fmtdesc*>(arg));
      case VIDIOC_ENUM_FRAMESIZES:
        return enumSizes(static_cast<v4l2_frmsizeenum*>(arg));
      case VIDIOC_ENUM_FRAMEINTERVALS:
        return enumIntervals(static_cast<v4l2_frmivalenum*>(arg));
      case VIDIOC_G_FMT:
        return getFormat(static_cast<v4l2_format*>(arg));
      case VIDIOC_S_FMT:
        return setFormatIoctl(static_cast<v4l2_format*>(arg));
      case VIDIOC_G_PARM:
      case VIDIOC_S_PARM:
        return parm(request == VIDIOC_S_PARM, static_cast<v4l2_streamparm*>(arg));
      case VIDIOC_REQBUFS:
        return requestBuffers(static_cast<v4l2_requestbuffers*>(arg));
      case VIDIOC_QUERYBUF:
        return queryBuffer(static_cast<v4l2_buffer*>(arg));
      case VIDIOC_QBUF:
        return queueBuffer(static_cast<v4l2_buffer*>(arg));
      case VIDIOC_DQBUF:
        return dequeueBuffer(static_cast<v4l2_buffer*>(arg));
      case VIDIOC_STREAMON:
        return streamOn(static_cast<int*>(arg));
      case VIDIOC_STREAMOFF:
        if (*static_cast<int*>(arg) != V4L2_BUF_TYPE_VIDEO_CAPTURE) return -EINVAL;
        stopStreaming();
        return 0;
      case VIDIOC_QUERYCTRL:
        return queryControl(static_cast<v4l2_queryctrl*>(arg));
      case VIDIOC_G_CTRL:
      case VIDIOC_S_CTRL:
        return controlIoctl(request == VIDIOC_S_CTRL, static_cast<v4l2_control*>(arg));
      default:
        return -ENOTTY;
    }
  }

  void* mmap(std::size_t length, int fd, std::int64_t offset, int* error) override {
    if (open_fds_.count(fd) == 0 || unplugged_) {
      *error = open_fds_.count(fd) == 0 ? EBADF : ENODEV;
      return nullptr;
    }
    for (std::size_t i = 0; i < buffers_.size(); ++i) {
      if (static_cast<std::int64_t>(i) * kOffsetStep == offset &&
          length <= buffers_[i].data.size() && length > 0) {
        buffers_[i].mapped = true;
        return buffers_[i].data.data();
      }
    }
    *error = EINVAL;
    return nullptr;
  }

  int munmap(void* address, std::size_t length) override {
    for (Buffer& b : buffers_) {
      if (b.mapped && b.data.data() == address && length == b.data.size()) {
        b.mapped = false;
        return 0;
      }
    }
    return -EINVAL;
  }

  int poll(int fd, int /*timeout_ms*/, short* revents) override {
    if (open_fds_.count(fd) == 0) return -EBADF;
    *revents = 0;
    if (unplugged_) {
      *revents = POLLERR | POLLHUP;
      return 1;
    }
    if (!streaming_) {
      *revents = POLLERR;
      return 1;
    }
    if (!done_.empty()) {
      *revents = POLLIN | POLLRDNORM;
      return 1;
    }
    if (config_.spurious_wakeups && (++polls_ % 2) == 1) {
      *revents = POLLIN | POLLRDNORM;
      return 1;
    }
    if (config_.unplug_after >= 0 && produced_ >= config_.unplug_after) {
      unplugged_ = true;
      *revents = POLLERR | POLLHUP;
      return 1;
    }
    if (config_.stall_after >= 0 && produced_ >= config_.stall_after) return 0;
    if (queued_.empty()) return 0;  // no buffer to fill: nothing can arrive
    produceFrame();
    *revents = POLLIN | POLLRDNORM;
    return 1;
  }

 private:
  enum class State { User, Queued, Done };
  struct Buffer {
    std::vector<unsigned char> data;
    State state = State::User;
    bool mapped = false;
    std::uint32_t bytes_used = 0;
    std::uint32_t flags = 0;
    timeval timestamp{};
    std::uint32_t sequence = 0;
  };
  struct Control {
    long long minimum, maximum, step, default_value, value;
  };

  const FakeFormat* findFormat(std::uint32_t fourcc) const {
    for (const FakeFormat& f : config_.formats)
      if (f.fourcc == fourcc) return &f;
    return nullptr;
  }

  void setFormat(const FakeFormat& f, std::pair<int, int> size) {
    fourcc_ = f.fourcc;
    width_ = size.first;
    height_ = size.second;
    fps_ = f.fps.empty() ? 30.0 : f.fps.front();
    if (fakeUncompressed(fourcc_)) {
      bytes_per_line_ =
          static_cast<std::uint32_t>(width_ * fakeBytesPerPixel(fourcc_) + config_.row_padding);
      size_image_ = bytes_per_line_ * static_cast<std::uint32_t>(height_);
    } else {
      bytes_per_line_ = 0;
      size_image_ = static_cast<std::uint32_t>(width_ * height_ * 2 + 4096);
    }
  }

  int queryCap(v4l2_capability* cap) {
    std::memset(cap, 0, sizeof *cap);
    std::strncpy(reinterpret_cast<char*>(cap->driver), "fake", sizeof cap->driver - 1);
    std::strncpy(reinterpret_cast<char*>(cap->card), "Fake Camera", sizeof cap->card - 1);
    const std::uint32_t caps =
        config_.capture ? V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING : V4L2_CAP_VIDEO_OUTPUT;
    cap->device_caps = caps;
    cap->capabilities = caps | V4L2_CAP_DEVICE_CAPS;
    return 0;
  }

  int enumFormat(v4l2_fmtdesc* f) {
    if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || f->index >= config_.formats.size())
      return -EINVAL;
    const FakeFormat& ff = config_.formats[f->index];
    f->pixelformat = ff.fourcc;
    f->flags = fakeUncompressed(ff.fourcc) ? 0 : V4L2_FMT_FLAG_COMPRESSED;
    std::memset(f->description, 0, sizeof f->description);
    std::strncpy(reinterpret_cast<char*>(f->description), ff.description.c_str(),
                 sizeof f->description - 1);
    return 0;
  }

  int enumSizes(v4l2_frmsizeenum* e) {
    const FakeFormat* f = findFormat(e->pixel_format);
    if (f == nullptr || e->index >= f->sizes.size()) return -EINVAL;
    e->type = V4L2_FRMSIZE_TYPE_DISCRETE;
    e->discrete.width = static_cast<std::uint32_t>(f->sizes[e->index].first);
    e->discrete.height = static_cast<std::uint32_t>(f->sizes[e->index].second);
    return 0;
  }

  int enumIntervals(v4l2_frmivalenum* e) {
    const FakeFormat* f = findFormat(e->pixel_format);
    if (f == nullptr || e->index >= f->fps.size()) return -EINVAL;
    const auto size = std::make_pair(static_cast<int>(e->width), static_cast<int>(e->height));
    if (std::find(f->sizes.begin(), f->sizes.end(), size) == f->sizes.end()) return -EINVAL;
    e->type = V4L2_FRMIVAL_TYPE_DISCRETE;
    e->discrete.numerator = 1;
    e->discrete.denominator = static_cast<std::uint32_t>(f->fps[e->index]);
    return 0;
  }

  int getFormat(v4l2_format* f) {
    if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return -EINVAL;
    std::memset(&f->fmt, 0, sizeof f->fmt);
    f->fmt.pix.width = static_cast<std::uint32_t>(width_);
    f->fmt.pix.height = static_cast<std::uint32_t>(height_);
    f->fmt.pix.pixelformat = fourcc_;
    f->fmt.pix.field = V4L2_FIELD_NONE;
    f->fmt.pix.bytesperline = bytes_per_line_;
    f->fmt.pix.sizeimage = size_image_;
    f->fmt.pix.colorspace = V4L2_COLORSPACE_SRGB;
    return 0;
  }

  int setFormatIoctl(v4l2_format* f) {
    if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return -EINVAL;
    if (config_.busy || !buffers_.empty()) return -EBUSY;
    const FakeFormat* ff = findFormat(f->fmt.pix.pixelformat);
    if (ff == nullptr) ff = &config_.formats.front();  // drivers adjust, they do not refuse
    std::pair<int, int> best = ff->sizes.front();
    auto distance = [&](std::pair<int, int> s) {
      return std::abs(s.first - static_cast<int>(f->fmt.pix.width)) +
             std::abs(s.second - static_cast<int>(f->fmt.pix.height));
    };
    for (const auto& s : ff->sizes)
      if (distance(s) < distance(best)) best = s;
    setFormat(*ff, best);
    return getFormat(f);
  }

  int parm(bool set, v4l2_streamparm* p) {
    if (p->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return -EINVAL;
    if (set) {
      if (streaming_ || config_.busy) return -EBUSY;
      const v4l2_fract t = p->parm.capture.timeperframe;
      if (t.numerator > 0 && t.denominator > 0) {
        const double wanted = static_cast<double>(t.denominator) / t.numerator;
        double best = fps_;
        if (const FakeFormat* f = findFormat(fourcc_); f != nullptr)
          for (int r : f->fps)
            if (std::abs(r - wanted) < std::abs(best - wanted)) best = r;
        fps_ = best;
      }
    }
    std::memset(&p->parm, 0, sizeof p->parm);
    p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
    p->parm.capture.timeperframe.numerator = 1;
    p->parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(fps_);
    return 0;
  }

  int requestBuffers(v4l2_requestbuffers* r) {
    if (r->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || r->memory != V4L2_MEMORY_MMAP) return -EINVAL;
    if (config_.busy || streaming_ || mappedCount() > 0) return -EBUSY;
    buffers_.clear();
    queued_.clear();
    done_.clear();
    const std::uint32_t n = std::min(r->count, config_.max_buffers);
    for (std::uint32_t i = 0; i < n; ++i) {
      Buffer b;
      b.data.assign(size_image_, 0);
      buffers_.push_back(std::move(b));
    }
    r->count = n;
    return 0;
  }

  bool validBuffer(const v4l2_buffer* b) const {
    return b->type == V4L2_BUF_TYPE_VIDEO_CAPTURE && b->memory == V4L2_MEMORY_MMAP &&
           b->index < buffers_.size();
  }

  void describe(std::uint32_t index, v4l2_buffer* out) const {
    const Buffer& b = buffers_[index];
    std::memset(out, 0, sizeof *out);
    out->index = index;
    out->type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    out->memory = V4L2_MEMORY_MMAP;
    out->length = static_cast<std::uint32_t>(b.data.size());
    out->m.offset = static_cast<std::uint32_t>(index * kOffsetStep);
    out->bytesused = b.bytes_used;
    out->timestamp = b.timestamp;
    out->sequence = b.sequence;
    out->field = V4L2_FIELD_NONE;
    out->flags = b.flags | (b.mapped ? V4L2_BUF_FLAG_MAPPED : 0) |
                 (b.state == State::Queued ? V4L2_BUF_FLAG_QUEUED : 0) |
                 (b.state == State::Done ? V4L2_BUF_FLAG_DONE : 0);
  }

  int queryBuffer(v4l2_buffer* b) {
    if (!validBuffer(b)) return -EINVAL;
    describe(b->index, b);
    return 0;
  }

  int queueBuffer(v4l2_buffer* b) {
    if (!validBuffer(b) || buffers_[b->index].state != State::User) return -EINVAL;
    buffers_[b->index].state = State::Queued;
    queued_.push_back(static_cast<int>(b->index));
    return 0;
  }

  int dequeueBuffer(v4l2_buffer* b) {
    if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP) return -EINVAL;
    if (!streaming_) return -EINVAL;
    if (done_.empty()) return non_blocking_ ? -EAGAIN : -EDEADLK;  // blocking would hang here
    const int index = done_.front();
    done_.pop_front();
    buffers_[static_cast<std::size_t>(index)].state = State::User;
    describe(static_cast<std::uint32_t>(index), b);
    return 0;
  }

  int streamOn(const int* type) {
    if (*type != V4L2_BUF_TYPE_VIDEO_CAPTURE || buffers_.empty()) return -EINVAL;
    if (config_.busy) return -EBUSY;
    streaming_ = true;
    return 0;
  }

  void stopStreaming() {
    streaming_ = false;
    queued_.clear();
    done_.clear();
    for (Buffer& b : buffers_) b.state = State::User;
  }

  int queryControl(v4l2_queryctrl* q) {
    const auto it = controls_.find(q->id);
    if (it == controls_.end()) return -EINVAL;
    const unsigned id = q->id;
    std::memset(q, 0, sizeof *q);
    q->id = id;
    q->type = id == V4L2_CID_EXPOSURE_AUTO ? V4L2_CTRL_TYPE_MENU : V4L2_CTRL_TYPE_INTEGER;
    q->minimum = static_cast<__s32>(it->second.minimum);
    q->maximum = static_cast<__s32>(it->second.maximum);
    q->step = static_cast<__s32>(it->second.step);
    q->default_value = static_cast<__s32>(it->second.default_value);
    return 0;
  }

  int controlIoctl(bool set, v4l2_control* c) {
    const auto it = controls_.find(c->id);
    if (it == controls_.end()) return -EINVAL;
    if (!set) {
      c->value = static_cast<__s32>(it->second.value);
      return 0;
    }
    if (c->value < it->second.minimum || c->value > it->second.maximum) return -ERANGE;
    if (c->id == V4L2_CID_EXPOSURE_ABSOLUTE && !manualExposure()) return -EACCES;
    it->second.value = c->value;
    return 0;
  }

  bool manualExposure() const {
    const auto it = controls_.find(V4L2_CID_EXPOSURE_AUTO);
    return it != controls_.end() && it->second.value == V4L2_EXPOSURE_MANUAL;
  }

  void produceFrame() {
    const std::int64_t n = produced_++;
    const int index = queued_.front();
    queued_.pop_front();
    Buffer& b = buffers_[static_cast<std::size_t>(index)];
    if (config_.exposure_controls && !manualExposure())
      controls_[V4L2_CID_EXPOSURE_ABSOLUTE].value = 100 + n % 50;
    fill(n, b);
    if (config_.truncated_frames.count(n) != 0) b.bytes_used /= 2;
    b.flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF |
              (config_.corrupt_frames.count(n) != 0 ? V4L2_BUF_FLAG_ERROR : 0);
    const double t = config_.first_timestamp + static_cast<double>(n) / fps_;
    const auto usec_total = static_cast<long long>(t * 1e6 + 0.5);
    b.timestamp.tv_sec = static_cast<time_t>(usec_total / 1000000);
    b.timestamp.tv_usec = static_cast<suseconds_t>(usec_total % 1000000);
    b.sequence = static_cast<std::uint32_t>(n);
    b.state = State::Done;
    done_.push_back(index);
  }

  void fill(std::int64_t n, Buffer& b) const {
    b.bytes_used = static_cast<std::uint32_t>(
        fillFakeFrame(fourcc_, width_, height_, bytes_per_line_, n, config_.jpeg_quality, b.data));
  }

  Config config_;
  std::map<unsigned, Control> controls_;
  std::set<int> open_fds_;
  int next_fd_ = 3;
  bool non_blocking_ = false;
  bool unplugged_ = false;
  std::uint32_t fourcc_ = 0;
  int width_ = 0;
  int height_ = 0;
  double fps_ = 30.0;
  std::uint32_t bytes_per_line_ = 0;
  std::uint32_t size_image_ = 0;
  std::vector<Buffer> buffers_;
  std::deque<int> queued_;
  std::deque<int> done_;
  bool streaming_ = false;
  std::int64_t produced_ = 0;
  std::int64_t polls_ = 0;
};

}  // namespace ldsm::test
