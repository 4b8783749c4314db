// Video file frame source with OpenCV videoio.
#include "dataset/video_source.h"

#include <cmath>
#include <filesystem>
#include <limits>

#include "dataset/image_decoding.h"
#include "ldsm/error.h"

namespace ldsm::drivers::detail {
namespace {

/// Rate used for timestamps when the container reports none.
constexpr double kFallbackFps = 30.0;

void openCapture(cv::VideoCapture& capture, const std::string& path) {
  bool opened = false;
  try {
    // FFmpeg first: it fails quietly on a bad file, where probing every backend logs noise.
    opened = capture.open(path, cv::CAP_FFMPEG) || capture.open(path, cv::CAP_ANY);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot open video: " + e.what());
  }
  if (!opened) throw InputError(path + ": cannot open video (unsupported or corrupt file)");
}

}  // namespace

void describeVideo(DatasetDescription& description) {
  const std::string& path = description.root;
  cv::VideoCapture capture;
  openCapture(capture, path);
  cv::Mat first;
  if (!capture.read(first) || first.empty()) throw InputError(path + ": video has no frames");
  description.width = first.cols;
  description.height = first.rows;
  const double fps = capture.get(cv::CAP_PROP_FPS);
  description.nominal_fps = std::isfinite(fps) && fps > 0.0 ? fps : 0.0;
  const double count = capture.get(cv::CAP_PROP_FRAME_COUNT);
  description.frame_count = std::isfinite(count) && count > 0.0 ? std::llround(count) : -1;
  description.timestamps_assumed = description.nominal_fps == 0.0;
  const auto dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (std::filesystem::is_regular_file(dir / "camera.txt", ec)) {
    description.calibration_file = (dir / "camera.txt").string();
    description.calibration_kind = CalibrationFileKind::DsoCamera;
  }
}

VideoSource::VideoSource(const DatasetDescription& description) : path_(description.root) {
  openCapture(capture_, path_);
  info_.name = "video";
  info_.width = description.width;
  info_.height = description.height;
  info_.frame_count = description.frame_count;
  info_.nominal_fps = description.nominal_fps;
}

bool VideoSource::next(Frame& frame) {
  if (ended_) return false;
  try {
    if (!capture_.read(decoded_) || decoded_.empty()) {
      ended_ = true;
      return false;
    }
    const std::string where = path_ + ": frame " + std::to_string(next_index_);
    matToGrey(decoded_, where, scratch_, frame.image);
    if (info_.width == 0 && info_.height == 0) {
      info_.width = frame.image.width();
      info_.height = frame.image.height();
    } else if (frame.image.width() != info_.width || frame.image.height() != info_.height) {
      throw InputError(where + ": frame is " + std::to_string(frame.image.width()) + "x" +
                       std::to_string(frame.image.height()) + " but the first frame is " +
                       std::to_string(info_.width) + "x" + std::to_string(info_.height));
    }
  } catch (const cv::Exception& e) {
    ended_ = true;
    throw InputError(path_ + ": frame " + std::to_string(next_index_) +
                     ": cannot decode: " + e.what());
  } catch (...) {
    ended_ = true;
    throw;
  }
  const double fps = info_.nominal_fps > 0.0 ? info_.nominal_fps : kFallbackFps;
  const double from_rate = static_cast<double>(next_index_) / fps;
  const double position = capture_.get(cv::CAP_PROP_POS_MSEC) * 1e-3;
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
