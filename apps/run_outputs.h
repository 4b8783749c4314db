// What `ldsm run` writes to its output folder: trajectory.txt and keyframes.txt (TUM format),
// points.ply (the map), stats.json (counts, per-stage timing, the frame pipeline's drops,
// queue depths and latencies, memory, status, accuracy, the calibration refinement over time)
// and the camera the run ended with (the online refinement applied to the given calibration) as
// camera.txt (DSO format) and camchain.yaml (Kalibr).
#pragma once

#include <optional>
#include <string>

#include "ldsm/eval/ate.h"
#include "ldsm/system.h"

namespace ldsm::app {

struct RunSummary {
  std::string dataset;          ///< dataset path or camera device
  std::string status;           ///< "finished", "stopped: <reason>", ...
  std::string mode;             ///< "deterministic", "offline" or "live" (camera, real-time replay)
  double realtime_speed = 0.0;  ///< replay speed with --realtime, 0 otherwise
  double max_source_lateness_ms = 0.0;  ///< --realtime: latest a frame was released
  double wall_seconds = 0.0;
  double ms_per_frame = 0.0;  ///< mean processing time per frame
  double peak_rss_mb = 0.0;
  std::optional<eval::AteResult> ate;
  /// The calibration the run was given (or guessed with --fov) and where it came from: the
  /// camera the engine ended with is written back in its model (camera.txt, camchain.yaml).
  /// Not written when its input size is 0.
  GeometricCalibration calibration;
  std::string calibration_source;
};

/// Peak resident memory of this process so far, MB.
double peakRssMb();

/// Writes trajectory.txt, keyframes.txt, points.ply, stats.json, camera.txt and camchain.yaml
/// into `dir` (created when missing). Every file is replaced atomically (a crash or a full disk
/// never leaves a truncated one); each is tried even when another failed, and the failures are
/// thrown together as one Error naming the files.
/// `frames` is the trajectory written (System::trajectory(), after the frames it retired).
void writeRunOutputs(const std::string& dir, const System& system, const Trajectory& frames,
                     const RunSummary& summary);

/// trajectory.txt (`frames`) and keyframes.txt alone, as far as the run has got (the periodic
/// flush of a long run), the same way.
void writeTrajectoriesSoFar(const std::string& dir, const System& system, const Trajectory& frames);

}  // namespace ldsm::app
