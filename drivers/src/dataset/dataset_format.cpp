// Dataset format names and layout detection.
#include "ldsm/drivers/dataset_format.h"

#include "dataset/file_listing.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <string_view>
#include <system_error>

#include "ldsm/error.h"

namespace fs = std::filesystem;

namespace ldsm::drivers {
namespace {

struct FormatName {
  DatasetFormat format;
  const char* name;
};

constexpr std::array<FormatName, 7> kFormatNames{{
    {DatasetFormat::Auto, "auto"},
    {DatasetFormat::TumMono, "tum-mono"},
    {DatasetFormat::Euroc, "euroc"},
    {DatasetFormat::Kitti, "kitti"},
    {DatasetFormat::TumRgbd, "tum-rgbd"},
    {DatasetFormat::Folder, "folder"},
    {DatasetFormat::Video, "video"},
}};

std::string lowerExtension(const std::string& file_name) {
  std::string ext = fs::path(file_name).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

template <std::size_t N>
bool isOneOf(const std::string& ext, const std::array<std::string_view, N>& list) {
  return std::find(list.begin(), list.end(), ext) != list.end();
}

bool isDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

bool hasKittiSequences(const fs::path& root) {
  std::error_code ec;
  fs::directory_iterator it(root / "sequences", ec);
  if (ec) return false;
  for (const auto& entry : it) {
    if (isDir(entry.path() / "image_0")) return true;
  }
  return false;
}

bool containsImages(const fs::path& root) {
  std::error_code ec;
  fs::directory_iterator it(root, ec);
  if (ec) return false;
  for (const auto& entry : it) {
    if (isFile(entry.path()) && hasImageExtension(entry.path().filename().string())) return true;
  }
  return false;
}

}  // namespace

const char* toString(DatasetFormat format) {
  for (const auto& f : kFormatNames) {
    if (f.format == format) return f.name;
  }
  return "unknown";
}

DatasetFormat parseDatasetFormat(const std::string& name) {
  for (const auto& f : kFormatNames) {
    if (name == f.name) return f.format;
  }
  std::string accepted;
  for (const auto& f : kFormatNames) accepted += std::string(accepted.empty() ? "" : ", ") + f.name;
  throw ConfigError("unknown dataset format '" + name + "' (accepted: " + accepted + ")");
}

bool hasImageExtension(const std::string& file_name) {
  static constexpr std::array<std::string_view, 10> kExts{
      ".png", ".jpg", ".jpeg", ".bmp", ".pgm", ".ppm", ".pnm", ".tif", ".tiff", ".webp"};
  return isOneOf(lowerExtension(file_name), kExts);
}

bool hasVideoExtension(const std::string& file_name) {
  static constexpr std::array<std::string_view, 12> kExts{".mp4",  ".avi", ".mkv", ".mov",
                                                          ".webm", ".m4v", ".mpg", ".mpeg",
                                                          ".wmv",  ".flv", ".ogv", ".mjpeg"};
  return isOneOf(lowerExtension(file_name), kExts);
}

DatasetFormat detectDatasetFormat(const std::string& path) {
  const fs::path root(path);
  std::error_code ec;
  const fs::file_status status = fs::status(root, ec);
  if (ec || !fs::exists(status)) throw InputError(path + ": no such file or directory");
  if (fs::is_regular_file(status)) {
    if (hasVideoExtension(path)) return DatasetFormat::Video;
    throw InputError(path +
                     ": not a dataset: a file that is not a video (expected a dataset folder or a "
                     "video file such as .mp4, .avi, .mkv)");
  }
  if (!fs::is_directory(status)) throw InputError(path + ": not a folder or a video file");

  if (isFile(root / "mav0/cam0/data.csv") || isFile(root / "cam0/data.csv")) {
    return DatasetFormat::Euroc;
  }
  if (hasKittiSequences(root) || (isDir(root / "image_0") && isFile(root / "times.txt"))) {
    return DatasetFormat::Kitti;
  }
  if (isFile(root / "rgb.txt")) return DatasetFormat::TumRgbd;
  if (isFile(root / "times.txt") && (isDir(root / "images") || isFile(root / "images.zip"))) {
    return DatasetFormat::TumMono;
  }
  if (containsImages(root) || containsImages(detail::imageFolderOf(root.string())))
    return DatasetFormat::Folder;
  throw InputError(path +
                   ": unknown dataset layout: looked for mav0/cam0/data.csv or cam0/data.csv "
                   "(euroc), sequences/NN/image_0 or image_0/ + times.txt (kitti), rgb.txt "
                   "(tum-rgbd), times.txt + images/ or images.zip (tum-mono), image files "
                   "(folder)");
}

}  // namespace ldsm::drivers
