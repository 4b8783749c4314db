// Frame poses a long run keeps on disk instead of in memory: the poses System::takeRetiredFrames()
// hands out (system.frame_history) are appended to a binary file as they come, and read back
// when the whole trajectory is written. A private working file of one process (host byte order,
// no format version): the trajectory's outputs are the TUM files written from it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "ldsm/types.h"

namespace ldsm::drivers {

class TrajectorySpill {
 public:
  /// Nothing is created until the first append(); a file left at `path` by an earlier run is
  /// replaced then.
  explicit TrajectorySpill(std::string path);
  ~TrajectorySpill();
  TrajectorySpill(const TrajectorySpill&) = delete;
  TrajectorySpill& operator=(const TrajectorySpill&) = delete;

  /// Appends poses and flushes them to the file. Throws ldsm::Error naming the file when it
  /// cannot be written (full disk); the poses that could not be written are kept and written
  /// with the next append().
  void append(const Trajectory& poses);
  /// Every pose appended so far, oldest first, followed by `newer`.
  Trajectory read(const Trajectory& newer = {}) const;
  /// Poses on disk.
  std::int64_t size() const { return written_; }
  const std::string& path() const { return path_; }
  /// Deletes the file (the poses are gone).
  void remove();

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::int64_t written_ = 0;
  Trajectory pending_;  ///< taken but not yet written (the disk was full)
};

}  // namespace ldsm::drivers
