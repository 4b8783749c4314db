// Video file frame source over the video plugin.
#include "dataset/video_source.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "dataset/video_plugin_loader.h"
#include "ldsm/error.h"

namespace ldsm::drivers::detail {
namespace {

/// Rate used for timestamps when the container reports none.
constexpr double kFallbackFps = 30.0;
constexpr std::size_t kErrorSize = 512;

LdsmVideo* openVideo(const LdsmVideoPlugin& plugin, const std::string& path) {
  char error[kErrorSize] = {};
  LdsmVideo* video = plugin.open(path.c_str(), error, sizeof error);
  if (video == nullptr) throw InputError(path + ": cannot open video (" + error + ")");
  return video;
}

/// Copies a plugin frame into `out` (resized only when needed).
void copyFrame(const LdsmVideoFrame& frame, ImageU8& out) {
  out.resize(frame.width, frame.height);
  for (int y = 0; y < frame.height; ++y)
    std::memcpy(out.row(y), frame.data + frame.stride * y, static_cast<std::size_t>(frame.width));
}

}  // namespace

void describeVideo(DatasetDescription& description) {
  const std::string& path = description.root;
  const LdsmVideoPlugin& plugin = loadVideoPlugin(path);
  const std::unique_ptr<LdsmVideo, void (*)(LdsmVideo*)> video(openVideo(plugin, path),
                                                               plugin.close);
  char error[kErrorSize] = {};
  LdsmVideoFrame first{};
  const int got = plugin.next(video.get(), &first, error, sizeof error);
  if (got < 0) throw InputError(path + ": frame 0: cannot decode (" + error + ")");
  if (got == 0) throw InputError(path + ": video has no frames");
  description.width = first.width;
  description.height = first.height;
  const double fps = plugin.fps(video.get());
  description.nominal_fps = std::isfinite(fps) && fps > 0.0 ? fps : 0.0;
  const double count = plugin.frame_count(video.get());
  description.frame_count = std::isfinite(count) && count > 0.0 ? std::llround(count) : -1;
  description.timestamps_assumed = description.nominal_fps == 0.0;
  const auto dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (std::filesystem::is_regular_file(dir / "camera.txt", ec)) {
    description.calibration_file = (dir / "camera.txt").string();
    description.calibration_kind = CalibrationFileKind::DsoCamera;
  }
}

VideoSource::VideoSource(const DatasetDescription& description)
    : path_(description.root), plugin_(&loadVideoPlugin(description.root)) {
  video_ = openVideo(*plugin_, path_);
  info_.name = "video";
  info_.width = description.width;
  info_.height = description.height;
  info_.frame_count = description.frame_count;
  info_.nominal_fps = description.nominal_fps;
}

VideoSource::~VideoSource() {
  plugin_->close(video_);
}

bool VideoSource::next(Frame& frame) {
  if (ended_) return false;
  const std::string where = path_ + ": frame " + std::to_string(next_index_);
  char error[kErrorSize] = {};
  LdsmVideoFrame decoded{};
  const int got = plugin_->next(video_, &decoded, error, sizeof error);
  if (got <= 0) {
    ended_ = true;
    if (got < 0) throw InputError(where + ": cannot decode (" + error + ")");
    return false;
  }
  if (info_.width == 0 && info_.height == 0) {
    info_.width = decoded.width;
    info_.height = decoded.height;
  } else if (decoded.width != info_.width || decoded.height != info_.height) {
    ended_ = true;
    throw InputError(where + ": frame is " + std::to_string(decoded.width) + "x" +
                     std::to_string(decoded.height) + " but the first frame is " +
                     std::to_string(info_.width) + "x" + std::to_string(info_.height));
  }
  copyFrame(decoded, frame.image);
  const double fps = info_.nominal_fps > 0.0 ? info_.nominal_fps : kFallbackFps;
  const double from_rate = static_cast<double>(next_index_) / fps;
  const double position = decoded.position_ms * 1e-3;
  double t = from_rate;
  if (std::isfinite(position) && position >= 0.0 &&
      (next_index_ == 0 || position > last_timestamp_)) {
    t = position;
  }
  if (next_index_ > 0 && !(t > last_timestamp_)) t = last_timestamp_ + 1.0 / fps;
  frame.index = next_index_++;
  frame.timestamp = t;
  frame.exposure_ms = std::numeric_limits<double>::quiet_NaN();
  last_timestamp_ = t;
  return true;
}

}  // namespace ldsm::drivers::detail
