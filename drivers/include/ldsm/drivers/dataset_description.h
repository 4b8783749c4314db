// What a recorded sequence holds, read from its folder without decoding more than its first image:
// the frame list with timestamps and exposures, and the calibration, photometric and ground-truth
// files found beside it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/drivers/dataset_format.h"
#include "ldsm/drivers/trajectory_io.h"

namespace ldsm::drivers {

/// Kind of a geometric calibration file found in a dataset.
enum class CalibrationFileKind {
  None,        ///< no calibration file found
  DsoCamera,   ///< DSO camera.txt
  CameraYaml,  ///< EuRoC sensor.yaml or Kalibr camchain YAML
  KittiCalib,  ///< KITTI calib.txt (projection matrices P0..P3)
};

/// "none", "dso-camera", "camera-yaml" or "kitti-calib".
const char* toString(CalibrationFileKind kind);

/// Rate at which frames of a layout without timestamps (plain folder) are assumed to be taken.
inline constexpr double kAssumedFolderFps = 30.0;

struct DatasetDescription {
  DatasetFormat format = DatasetFormat::Auto;
  std::string root;             ///< the folder (or video file) described
  std::string timestamps_file;  ///< times.txt / data.csv / rgb.txt; empty when there is none
  /// The zip archive holding the images (TUM-Mono images.zip); empty when images are files.
  std::string image_archive;
  /// Image file paths, or entry names inside image_archive, in stream order. Empty for Video.
  std::vector<std::string> images;
  /// Seconds, strictly increasing, one per image. Empty for Video (decoded on the fly).
  std::vector<double> timestamps;
  /// Milliseconds, one per image; NaN when unknown.
  std::vector<double> exposures_ms;
  /// True when the layout has no timestamps and they were made up from a nominal rate.
  bool timestamps_assumed = false;
  /// Number of frames: images.size(), or for Video the count the container reports (-1 unknown).
  std::int64_t frame_count = 0;
  /// Mean frame rate over the sequence (Video: the container's rate), 0 when unknown.
  double nominal_fps = 0.0;

  std::string calibration_file;  ///< empty when none was found
  CalibrationFileKind calibration_kind = CalibrationFileKind::None;
  int calibration_camera = 0;  ///< camera index inside a KITTI calib.txt (P0 for image_0)

  std::string photometric_response_file;  ///< pcalib.txt (inverse response), empty when absent
  std::string vignette_file;              ///< vignette.png, empty when absent

  std::string groundtruth_file;  ///< empty when no ground truth was found
  TrajectoryFormat groundtruth_format = TrajectoryFormat::Auto;

  int width = 0;  ///< size of the first image (all images must have it)
  int height = 0;

  /// True when at least one frame has a known exposure time.
  bool hasExposures() const;
  /// First and last timestamps (0 when there are none).
  double firstTimestamp() const { return timestamps.empty() ? 0.0 : timestamps.front(); }
  double lastTimestamp() const { return timestamps.empty() ? 0.0 : timestamps.back(); }
};

/// Reads the layout of `path` (detected when `format` is Auto): lists the images, parses and
/// checks the timestamps, decodes the first image for its size and finds calibration,
/// photometric and ground-truth files. Throws ldsm::InputError naming the file (and line) at
/// fault: missing folder, unknown layout, malformed timestamp line, non-increasing timestamps,
/// image count different from the timestamp count, missing or unreadable first image, no images.
DatasetDescription describeDataset(const std::string& path,
                                   DatasetFormat format = DatasetFormat::Auto);

}  // namespace ldsm::drivers
