// Asking an open device what it is and what it offers: VIDIOC_QUERYCAP, ENUM_FMT,
// ENUM_FRAMESIZES, ENUM_FRAMEINTERVALS.
#pragma once

#include <vector>

#include "ldsm/drivers/v4l2_source.h"
#include "v4l2/v4l2_device.h"

namespace ldsm::drivers::v4l2 {

/// Throws ldsm::DeviceError unless the device captures video with streaming (mmap) I/O.
void checkCaptureDevice(Device& device);

/// Every capture format with its sizes and rates (formats ldsm cannot convert included, with
/// supported = false). Throws ldsm::DeviceError when the device fails (ENODEV...).
std::vector<V4l2FormatDescription> enumerateFormats(Device& device);

}  // namespace ldsm::drivers::v4l2
