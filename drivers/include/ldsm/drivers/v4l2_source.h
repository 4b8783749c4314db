// Frames from a V4L2 camera (/dev/videoN): format, size and frame-rate negotiation, memory-mapped
// streaming with a fixed number of buffers, kernel timestamps, manual exposure and gain through
// V4L2 controls with the exposure read back for every frame, and conversion of GREY, Y10, Y16,
// YUYV and MJPEG (decoded with libjpeg) to 8-bit grey.
//
// Every failure throws ldsm::DeviceError naming the device, what went wrong and what to do
// (device missing, busy, unplugged, format not supported, no frame within the poll timeout);
// after an error next() returns false. The kernel calls go through a V4l2Kernel so that tests
// can inject a fake device. Linux only (built with LDSM_WITH_V4L2).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ldsm/drivers/frame_source.h"
#include "ldsm/drivers/v4l2_kernel.h"

namespace ldsm::drivers {

/// Pixel formats the V4L2 source converts to 8-bit grey.
enum class V4l2PixelFormat {
  Grey,   ///< 8-bit luminance ('GREY')
  Y10,    ///< 10-bit luminance in 16-bit little-endian words ('Y10 '): v >> 2
  Y16,    ///< 16-bit luminance, little-endian ('Y16 '): v >> 8
  Yuyv,   ///< packed 4:2:2 Y0 U Y1 V ('YUYV'): the Y samples
  Mjpeg,  ///< Motion-JPEG ('MJPG' or 'JPEG'): decoded to luma with libjpeg
};

/// "GREY", "Y10", "Y16", "YUYV", "MJPEG".
const char* toString(V4l2PixelFormat format);
/// Parses a format name, case-insensitively: GREY (or GRAY), Y10, Y16, YUYV, MJPEG (or MJPG).
/// Throws ldsm::ConfigError listing the accepted names.
V4l2PixelFormat parseV4l2PixelFormat(const std::string& name);
/// The V4L2 four-character code of a format (V4L2_PIX_FMT_*).
std::uint32_t v4l2FourCc(V4l2PixelFormat format);
/// "YUYV" from 0x56595559: the four characters of a code (non-printable ones as '?').
std::string fourCcToString(std::uint32_t fourcc);

struct V4l2Options {
  std::string device = "/dev/video0";
  /// Formats in order of preference: the first one the device offers at the requested size wins.
  std::vector<V4l2PixelFormat> formats = {V4l2PixelFormat::Grey, V4l2PixelFormat::Y16,
                                          V4l2PixelFormat::Y10, V4l2PixelFormat::Yuyv,
                                          V4l2PixelFormat::Mjpeg};
  int width = 0;  ///< 0 (with height 0): the largest size of the chosen format
  int height = 0;
  double fps = 0.0;          ///< 0: the device's current frame rate; else the closest one offered
  int buffer_count = 4;      ///< mmap buffers requested, 2..32 (the driver may grant more)
  double exposure_ms = 0.0;  ///< > 0: manual exposure (auto exposure off)
  double gain = -1.0;        ///< >= 0: manual gain, in the device's V4L2_CID_GAIN units
  bool lock_auto_exposure = false;  ///< freeze the exposure the camera has chosen at start
  int poll_timeout_ms = 2000;       ///< longest wait for a frame before DeviceError
};

/// Throws ldsm::ConfigError naming the option when a value is out of range.
void validate(const V4l2Options& options);

/// One entry of a format's frame sizes: a discrete size (min == max) or a stepwise range, with
/// the frame rates the device offers at that size (at the largest size of a range).
struct V4l2FrameSize {
  int min_width = 0, max_width = 0, step_width = 1;
  int min_height = 0, max_height = 0, step_height = 1;
  std::vector<double> fps;  ///< discrete frame rates, highest first; empty when a range
  double min_fps = 0.0;     ///< continuous or stepwise rate range (0 when unknown)
  double max_fps = 0.0;
  bool isDiscrete() const { return min_width == max_width && min_height == max_height; }
  bool contains(int width, int height) const;
};

/// A pixel format the device offers (VIDIOC_ENUM_FMT) with its sizes (ENUM_FRAMESIZES) and
/// rates (ENUM_FRAMEINTERVALS).
struct V4l2FormatDescription {
  std::uint32_t fourcc = 0;
  std::string description;  ///< the driver's text
  bool supported = false;   ///< one ldsm converts (then `format` is set)
  V4l2PixelFormat format = V4l2PixelFormat::Grey;
  std::vector<V4l2FrameSize> sizes;
};

/// The negotiated stream.
struct V4l2Mode {
  V4l2PixelFormat format = V4l2PixelFormat::Grey;
  int width = 0;
  int height = 0;
  double fps = 0.0;  ///< requested frame rate (0: leave the device's)
};

/// Picks the first preferred format offered at the requested size (or its largest size), and the
/// offered rate closest to the requested one. Throws ldsm::DeviceError "<device>: format not
/// supported: ..." listing what the device offers.
V4l2Mode chooseV4l2Mode(const std::vector<V4l2FormatDescription>& offered,
                        const V4l2Options& options);

/// A human-readable table of formats, sizes and rates (for `ldsm record --list-formats`).
std::string describeV4l2Formats(const std::vector<V4l2FormatDescription>& formats);

/// Opens `device` only to enumerate its formats. Throws ldsm::DeviceError.
std::vector<V4l2FormatDescription> listV4l2Formats(
    const std::string& device, std::shared_ptr<V4l2Kernel> kernel = systemV4l2Kernel());

class V4l2Source : public FrameSource {
 public:
  /// Opens the device, negotiates the mode, sets the controls, maps the buffers and starts
  /// streaming. Throws ldsm::ConfigError for bad options, ldsm::DeviceError for device problems.
  explicit V4l2Source(const V4l2Options& options,
                      std::shared_ptr<V4l2Kernel> kernel = systemV4l2Kernel());
  ~V4l2Source() override;
  V4l2Source(const V4l2Source&) = delete;
  V4l2Source& operator=(const V4l2Source&) = delete;

  /// name "v4l2:<device>", the negotiated size, frame_count -1, the device's frame rate.
  SourceInfo info() const override;
  /// Waits for the next frame (at most the poll timeout), converts it into frame.image (buffer
  /// reused), sets the kernel timestamp (seconds on CLOCK_MONOTONIC, the clock of
  /// std::chrono::steady_clock) and the exposure read back from the device (NaN when it has no
  /// exposure control). Frames the driver flags as corrupt, truncated frames and undecodable
  /// MJPEG frames are skipped (skippedFrames()); too many in a row is a DeviceError.
  bool next(Frame& frame) override;

  const V4l2Mode& mode() const;
  const std::vector<V4l2FormatDescription>& offeredFormats() const;
  int bufferCount() const;             ///< buffers granted by the driver
  std::int64_t skippedFrames() const;  ///< corrupt or truncated frames skipped so far

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldsm::drivers
