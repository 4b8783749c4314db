// Snapshots of a finished run for `ldsm view DIR`: its output folder (trajectory.txt,
// keyframes.txt, points.ply, stats.json, as `ldsm run` writes them) read once.
#pragma once

#include <string>

#include "snapshot.h"

namespace ldsm::viewer {

class RunFolderSource : public SnapshotSource {
 public:
  /// Reads the folder. A missing file is left out (with a warning); a malformed one throws
  /// ldsm::InputError naming it, and so does a folder with none of the four files.
  explicit RunFolderSource(const std::string& dir);
  ViewerSnapshot snapshot(bool with_points) override;

 private:
  ViewerSnapshot snapshot_;
};

}  // namespace ldsm::viewer
