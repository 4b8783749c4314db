#include "ldsm/drivers/sim/tum_mono_writer.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/image_file.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/drivers/atomic_file.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace fs = std::filesystem;
namespace {

void makeDirectory(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw Error(dir.string() + ": cannot create directory" + (ec ? " (" + ec.message() + ")" : ""));
}

int indexDigits(std::int64_t frames) {
  int digits = 5;
  for (std::int64_t limit = 100000; frames > limit; limit *= 10) ++digits;
  return digits;
}

// Shortest text that reads back as exactly `v`.
std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string frameName(std::int64_t index, int digits) {
  std::string s = std::to_string(index);
  if (static_cast<int>(s.size()) < digits)
    s.insert(0, static_cast<std::size_t>(digits) - s.size(), '0');
  return s;
}

// Removes images/<digits>.png files with an index >= frames (left over from a longer run).
void removeStaleFrames(const fs::path& images, std::int64_t frames) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(images, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string stem = it->path().stem().string();
    if (it->path().extension() != ".png" || stem.empty() || stem.size() > 12 ||
        stem.find_first_not_of("0123456789") != std::string::npos)
      continue;
    if (std::stoll(stem) >= frames) stale.push_back(it->path());
  }
  for (const fs::path& p : stale) fs::remove(p, ec);
}

}  // namespace

TumMonoWriteSummary writeTumMonoSequence(SimSource& source, const std::string& out_dir,
                                         const TumMonoWriteOptions& options,
                                         const SimProgress& progress) {
  if (!(std::fabs(options.focal_error) < 0.5))
    throw ConfigError("sim option focal_error = " + std::to_string(options.focal_error) +
                      " is outside (-0.5, 0.5)");
  const fs::path root(out_dir);
  const fs::path images = root / "images";
  makeDirectory(images);
  const std::int64_t frames = source.frameCount();
  const int digits = indexDigits(frames);

  // Calibration files first, so a partial sequence is still self-describing.
  GeometricCalibration written = source.geometricCalibration();
  written.input.fx *= 1.0 + options.focal_error;
  written.input.fy *= 1.0 + options.focal_error;
  calib::writeDsoCameraFile((root / "camera.txt").string(), written);
  const PhotometricCalibration& photometric = source.photometricCalibration();
  calib::writeInverseResponse((root / "pcalib.txt").string(), photometric.inverse_response);
  calib::writeVignette((root / "vignette.png").string(), photometric.vignette);
  writeTumTrajectory((root / "groundtruth.txt").string(), source.groundTruth());

  std::string times;
  Frame frame;
  for (std::int64_t i = 0; i < frames; ++i) {
    source.renderFrame(i, frame);
    const std::string name = frameName(i, digits);
    const fs::path file = images / (name + ".png");
    calib::writePng(file.string(), frame.image.view());
    times += name + ' ' + shortest(frame.timestamp) + ' ' + shortest(frame.exposure_ms) + '\n';
    if (progress) progress(i + 1, frames);
  }
  writeFileAtomically((root / "times.txt").string(), times);
  removeStaleFrames(images, frames);

  TumMonoWriteSummary summary;
  summary.frames = frames;
  summary.path_length_m = pathLength(source.groundTruth());
  summary.out_dir = out_dir;
  return summary;
}

TumMonoWriteSummary writeTumMonoSequence(SimSource& source, const std::string& out_dir,
                                         const SimProgress& progress) {
  return writeTumMonoSequence(source, out_dir, TumMonoWriteOptions{}, progress);
}

}  // namespace ldsm::drivers::sim
