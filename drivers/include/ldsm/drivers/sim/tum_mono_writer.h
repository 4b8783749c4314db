// Writes a synthetic sequence in the TUM-Mono layout, so it can be read back like a recorded one:
//   out_dir/images/00000.png ...   8-bit grey frames
//   out_dir/times.txt              "id timestamp exposure_ms" per frame
//   out_dir/camera.txt             DSO camera file (pinhole, output none)
//   out_dir/pcalib.txt             inverse response G^-1 (256 values)
//   out_dir/vignette.png           16-bit vignette
//   out_dir/groundtruth.txt        camera-to-world poses, TUM format
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "ldsm/drivers/sim/sim_source.h"

namespace ldsm::drivers::sim {

struct TumMonoWriteOptions {
  /// camera.txt gets fx and fy scaled by (1 + focal_error) while the images are rendered with the
  /// true camera: a deliberately wrong calibration that makes odometry drift realistically.
  double focal_error = 0.0;
};

struct TumMonoWriteSummary {
  std::int64_t frames = 0;
  double path_length_m = 0.0;  ///< length of the ground-truth path
  std::string out_dir;
};

/// Called after each written frame with (frames done, total).
using SimProgress = std::function<void(std::int64_t done, std::int64_t total)>;

/// Renders every frame of `source` (from frame 0, whatever its stream position) into `out_dir`
/// (created if needed). Frame files of an earlier, longer run in out_dir/images are removed.
/// Throws ldsm::ConfigError for |focal_error| >= 0.5, ldsm::Error naming the file that cannot be
/// written.
TumMonoWriteSummary writeTumMonoSequence(SimSource& source, const std::string& out_dir,
                                         const TumMonoWriteOptions& options = {},
                                         const SimProgress& progress = {});

/// The same with default options (true calibration in camera.txt).
TumMonoWriteSummary writeTumMonoSequence(SimSource& source, const std::string& out_dir,
                                         const SimProgress& progress);

}  // namespace ldsm::drivers::sim
