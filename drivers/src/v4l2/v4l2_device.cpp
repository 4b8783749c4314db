#include "v4l2/v4l2_device.h"

#include <fcntl.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "ldsm/error.h"

namespace ldsm::drivers::v4l2 {
namespace {

std::string adviceFor(const std::string& device, int error) {
  switch (error) {
    case ENOENT:
      return "device missing: is the camera connected? `ls /dev/video*` lists the video devices "
             "and `v4l2-ctl --list-devices` names them; without a camera, load the vivid test "
             "driver (sudo modprobe vivid)";
    case ENODEV:
    case ENXIO:
      return "device gone: the camera was unplugged or its driver unloaded; reconnect it and "
             "start again";
    case EBUSY:
      return "device busy: another program is using the camera; close it (`fuser " + device +
             "` shows which process holds it)";
    case EACCES:
    case EPERM:
      return "permission denied: add the user to the 'video' group (sudo usermod -aG video "
             "$USER) and log in again";
    case ENOTTY:
      return "not a V4L2 video device: give a /dev/videoN capture node";
    case EIO:
      return "I/O error in the camera driver: check the cable and the USB port, or lower the "
             "resolution or frame rate";
    default:
      return "";
  }
}

}  // namespace

std::string deviceErrorMessage(const std::string& device, const std::string& what, int error) {
  std::string message = device + ": " + what + ": " + std::strerror(error);
  const std::string advice = adviceFor(device, error);
  if (!advice.empty()) message += " (" + advice + ")";
  return message;
}

void throwDeviceError(const std::string& device, const std::string& what, int error) {
  throw DeviceError(deviceErrorMessage(device, what, error));
}

Device::Device(std::shared_ptr<V4l2Kernel> kernel, std::string path)
    : kernel_(std::move(kernel)), path_(std::move(path)) {
  if (!kernel_) throw DeviceError(path_ + ": no kernel interface given");
  const int fd = kernel_->open(path_, O_RDWR | O_NONBLOCK);
  if (fd < 0) throwDeviceError(path_, "cannot open", -fd);
  fd_ = fd;
}

Device::~Device() {
  if (fd_ >= 0) kernel_->close(fd_);
}

void Device::ioctlOrThrow(unsigned long request, void* arg, const std::string& what) {
  const int r = ioctl(request, arg);
  if (r < 0) throwDeviceError(path_, what, -r);
}

}  // namespace ldsm::drivers::v4l2
