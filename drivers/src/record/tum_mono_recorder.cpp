#include "ldsm/drivers/tum_mono_recorder.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "ldsm/calib/image_file.h"
#include "ldsm/error.h"

namespace ldsm::drivers {
namespace fs = std::filesystem;
namespace {

constexpr int kNameDigits = 6;

std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string frameName(std::int64_t index) {
  std::string s = std::to_string(index);
  if (s.size() < kNameDigits) s.insert(0, kNameDigits - s.size(), '0');
  return s;
}

bool isFrameFile(const fs::path& p) {
  const std::string stem = p.stem().string();
  return p.extension() == ".png" && !stem.empty() &&
         stem.find_first_not_of("0123456789") == std::string::npos;
}

/// Refuses (or with `overwrite` clears) an earlier recording: times.txt and numbered images.
void prepareFolder(const fs::path& root, const fs::path& images, bool overwrite) {
  std::error_code ec;
  std::vector<fs::path> frames;
  for (fs::directory_iterator it(images, ec), end; !ec && it != end; it.increment(ec))
    if (isFrameFile(it->path())) frames.push_back(it->path());
  const bool has_times = fs::exists(root / "times.txt", ec);
  if ((has_times || !frames.empty()) && !overwrite)
    throw Error(root.string() +
                ": already holds a recording (times.txt or images/*.png); choose another output "
                "folder or overwrite it");
  for (const fs::path& p : frames) fs::remove(p, ec);
  fs::remove(root / "times.txt", ec);
  fs::create_directories(images, ec);
  if (!fs::is_directory(images, ec))
    throw Error(images.string() + ": cannot create directory" +
                (ec ? " (" + ec.message() + ")" : ""));
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

RecordSummary recordTumMono(FrameSource& source, const std::string& out_dir,
                            const RecordOptions& options, const RecordCallback& on_frame) {
  if (options.max_frames < 0)
    throw ConfigError("record: max_frames = " + std::to_string(options.max_frames) +
                      " is negative (0: no limit)");
  if (options.png_compression < 0 || options.png_compression > 9)
    throw ConfigError("record: png_compression = " + std::to_string(options.png_compression) +
                      " is outside 0..9");
  const fs::path root(out_dir);
  const fs::path images = root / "images";
  prepareFolder(root, images, options.overwrite);
  const std::string times_path = (root / "times.txt").string();
  std::unique_ptr<std::FILE, FileCloser> times(std::fopen(times_path.c_str(), "w"));
  if (!times) throw Error(times_path + ": cannot open for writing");

  RecordSummary summary;
  summary.out_dir = out_dir;
  const double period = source.info().nominal_fps > 0.0 ? 1.0 / source.info().nominal_fps : 0.0;
  calib::PngWriteOptions png;
  png.compression_level = options.png_compression;
  Frame frame;
  for (;;) {
    if (options.max_frames > 0 && summary.frames >= options.max_frames) break;
    try {
      if (!source.next(frame)) break;
    } catch (const DeviceError& e) {
      times.reset();
      throw DeviceError(std::string(e.what()) + "; " + std::to_string(summary.frames) +
                        " frames recorded so far are kept in " + out_dir);
    } catch (const InputError& e) {
      times.reset();
      throw InputError(std::string(e.what()) + "; " + std::to_string(summary.frames) +
                       " frames recorded so far are kept in " + out_dir);
    }
    if (summary.frames > 0 && !(frame.timestamp > summary.last_timestamp)) {
      ++summary.out_of_order;
      continue;
    }
    if (summary.frames > 0 && period > 0.0 &&
        frame.timestamp - summary.last_timestamp > 1.5 * period)
      ++summary.gaps;
    const std::string name = frameName(summary.frames);
    calib::writePng((images / (name + ".png")).string(), frame.image.view(), png);
    std::string line = name + ' ' + shortest(frame.timestamp);
    if (std::isfinite(frame.exposure_ms) && frame.exposure_ms > 0.0)
      line += ' ' + shortest(frame.exposure_ms);
    line += '\n';
    if (std::fputs(line.c_str(), times.get()) < 0 || std::fflush(times.get()) != 0)
      throw Error(times_path + ": write error");
    if (summary.frames == 0) summary.first_timestamp = frame.timestamp;
    summary.last_timestamp = frame.timestamp;
    ++summary.frames;
    if (on_frame && !on_frame(frame, summary.frames)) break;
  }
  if (std::fclose(times.release()) != 0) throw Error(times_path + ": write error");
  return summary;
}

}  // namespace ldsm::drivers
