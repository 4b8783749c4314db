// Timestamp file parsers of the TUM-Mono, EuRoC, TUM RGB-D and KITTI layouts.
#include "dataset/timestamp_files.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "dataset/text_lines.h"
#include "ldsm/error.h"

namespace ldsm::drivers::detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string joined(const std::vector<std::string>& fields) {
  std::string s;
  for (const auto& f : fields) s += (s.empty() ? "" : " ") + f;
  return s;
}

double timestampField(const std::string& path, const TextLine& line, std::size_t index,
                      const char* expected) {
  double t = 0.0;
  if (!parseFiniteDouble(line.fields[index], t)) {
    throw InputError(atLine(
        path, line.number,
        "timestamp '" + line.fields[index] + "' is not a number (expected " + expected + ")"));
  }
  return t;
}

}  // namespace

std::vector<TimedEntry> readTumMonoTimes(const std::string& path) {
  std::vector<TimedEntry> entries;
  for (const TextLine& line : readDataLines(path)) {
    if (line.fields.size() != 2 && line.fields.size() != 3) {
      throw InputError(
          atLine(path, line.number,
                 "expected 'id timestamp [exposure_ms]', got '" + joined(line.fields) + "'"));
    }
    std::int64_t id = 0;
    if (!parseInt64(line.fields[0], id) || id < 0) {
      throw InputError(atLine(path, line.number,
                              "frame id '" + line.fields[0] + "' is not a non-negative integer"));
    }
    TimedEntry e;
    e.name = line.fields[0];
    e.line = line.number;
    e.timestamp = timestampField(path, line, 1, "'id timestamp [exposure_ms]'");
    e.exposure_ms = kNaN;
    if (line.fields.size() == 3) {
      if (!parseFiniteDouble(line.fields[2], e.exposure_ms) || e.exposure_ms <= 0.0) {
        throw InputError(
            atLine(path, line.number,
                   "exposure '" + line.fields[2] + "' is not a positive number of milliseconds"));
      }
    }
    entries.push_back(std::move(e));
  }
  return entries;
}

std::vector<TimedEntry> readEurocImageCsv(const std::string& path) {
  std::vector<TimedEntry> entries;
  for (const TextLine& line : readDataLines(path, ',')) {
    if (line.fields.size() != 2 || line.fields[1].empty()) {
      throw InputError(
          atLine(path, line.number,
                 "expected 'timestamp_ns,filename', got '" + joined(line.fields) + "'"));
    }
    std::int64_t ns = 0;
    if (!parseInt64(line.fields[0], ns) || ns < 0) {
      throw InputError(atLine(
          path, line.number,
          "timestamp '" + line.fields[0] + "' is not a non-negative integer of nanoseconds"));
    }
    TimedEntry e;
    // Whole seconds and the fraction separately keep the nanoseconds exact before rounding.
    e.timestamp =
        static_cast<double>(ns / 1000000000) + static_cast<double>(ns % 1000000000) * 1e-9;
    e.exposure_ms = kNaN;
    e.name = line.fields[1];
    e.line = line.number;
    entries.push_back(std::move(e));
  }
  return entries;
}

std::vector<TimedEntry> readTumRgbdList(const std::string& path) {
  std::vector<TimedEntry> entries;
  for (const TextLine& line : readDataLines(path)) {
    if (line.fields.size() != 2) {
      throw InputError(atLine(path, line.number,
                              "expected 'timestamp path', got '" + joined(line.fields) + "'"));
    }
    TimedEntry e;
    e.timestamp = timestampField(path, line, 0, "'timestamp path'");
    e.exposure_ms = kNaN;
    e.name = line.fields[1];
    e.line = line.number;
    entries.push_back(std::move(e));
  }
  return entries;
}

std::vector<TimedEntry> readKittiTimes(const std::string& path) {
  std::vector<TimedEntry> entries;
  for (const TextLine& line : readDataLines(path)) {
    if (line.fields.size() != 1) {
      throw InputError(
          atLine(path, line.number,
                 "expected one timestamp in seconds, got '" + joined(line.fields) + "'"));
    }
    TimedEntry e;
    e.timestamp = timestampField(path, line, 0, "seconds");
    e.exposure_ms = kNaN;
    e.line = line.number;
    entries.push_back(std::move(e));
  }
  return entries;
}

void checkStrictlyIncreasing(const std::vector<TimedEntry>& entries, const std::string& path) {
  for (std::size_t i = 1; i < entries.size(); ++i) {
    if (!(entries[i].timestamp > entries[i - 1].timestamp)) {
      const bool duplicate = entries[i].timestamp == entries[i - 1].timestamp;
      throw InputError(atLine(path, entries[i].line,
                              std::string(duplicate ? "duplicated" : "non-monotonic") +
                                  " timestamp " + std::to_string(entries[i].timestamp) + " (line " +
                                  std::to_string(entries[i - 1].line) + " has " +
                                  std::to_string(entries[i - 1].timestamp) +
                                  "); timestamps must increase"));
    }
  }
}

}  // namespace ldsm::drivers::detail
