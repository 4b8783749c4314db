// What `ldsm run` writes to its output folder: trajectory.txt and keyframes.txt (TUM format),
// points.ply (the map) and stats.json (counts, per-stage timing, memory, status, accuracy).
#pragma once

#include <optional>
#include <string>

#include "ldsm/eval/ate.h"
#include "ldsm/system.h"

namespace ldsm::app {

struct RunSummary {
  std::string dataset;
  std::string status;  ///< "finished", "stopped: <reason>", ...
  double wall_seconds = 0.0;
  double ms_per_frame = 0.0;  ///< mean processing time per frame
  double peak_rss_mb = 0.0;
  std::optional<eval::AteResult> ate;
};

/// Peak resident memory of this process so far, MB.
double peakRssMb();

/// Writes trajectory.txt, keyframes.txt, points.ply and stats.json into `dir` (created when
/// missing). Every file is replaced atomically.
void writeRunOutputs(const std::string& dir, const System& system, const RunSummary& summary);

}  // namespace ldsm::app
