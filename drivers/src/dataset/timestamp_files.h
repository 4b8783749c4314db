// Parsers of the per-frame timestamp files of the dataset layouts. Each returns one entry per data
// line with the line number, and throws ldsm::InputError "<file>:<line>: ..." on a malformed line.
#pragma once

#include <string>
#include <vector>

namespace ldsm::drivers::detail {

/// One frame of a timestamp file.
struct TimedEntry {
  double timestamp = 0.0;  ///< seconds
  double exposure_ms;      ///< NaN when the file does not give it
  std::string name;        ///< image file name / relative path, or the frame id for TUM-Mono
  int line = 0;            ///< 1-based line number in the file
};

/// TUM-Mono times.txt: "id timestamp_s [exposure_ms]".
std::vector<TimedEntry> readTumMonoTimes(const std::string& path);

/// EuRoC cam0/data.csv: "timestamp_ns,filename" (header line "#timestamp [ns],filename").
std::vector<TimedEntry> readEurocImageCsv(const std::string& path);

/// TUM RGB-D rgb.txt: "timestamp_s path" after '#' comment lines.
std::vector<TimedEntry> readTumRgbdList(const std::string& path);

/// KITTI odometry times.txt: one timestamp in seconds per line.
std::vector<TimedEntry> readKittiTimes(const std::string& path);

/// Throws ldsm::InputError naming `path` and the line when a timestamp is not strictly greater
/// than the one before it (backwards or duplicated).
void checkStrictlyIncreasing(const std::vector<TimedEntry>& entries, const std::string& path);

}  // namespace ldsm::drivers::detail
