#include "v4l2/v4l2_controls.h"

#include <linux/videodev2.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include "ldsm/error.h"

namespace ldsm::drivers::v4l2 {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

long long getControl(Device& device, unsigned id, const char* name) {
  v4l2_control c;
  std::memset(&c, 0, sizeof c);
  c.id = id;
  device.ioctlOrThrow(VIDIOC_G_CTRL, &c, std::string("reading control ") + name);
  return c.value;
}

void setControl(Device& device, unsigned id, long long value, const char* name) {
  v4l2_control c;
  std::memset(&c, 0, sizeof c);
  c.id = id;
  c.value = static_cast<__s32>(value);
  device.ioctlOrThrow(VIDIOC_S_CTRL, &c,
                      std::string("setting control ") + name + " to " + std::to_string(value));
}

/// Sets `id` when the device has it; failures are ignored (optional refinements).
void trySetControl(Device& device, unsigned id, long long value) {
  if (!queryControl(device, id)) return;
  v4l2_control c;
  std::memset(&c, 0, sizeof c);
  c.id = id;
  c.value = static_cast<__s32>(value);
  device.ioctl(VIDIOC_S_CTRL, &c);
}

void switchToManualExposure(Device& device) {
  if (!queryControl(device, V4L2_CID_EXPOSURE_AUTO))
    throw DeviceError(device.path() +
                      ": the device has no exposure mode control (V4L2_CID_EXPOSURE_AUTO): "
                      "cannot set or lock the exposure; record with automatic exposure instead");
  setControl(device, V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, "exposure_auto");
  // Keep the frame rate constant instead of stretching frames in the dark.
  trySetControl(device, V4L2_CID_EXPOSURE_AUTO_PRIORITY, 0);
}

}  // namespace

std::optional<ControlRange> queryControl(Device& device, unsigned id) {
  v4l2_queryctrl q;
  std::memset(&q, 0, sizeof q);
  q.id = id;
  const int r = device.ioctl(VIDIOC_QUERYCTRL, &q);
  if (r == -EINVAL || r == -ENOTTY) return std::nullopt;
  if (r < 0) throwDeviceError(device.path(), "VIDIOC_QUERYCTRL", -r);
  if ((q.flags & V4L2_CTRL_FLAG_DISABLED) != 0) return std::nullopt;
  ControlRange range;
  range.minimum = q.minimum;
  range.maximum = q.maximum;
  range.step = q.step > 0 ? q.step : 1;
  range.default_value = q.default_value;
  return range;
}

long long exposureToV4l2(double exposure_ms) {
  return std::llround(exposure_ms * 10.0);
}

double exposureFromV4l2(long long value) {
  return static_cast<double>(value) * 0.1;
}

ExposureControls::ExposureControls(Device& device, const V4l2Options& options) {
  const std::optional<ControlRange> exposure = queryControl(device, V4L2_CID_EXPOSURE_ABSOLUTE);
  has_exposure_ = exposure.has_value();

  if (options.exposure_ms > 0.0) {
    if (!exposure)
      throw DeviceError(device.path() +
                        ": the device has no manual exposure control "
                        "(V4L2_CID_EXPOSURE_ABSOLUTE): drop the exposure option");
    const long long value = exposureToV4l2(options.exposure_ms);
    if (value < exposure->minimum || value > exposure->maximum)
      throw DeviceError(device.path() + ": exposure " + number(options.exposure_ms) +
                        " ms is outside the device's range " +
                        number(exposureFromV4l2(exposure->minimum)) + ".." +
                        number(exposureFromV4l2(exposure->maximum)) + " ms");
    switchToManualExposure(device);
    setControl(device, V4L2_CID_EXPOSURE_ABSOLUTE, value, "exposure_absolute");
  } else if (options.lock_auto_exposure) {
    if (queryControl(device, V4L2_CID_3A_LOCK)) {
      // Auto exposure stays on but holds its current value.
      const long long locks = getControl(device, V4L2_CID_3A_LOCK, "3a_lock");
      setControl(device, V4L2_CID_3A_LOCK, locks | V4L2_LOCK_EXPOSURE, "3a_lock");
    } else {
      // Manual mode with the value auto exposure has chosen (some drivers reset it on the switch).
      const long long current =
          exposure ? getControl(device, V4L2_CID_EXPOSURE_ABSOLUTE, "exposure_absolute") : -1;
      switchToManualExposure(device);
      if (current >= 0)
        setControl(device, V4L2_CID_EXPOSURE_ABSOLUTE, current, "exposure_absolute");
    }
  }

  if (options.gain >= 0.0) {
    unsigned id = V4L2_CID_GAIN;
    std::optional<ControlRange> gain = queryControl(device, id);
    if (!gain) {
      id = V4L2_CID_ANALOGUE_GAIN;
      gain = queryControl(device, id);
    }
    if (!gain)
      throw DeviceError(device.path() +
                        ": the device has no gain control (V4L2_CID_GAIN or "
                        "V4L2_CID_ANALOGUE_GAIN): drop the gain option");
    const long long value = std::llround(options.gain);
    if (value < gain->minimum || value > gain->maximum)
      throw DeviceError(device.path() + ": gain " + number(options.gain) +
                        " is outside the device's range " + std::to_string(gain->minimum) + ".." +
                        std::to_string(gain->maximum));
    trySetControl(device, V4L2_CID_AUTOGAIN, 0);
    setControl(device, id, value, "gain");
  }
}

double ExposureControls::readExposureMs(Device& device) const {
  if (!has_exposure_) return std::numeric_limits<double>::quiet_NaN();
  v4l2_control c;
  std::memset(&c, 0, sizeof c);
  c.id = V4L2_CID_EXPOSURE_ABSOLUTE;
  const int r = device.ioctl(VIDIOC_G_CTRL, &c);
  if (r == -ENODEV) throwDeviceError(device.path(), "reading the exposure", ENODEV);
  if (r < 0 || c.value <= 0) return std::numeric_limits<double>::quiet_NaN();
  return exposureFromV4l2(c.value);
}

}  // namespace ldsm::drivers::v4l2
