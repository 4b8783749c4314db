// The real kernel behind V4l2Kernel: plain system calls.
#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>

#include "ldsm/drivers/v4l2_kernel.h"

namespace ldsm::drivers {
namespace {

class SystemV4l2Kernel final : public V4l2Kernel {
 public:
  int open(const std::string& path, int flags) override {
    const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
    return fd >= 0 ? fd : -errno;
  }
  int close(int fd) override { return ::close(fd) == 0 ? 0 : -errno; }
  int ioctl(int fd, unsigned long request, void* arg) override {
    int r = 0;
    do {
      r = ::ioctl(fd, request, arg);
    } while (r < 0 && errno == EINTR);
    return r >= 0 ? r : -errno;
  }
  void* mmap(std::size_t length, int fd, std::int64_t offset, int* error) override {
    void* p =
        ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, static_cast<off_t>(offset));
    if (p == MAP_FAILED) {
      if (error != nullptr) *error = errno;
      return nullptr;
    }
    return p;
  }
  int munmap(void* address, std::size_t length) override {
    return ::munmap(address, length) == 0 ? 0 : -errno;
  }
  int poll(int fd, int timeout_ms, short* revents) override {
    pollfd p{};
    p.fd = fd;
    p.events = POLLIN;
    const int r = ::poll(&p, 1, timeout_ms);
    if (r < 0) return -errno;
    if (revents != nullptr) *revents = p.revents;
    return r;
  }
};

}  // namespace

std::shared_ptr<V4l2Kernel> systemV4l2Kernel() {
  return std::make_shared<SystemV4l2Kernel>();
}

}  // namespace ldsm::drivers
