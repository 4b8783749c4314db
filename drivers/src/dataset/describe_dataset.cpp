// describeDataset(): frame lists, timestamps and side files of every dataset layout.
#include <cmath>
#include <filesystem>
#include <limits>
#include <system_error>

#include "dataset/file_listing.h"
#include "dataset/timestamp_files.h"
#include "dataset/video_source.h"
#include "dataset/zip_archive.h"
#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/error.h"

namespace fs = std::filesystem;

namespace ldsm::drivers {
namespace {

using detail::TimedEntry;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

bool isDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

std::string str(const fs::path& p) {
  return p.string();
}

/// Throws when `file` is missing: "<file>: no such file (<layout> layout needs <needs>)".
void requireFile(const fs::path& file, const char* layout, const char* needs) {
  if (!isFile(file)) {
    throw InputError(str(file) + ": no such file (" + layout + " layout needs " + needs + ")");
  }
}

void setTimes(DatasetDescription& d, const std::vector<TimedEntry>& entries) {
  d.timestamps.clear();
  d.exposures_ms.clear();
  for (const auto& e : entries) {
    d.timestamps.push_back(e.timestamp);
    d.exposures_ms.push_back(e.exposure_ms);
  }
}

void checkCount(const DatasetDescription& d, const std::string& images_where) {
  if (d.images.size() != d.timestamps.size()) {
    throw InputError(d.timestamps_file + ": " + std::to_string(d.timestamps.size()) +
                     " timestamps but " + images_where + " holds " +
                     std::to_string(d.images.size()) + " images");
  }
}

/// Images named by a timestamp file relative to `dir`; each must exist.
void setListedImages(DatasetDescription& d, const std::vector<TimedEntry>& entries,
                     const fs::path& dir) {
  d.images.clear();
  for (const auto& e : entries) {
    const fs::path image = dir / e.name;
    if (!isFile(image)) {
      throw InputError(atLine(d.timestamps_file, e.line,
                              "image '" + e.name + "' not found (" + str(image) + ")"));
    }
    d.images.push_back(str(image));
  }
}

void describeTumMono(DatasetDescription& d) {
  const fs::path root(d.root);
  const char* needs = "times.txt and images/ or images.zip";
  requireFile(root / "times.txt", "tum-mono", needs);
  d.timestamps_file = str(root / "times.txt");
  const auto entries = detail::readTumMonoTimes(d.timestamps_file);
  detail::checkStrictlyIncreasing(entries, d.timestamps_file);
  setTimes(d, entries);
  std::string images_where;
  if (isDir(root / "images")) {
    d.images = detail::listImageFiles(str(root / "images"));
    images_where = str(root / "images");
  } else {
    requireFile(root / "images.zip", "tum-mono", needs);
    d.image_archive = str(root / "images.zip");
    const detail::ZipArchive archive(d.image_archive);
    d.images.clear();
    for (auto& name : archive.fileNames()) {
      if (hasImageExtension(name)) d.images.push_back(std::move(name));
    }
    detail::sortNaturally(d.images);
    images_where = d.image_archive;
  }
  checkCount(d, images_where);
}

void describeEuroc(DatasetDescription& d) {
  const fs::path root(d.root);
  const fs::path cam = isFile(root / "cam0/data.csv") ? root / "cam0" : root / "mav0/cam0";
  requireFile(cam / "data.csv", "euroc", "mav0/cam0/data.csv and mav0/cam0/data/");
  d.timestamps_file = str(cam / "data.csv");
  const auto entries = detail::readEurocImageCsv(d.timestamps_file);
  detail::checkStrictlyIncreasing(entries, d.timestamps_file);
  setTimes(d, entries);
  setListedImages(d, entries, cam / "data");
  if (d.calibration_kind == CalibrationFileKind::None && isFile(cam / "sensor.yaml")) {
    d.calibration_file = str(cam / "sensor.yaml");
    d.calibration_kind = CalibrationFileKind::CameraYaml;
  }
  const fs::path mav = cam.parent_path();
  if (d.groundtruth_file.empty() && isFile(mav / "state_groundtruth_estimate0/data.csv")) {
    d.groundtruth_file = str(mav / "state_groundtruth_estimate0/data.csv");
    d.groundtruth_format = TrajectoryFormat::EurocCsv;
  }
}

/// The KITTI sequence folder: `root` itself (image_0/ + times.txt) or its only sequences/NN.
fs::path kittiSequence(const fs::path& root) {
  if (isDir(root / "image_0") && isFile(root / "times.txt")) return root;
  std::vector<std::string> sequences;
  std::error_code ec;
  for (fs::directory_iterator it(root / "sequences", ec), end; !ec && it != end; ++it) {
    if (isDir(it->path() / "image_0")) sequences.push_back(it->path().filename().string());
  }
  if (sequences.empty()) {
    throw InputError(str(root) +
                     ": no KITTI sequence (kitti layout needs image_0/ and times.txt, or "
                     "sequences/NN/image_0/ and sequences/NN/times.txt)");
  }
  if (sequences.size() > 1) {
    detail::sortNaturally(sequences);
    std::string list;
    for (const auto& s : sequences) list += (list.empty() ? "" : ", ") + s;
    throw InputError(str(root / "sequences") + ": several sequences (" + list +
                     "); pass one sequence folder, e.g. " + str(root / "sequences" / sequences[0]));
  }
  return root / "sequences" / sequences[0];
}

void describeKitti(DatasetDescription& d) {
  const fs::path root(d.root);
  const fs::path seq = kittiSequence(root);
  requireFile(seq / "times.txt", "kitti", "image_0/ and times.txt");
  d.timestamps_file = str(seq / "times.txt");
  const auto entries = detail::readKittiTimes(d.timestamps_file);
  detail::checkStrictlyIncreasing(entries, d.timestamps_file);
  setTimes(d, entries);
  d.images = detail::listImageFiles(str(seq / "image_0"));
  checkCount(d, str(seq / "image_0"));
  if (d.calibration_kind == CalibrationFileKind::None && isFile(seq / "calib.txt")) {
    d.calibration_file = str(seq / "calib.txt");
    d.calibration_kind = CalibrationFileKind::KittiCalib;
    d.calibration_camera = 0;
  }
  if (d.groundtruth_file.empty()) {
    // poses/NN.txt beside sequences/ (dataset root given) or two levels up (sequence given).
    std::error_code ec;
    const fs::path seq_full = fs::weakly_canonical(seq, ec);
    const std::string name = seq_full.filename().string() + ".txt";
    const fs::path base = seq == root ? seq_full.parent_path().parent_path() : root;
    if (isFile(base / "poses" / name)) {
      d.groundtruth_file = str(base / "poses" / name);
      d.groundtruth_format = TrajectoryFormat::Kitti;
    }
  }
}

void describeTumRgbd(DatasetDescription& d) {
  const fs::path root(d.root);
  requireFile(root / "rgb.txt", "tum-rgbd", "rgb.txt");
  d.timestamps_file = str(root / "rgb.txt");
  const auto entries = detail::readTumRgbdList(d.timestamps_file);
  detail::checkStrictlyIncreasing(entries, d.timestamps_file);
  setTimes(d, entries);
  setListedImages(d, entries, root);
}

void describeFolder(DatasetDescription& d) {
  d.images = detail::listImageFiles(detail::imageFolderOf(d.root));
  d.timestamps.resize(d.images.size());
  d.exposures_ms.assign(d.images.size(), kNaN);
  for (std::size_t i = 0; i < d.images.size(); ++i) {
    d.timestamps[i] = static_cast<double>(i) / kAssumedFolderFps;
  }
  d.timestamps_assumed = true;
}

/// Decodes the first image for the size of the sequence.
void readFirstImageSize(DatasetDescription& d) {
  std::vector<unsigned char> bytes;
  std::string where;
  if (!d.image_archive.empty()) {
    const detail::ZipArchive archive(d.image_archive);
    archive.read(archive.indexOf(d.images.front()), bytes);
    where = d.image_archive + ":" + d.images.front();
  } else {
    calib::readFileBytes(d.images.front(), bytes);
    where = d.images.front();
  }
  ImageU8 image;
  calib::decodeImage(bytes.data(), bytes.size(), where, image);
  d.width = image.width();
  d.height = image.height();
}

/// Side files every layout may have at its root; layout readers add their own fallbacks after.
void findCommonSideFiles(DatasetDescription& d) {
  const fs::path root(d.root);
  if (isFile(root / "camera.txt")) {
    d.calibration_file = str(root / "camera.txt");
    d.calibration_kind = CalibrationFileKind::DsoCamera;
  }
  if (isFile(root / "pcalib.txt")) d.photometric_response_file = str(root / "pcalib.txt");
  if (isFile(root / "vignette.png")) d.vignette_file = str(root / "vignette.png");
  if (isFile(root / "groundtruth.txt")) {
    d.groundtruth_file = str(root / "groundtruth.txt");
    d.groundtruth_format = TrajectoryFormat::Tum;
  }
}

/// Ground truth of lower priority than the layout's own (TUM-Mono's groundtruthSync.txt, a body
/// trajectory in TUM format).
void findFallbackGroundTruth(DatasetDescription& d) {
  const fs::path root(d.root);
  for (const char* name : {"groundtruthSync.txt", "groundtruth_body.txt"}) {
    if (d.groundtruth_file.empty() && isFile(root / name)) {
      d.groundtruth_file = str(root / name);
      d.groundtruth_format = TrajectoryFormat::Tum;
    }
  }
}

}  // namespace

const char* toString(CalibrationFileKind kind) {
  switch (kind) {
    case CalibrationFileKind::None:
      return "none";
    case CalibrationFileKind::DsoCamera:
      return "dso-camera";
    case CalibrationFileKind::CameraYaml:
      return "camera-yaml";
    case CalibrationFileKind::KittiCalib:
      return "kitti-calib";
  }
  return "unknown";
}

bool DatasetDescription::hasExposures() const {
  for (double e : exposures_ms) {
    if (!std::isnan(e)) return true;
  }
  return false;
}

DatasetDescription describeDataset(const std::string& path, DatasetFormat format) {
  if (format == DatasetFormat::Auto) {
    format = detectDatasetFormat(path);
  } else {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError(path + ": no such file or directory");
  }
  DatasetDescription d;
  d.format = format;
  d.root = path;
  if (format == DatasetFormat::Video) {
    detail::describeVideo(d);
    return d;
  }
  if (!isDir(path)) {
    throw InputError(path + ": not a folder (the " + std::string(toString(format)) +
                     " layout is a folder)");
  }
  findCommonSideFiles(d);
  switch (format) {
    case DatasetFormat::TumMono:
      describeTumMono(d);
      break;
    case DatasetFormat::Euroc:
      describeEuroc(d);
      break;
    case DatasetFormat::Kitti:
      describeKitti(d);
      break;
    case DatasetFormat::TumRgbd:
      describeTumRgbd(d);
      break;
    case DatasetFormat::Folder:
      describeFolder(d);
      break;
    case DatasetFormat::Auto:
    case DatasetFormat::Video:
      break;
  }
  findFallbackGroundTruth(d);
  if (d.images.empty()) {
    throw InputError(path + ": dataset has no images (" + toString(format) + " layout)");
  }
  d.frame_count = static_cast<std::int64_t>(d.images.size());
  if (d.timestamps_assumed) {
    d.nominal_fps = kAssumedFolderFps;
  } else if (d.timestamps.size() >= 2) {
    d.nominal_fps =
        static_cast<double>(d.timestamps.size() - 1) / (d.timestamps.back() - d.timestamps.front());
  }
  readFirstImageSize(d);
  return d;
}

}  // namespace ldsm::drivers
