// The few kernel calls the V4L2 source makes (open, close, ioctl, mmap, munmap, poll), behind an
// interface so that the driver can be tested against an in-process fake device that implements
// the kernel's V4L2 buffer state machine (tests/support/fake_v4l2_kernel.h). Errors are returned
// as negative errno values rather than through errno.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace ldsm::drivers {

class V4l2Kernel {
 public:
  virtual ~V4l2Kernel() = default;

  /// open(2) with `flags` (O_RDWR | O_NONBLOCK from the driver): a descriptor >= 0, or -errno.
  virtual int open(const std::string& path, int flags) = 0;
  /// close(2): 0 or -errno.
  virtual int close(int fd) = 0;
  /// ioctl(2), retried while interrupted by a signal: >= 0 on success, or -errno.
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  /// mmap(2) of `length` bytes at `offset` of the device, shared and readable/writable: the
  /// address, or nullptr with `*error` set to the errno value.
  virtual void* mmap(std::size_t length, int fd, std::int64_t offset, int* error) = 0;
  /// munmap(2): 0 or -errno.
  virtual int munmap(void* address, std::size_t length) = 0;
  /// poll(2) of one descriptor for POLLIN: > 0 with `*revents` set when ready or in error, 0 on
  /// timeout, or -errno (-EINTR when a signal arrived).
  virtual int poll(int fd, int timeout_ms, short* revents) = 0;
};

/// The real kernel: the system calls themselves.
std::shared_ptr<V4l2Kernel> systemV4l2Kernel();

}  // namespace ldsm::drivers
