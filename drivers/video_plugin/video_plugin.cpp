// The video plugin: video files decoded with OpenCV videoio to 8-bit grey, behind the C
// interface of video_plugin_api.h. Loaded by ldsm_drivers with dlopen() when a video is opened.
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/core/version.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "dataset/video_plugin_api.h"

struct LdsmVideo {
  cv::VideoCapture capture;
  cv::Mat decoded;
  cv::Mat grey;
  cv::Mat scratch;
};

namespace {

void setError(char* error, std::size_t size, const std::string& message) {
  if (error != nullptr && size > 0) std::snprintf(error, size, "%s", message.c_str());
}

/// Converts a decoded frame (8/16-bit, 1/3/4 channels) to 8-bit grey; false when unsupported.
bool toGrey(LdsmVideo& v) {
  const int depth = v.decoded.depth();
  const int channels = v.decoded.channels();
  if ((depth != CV_8U && depth != CV_16U) || (channels != 1 && channels != 3 && channels != 4))
    return false;
  const cv::Mat* grey = &v.decoded;
  if (channels != 1) {
    cv::cvtColor(v.decoded, v.scratch, channels == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
    grey = &v.scratch;
  }
  if (depth == CV_16U) {
    // The high byte, floor(v / 256), as the image decoders do: round(v / 256 - 0.498).
    grey->convertTo(v.grey, CV_8U, 1.0 / 256.0, -127.5 / 256.0);
  } else {
    grey->copyTo(v.grey);
  }
  return true;
}

LdsmVideo* openVideo(const char* path, char* error, std::size_t error_size) {
  try {
    auto video = std::make_unique<LdsmVideo>();
    // The backends that read files, FFmpeg first (it fails quietly on a bad file). Not CAP_ANY:
    // for a file nothing else opens, that also probes the camera backends, and gphoto2's probe
    // scans the USB bus for cameras (and leaks what it found, by LeakSanitizer).
    for (const int api : {cv::CAP_FFMPEG, cv::CAP_GSTREAMER, cv::CAP_OPENCV_MJPEG})
      if (video->capture.open(path, api)) return video.release();
    setError(error, error_size, "unsupported or corrupt file");
  } catch (const std::exception& e) {
    setError(error, error_size, e.what());
  } catch (...) {
    setError(error, error_size, "unknown error");
  }
  return nullptr;
}

void closeVideo(LdsmVideo* video) {
  try {
    delete video;
  } catch (...) {
  }
}

double property(const LdsmVideo* video, int id) {
  try {
    const double v = video->capture.get(id);
    return std::isfinite(v) ? v : 0.0;
  } catch (...) {
    return 0.0;
  }
}

double fps(const LdsmVideo* video) {
  return property(video, cv::CAP_PROP_FPS);
}

double frameCount(const LdsmVideo* video) {
  return property(video, cv::CAP_PROP_FRAME_COUNT);
}

int nextFrame(LdsmVideo* video, LdsmVideoFrame* frame, char* error, std::size_t error_size) {
  try {
    if (!video->capture.read(video->decoded) || video->decoded.empty()) return 0;
    if (!toGrey(*video)) {
      setError(error, error_size,
               "unsupported pixel type (" + std::to_string(video->decoded.channels()) +
                   " channels of depth code " + std::to_string(video->decoded.depth()) + ")");
      return -1;
    }
    frame->data = video->grey.data;
    frame->width = video->grey.cols;
    frame->height = video->grey.rows;
    frame->stride = static_cast<std::ptrdiff_t>(video->grey.step[0]);
    frame->position_ms = video->capture.get(cv::CAP_PROP_POS_MSEC);
    return 1;
  } catch (const std::exception& e) {
    setError(error, error_size, e.what());
  } catch (...) {
    setError(error, error_size, "unknown error");
  }
  return -1;
}

const LdsmVideoPlugin kPlugin = {LDSM_VIDEO_PLUGIN_ABI_VERSION,
                                 "OpenCV " CV_VERSION " videoio",
                                 openVideo,
                                 closeVideo,
                                 fps,
                                 frameCount,
                                 nextFrame};

}  // namespace

extern "C" __attribute__((visibility("default"))) const LdsmVideoPlugin* ldsm_video_plugin_v1() {
  return &kPlugin;
}
