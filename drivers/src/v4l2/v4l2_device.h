// An open V4L2 device node: the descriptor, the kernel interface it goes through, and the error
// messages that name the device and say what to do.
#pragma once

#include <memory>
#include <string>

#include "ldsm/drivers/v4l2_kernel.h"

namespace ldsm::drivers::v4l2 {

/// "<device>: <what>: <errno text> (<advice>)". The advice depends on the error: device missing,
/// busy, unplugged, permission denied, not a V4L2 node, I/O error.
std::string deviceErrorMessage(const std::string& device, const std::string& what, int error);

/// Throws ldsm::DeviceError with deviceErrorMessage(device, what, error).
[[noreturn]] void throwDeviceError(const std::string& device, const std::string& what, int error);

class Device {
 public:
  /// Opens `path` read/write and non-blocking. Throws ldsm::DeviceError (missing, busy,
  /// permission denied...).
  Device(std::shared_ptr<V4l2Kernel> kernel, std::string path);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  /// ioctl on the device: >= 0, or -errno.
  int ioctl(unsigned long request, void* arg) { return kernel_->ioctl(fd_, request, arg); }
  /// ioctl that throws ldsm::DeviceError "<device>: <what>: ..." on failure.
  void ioctlOrThrow(unsigned long request, void* arg, const std::string& what);

  const std::string& path() const { return path_; }
  V4l2Kernel& kernel() { return *kernel_; }
  int fd() const { return fd_; }

 private:
  std::shared_ptr<V4l2Kernel> kernel_;
  std::string path_;
  int fd_ = -1;
};

}  // namespace ldsm::drivers::v4l2
