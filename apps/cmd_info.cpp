// `ldsm info`: what a dataset folder (or video file) holds: layout, frames, resolution, time span,
// exposure, calibration, photometric files and ground truth. Exits 1 with "ldsm: error: ..." when
// the dataset cannot be read, and 1 after the report when a side file (calibration, ground truth)
// is present but broken.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "ldsm/calib/calibration_loader.h"
#include "ldsm/calib/describe_calibration.h"
#include "ldsm/calib/kitti_calib.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"

namespace ldsm::app {
namespace {

struct InfoOptions {
  std::string dataset;
  std::string format = "auto";
  bool verify = false;
};

/// printf into a std::string.
template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buf[1024];
  std::snprintf(buf, sizeof(buf), fmt, args...);
  return buf;
}

void printField(const char* name, const std::string& value) {
  std::printf("%-13s %s\n", (std::string(name) + ":").c_str(), value.c_str());
}

/// Further lines of a field, aligned under its value.
void printContinuation(const std::string& text) {
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::printf("%-13s %s\n", "", text.substr(begin, end - begin).c_str());
    begin = end + 1;
  }
}

std::string timeSpan(const drivers::DatasetDescription& d) {
  if (d.format == drivers::DatasetFormat::Video) {
    if (d.nominal_fps <= 0.0) return "unknown (the video reports no frame rate)";
    if (d.frame_count <= 0) return format("unknown length at %.3f fps", d.nominal_fps);
    return format("~%.3f s at %.3f fps (from the container)",
                  static_cast<double>(d.frame_count) / d.nominal_fps, d.nominal_fps);
  }
  const double duration = d.lastTimestamp() - d.firstTimestamp();
  std::string s =
      format("%.6f .. %.6f s (duration %.3f s", d.firstTimestamp(), d.lastTimestamp(), duration);
  s += d.nominal_fps > 0.0 ? format(", mean %.3f fps)", d.nominal_fps) : std::string(")");
  if (d.timestamps_assumed) s += format(" -- no timestamps: %.0f Hz assumed", d.nominal_fps);
  return s;
}

std::string exposure(const drivers::DatasetDescription& d) {
  if (!d.hasExposures()) return "unknown";
  double lo = INFINITY, hi = -INFINITY;
  std::size_t known = 0;
  for (double e : d.exposures_ms) {
    if (std::isnan(e)) continue;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
    ++known;
  }
  return format("known for %zu of %zu frames, %.3f .. %.3f ms", known, d.exposures_ms.size(), lo,
                hi);
}

/// Prints the calibration field with the parsed values; returns false when the file is present
/// but unreadable or invalid.
bool printCalibration(const drivers::DatasetDescription& d) {
  if (d.calibration_kind == drivers::CalibrationFileKind::None) {
    printField("calibration", "none found");
    return true;
  }
  printField("calibration",
             d.calibration_file + " (" + drivers::toString(d.calibration_kind) + ")");
  try {
    const GeometricCalibration calibration =
        d.calibration_kind == drivers::CalibrationFileKind::KittiCalib
            ? calib::readKittiCalib(d.calibration_file, d.calibration_camera, d.width, d.height)
            : calib::loadGeometricCalibration(d.calibration_file, d.width, d.height);
    printContinuation(calib::describe(calibration));
    return true;
  } catch (const InputError& e) {
    printContinuation(std::string("error: ") + e.what());
    return false;
  }
}

/// Prints the photometric field with the parsed values; returns false when a file is present but
/// unreadable or invalid.
bool printPhotometric(const drivers::DatasetDescription& d) {
  if (d.photometric_response_file.empty() && d.vignette_file.empty()) {
    printField("photometric", "none (no pcalib.txt or vignette.png)");
    return true;
  }
  if (!d.photometric_response_file.empty()) {
    printField("photometric", d.photometric_response_file + " (response)");
  }
  if (!d.vignette_file.empty()) {
    const std::string vignette = d.vignette_file + " (vignette)";
    if (d.photometric_response_file.empty()) {
      printField("photometric", vignette);
    } else {
      printContinuation(vignette);
    }
  }
  try {
    const PhotometricCalibration photometric = calib::loadPhotometricCalibration(
        d.photometric_response_file, d.vignette_file, d.width, d.height);
    printContinuation(calib::describe(photometric));
    return true;
  } catch (const InputError& e) {
    printContinuation(std::string("error: ") + e.what());
    return false;
  }
}

/// Prints the ground-truth field; returns false when the file is present but unreadable.
bool printGroundTruth(const drivers::DatasetDescription& d) {
  if (d.groundtruth_file.empty()) {
    printField("ground truth", "none");
    return true;
  }
  const char* name = drivers::trajectoryFormatName(d.groundtruth_format);
  try {
    const bool kitti = d.groundtruth_format == drivers::TrajectoryFormat::Kitti;
    const Trajectory poses = drivers::readTrajectory(d.groundtruth_file, d.groundtruth_format,
                                                     kitti ? &d.timestamps : nullptr);
    printField("ground truth",
               format("%s (%s, %zu poses, %.6f .. %.6f s)", d.groundtruth_file.c_str(), name,
                      poses.size(), poses.front().timestamp, poses.back().timestamp));
    return true;
  } catch (const InputError& e) {
    printField("ground truth", d.groundtruth_file + " (" + name + ")");
    printContinuation(std::string("error: ") + e.what());
    return false;
  }
}

/// Decodes every frame; throws ldsm::InputError naming the first bad image.
std::string verifyFrames(const drivers::DatasetDescription& d) {
  auto source = drivers::openDataset(d);
  drivers::Frame frame;
  std::int64_t n = 0;
  while (source->next(frame)) ++n;
  return format("all %lld frames decode at %d x %d", static_cast<long long>(n), d.width, d.height);
}

int runInfo(const InfoOptions& options) {
  const drivers::DatasetDescription d =
      drivers::describeDataset(options.dataset, drivers::parseDatasetFormat(options.format));
  printField("dataset", d.root);
  printField("layout", drivers::toString(d.format));
  if (d.format == drivers::DatasetFormat::Video) {
    printField("frames", d.frame_count >= 0 ? format("%lld (as reported by the container)",
                                                     static_cast<long long>(d.frame_count))
                                            : std::string("unknown"));
  } else {
    std::string frames = std::to_string(d.frame_count);
    if (!d.image_archive.empty()) frames += " (in " + d.image_archive + ")";
    printField("frames", frames);
  }
  printField("resolution", format("%d x %d", d.width, d.height));
  printField("time span", timeSpan(d));
  if (!d.timestamps_file.empty()) printField("timestamps", d.timestamps_file);
  printField("exposure", exposure(d));
  bool side_files_ok = printCalibration(d);
  side_files_ok = printPhotometric(d) && side_files_ok;
  side_files_ok = printGroundTruth(d) && side_files_ok;
  if (options.verify) printField("verified", verifyFrames(d));
  std::fflush(stdout);
  return side_files_ok ? 0 : 1;
}

}  // namespace

void addInfoCommand(CLI::App& app, CommandResult& result) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand("info",
                                     "Describe a dataset: layout, frames, time span, "
                                     "calibration, ground truth");
  sub->add_option("--dataset", options->dataset, "Dataset folder or video file")->required();
  sub->add_option("--format", options->format, "Dataset layout")
      ->check(CLI::IsMember({"auto", "tum-mono", "euroc", "kitti", "tum-rgbd", "folder", "video"}))
      ->capture_default_str();
  sub->add_flag("--verify", options->verify,
                "Decode every frame (finds unreadable or wrongly sized images)");
  sub->callback([options, &result]() { result.exit_code = runInfo(*options); });
}

}  // namespace ldsm::app
