// Frames from a camera through libcamera (Raspberry Pi and other CSI cameras): a raw stream of a
// monochrome sensor (R8, R10, R12, unpacked or CSI-2 packed) or a processed YUV stream (YUYV,
// UYVY, NV12, NV21, YUV420), whose luma becomes the 8-bit grey frame; exposure time and analogue
// gain set through libcamera controls and read back from each request's metadata.
//
// libcamera is loaded on demand from a plugin (libldsm_libcamera_plugin.so, built when
// pkg-config finds libcamera), so that processes that use no libcamera camera do not load it
// and its dependencies. The format conversion and the control mapping below are plain functions,
// testable without a camera.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ldsm/drivers/frame_source.h"
#include "ldsm/image.h"

namespace ldsm::drivers {

/// Pixel formats of plane 0 that the libcamera source converts to grey.
enum class LibcameraPixelFormat {
  Unsupported,
  R8,        ///< 8-bit mono
  R10,       ///< 10-bit mono in 16-bit little-endian words: v >> 2
  R12,       ///< 12-bit mono in 16-bit little-endian words: v >> 4
  R10Csi2p,  ///< 10-bit mono, MIPI CSI-2 packed: 4 pixels in 5 bytes (the first 4 are the MSBs)
  R12Csi2p,  ///< 12-bit mono, MIPI CSI-2 packed: 2 pixels in 3 bytes (the first 2 are the MSBs)
  Yuyv,      ///< packed 4:2:2, Y at even bytes
  Uyvy,      ///< packed 4:2:2, Y at odd bytes
  Nv12,      ///< Y plane then interleaved CbCr: plane 0 is luma
  Nv21,
  Yuv420,  ///< three planes: plane 0 is luma
};

/// libcamera's name of a format ("R8", "R10_CSI2P", "NV12"...; "unsupported").
const char* toString(LibcameraPixelFormat format);
/// Parses a libcamera format name (case-insensitive). Throws ldsm::ConfigError listing the
/// accepted names.
LibcameraPixelFormat parseLibcameraPixelFormat(const std::string& name);

/// A libcamera PixelFormat: DRM four-character code and modifier.
struct LibcameraFourCc {
  std::uint32_t fourcc = 0;
  std::uint64_t modifier = 0;
};
LibcameraFourCc libcameraFourCc(LibcameraPixelFormat format);
/// The format of a libcamera PixelFormat (Unsupported for Bayer and colour formats).
LibcameraPixelFormat classifyLibcameraFormat(std::uint32_t fourcc, std::uint64_t modifier);

/// Converts plane 0 of a frame (`size` bytes, rows `stride` bytes apart) to 8-bit grey in `out`.
/// Returns false with the reason in `problem` when the data is shorter than the layout needs or
/// the format is unsupported.
bool convertLibcameraPlane(LibcameraPixelFormat format, const unsigned char* data, std::size_t size,
                           int width, int height, int stride, ImageU8& out, std::string& problem);

struct LibcameraOptions {
  std::string camera_id;  ///< libcamera's id; empty: the first camera
  bool raw = true;        ///< the sensor's raw stream (mono sensors) instead of processed video
  /// Formats in order of preference; the first one the stream offers is used.
  std::vector<LibcameraPixelFormat> formats = {
      LibcameraPixelFormat::R8,       LibcameraPixelFormat::R10,      LibcameraPixelFormat::R12,
      LibcameraPixelFormat::R10Csi2p, LibcameraPixelFormat::R12Csi2p, LibcameraPixelFormat::Yuyv,
      LibcameraPixelFormat::Uyvy,     LibcameraPixelFormat::Nv12,     LibcameraPixelFormat::Nv21,
      LibcameraPixelFormat::Yuv420};
  int width = 0;  ///< 0 (with height 0): the stream's default size
  int height = 0;
  double fps = 0.0;                 ///< > 0: fixed frame duration (FrameDurationLimits)
  int buffer_count = 4;             ///< 2..32
  double exposure_ms = 0.0;         ///< > 0: manual exposure (ExposureTime, auto exposure off)
  double analogue_gain = 0.0;       ///< >= 1: manual analogue gain (AnalogueGain); 0: automatic
  bool lock_auto_exposure = false;  ///< auto exposure off at start (exposure and gain frozen)
  int timeout_ms = 2000;            ///< longest wait for a frame before DeviceError
};

/// Throws ldsm::ConfigError naming the option when a value is out of range.
void validate(const LibcameraOptions& options);

/// The libcamera controls set at start for `options`.
struct LibcameraControls {
  bool ae_enable = true;
  std::int32_t exposure_time_us = 0;   ///< ExposureTime; 0: not set
  float analogue_gain = 0.0f;          ///< AnalogueGain; 0: not set
  std::int64_t frame_duration_us = 0;  ///< FrameDurationLimits (min = max); 0: not set
};
LibcameraControls mapLibcameraControls(const LibcameraOptions& options);

/// Milliseconds from an ExposureTime metadata value (microseconds); NaN when not positive.
double exposureMsFromLibcamera(std::int64_t exposure_time_us);

/// True when ldsm was built with the libcamera plugin and it can be loaded.
bool libcameraAvailable();

/// Ids of the cameras libcamera sees. Throws ldsm::DeviceError when libcamera is unavailable.
std::vector<std::string> listLibcameraCameras();

/// Opens and starts a camera. Throws ldsm::ConfigError for bad options and ldsm::DeviceError
/// naming the problem ("no camera found", busy, format not supported, built without libcamera).
/// next() throws ldsm::DeviceError on a timeout or a disconnected camera; after that it returns
/// false.
std::unique_ptr<FrameSource> openLibcameraSource(const LibcameraOptions& options);

}  // namespace ldsm::drivers
