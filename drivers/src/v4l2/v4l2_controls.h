// Exposure and gain through V4L2 controls: manual exposure (V4L2_CID_EXPOSURE_ABSOLUTE, in units
// of 100 us) with auto exposure off, freezing the automatic exposure, manual gain, and reading
// the exposure back for every frame.
#pragma once

#include <optional>

#include "ldsm/drivers/v4l2_source.h"
#include "v4l2/v4l2_device.h"

namespace ldsm::drivers::v4l2 {

/// A control's range (VIDIOC_QUERYCTRL).
struct ControlRange {
  long long minimum = 0;
  long long maximum = 0;
  long long step = 1;
  long long default_value = 0;
};

/// The control's range, or nothing when the device has no such (enabled) control.
std::optional<ControlRange> queryControl(Device& device, unsigned id);

/// V4L2_CID_EXPOSURE_ABSOLUTE value (100 us units) for `exposure_ms`, rounded.
long long exposureToV4l2(double exposure_ms);
/// Milliseconds for a V4L2_CID_EXPOSURE_ABSOLUTE value.
double exposureFromV4l2(long long value);

class ExposureControls {
 public:
  /// Applies the exposure/gain options. Throws ldsm::DeviceError when a requested control is
  /// missing ("the device has no manual exposure control") or the value is outside the device's
  /// range (naming the range).
  ExposureControls(Device& device, const V4l2Options& options);

  /// The exposure in ms as the device reports it now (NaN when it has no exposure control or
  /// cannot report it). Throws ldsm::DeviceError when the device is gone.
  double readExposureMs(Device& device) const;

 private:
  bool has_exposure_ = false;
};

}  // namespace ldsm::drivers::v4l2
