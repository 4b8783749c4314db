// The frame source of video files, and the description of a video file. Decoding is done by the
// video plugin (OpenCV videoio), loaded when the first video is opened.
#pragma once

#include <cstdint>
#include <string>

#include "dataset/video_plugin_api.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/frame_source.h"

namespace ldsm::drivers::detail {

/// Fills the video fields of `description` (root = the video file): size of the first frame,
/// container frame count and rate. Throws ldsm::InputError naming the file when it cannot be
/// opened, has no decodable frame or the video plugin is missing.
void describeVideo(DatasetDescription& description);

/// Decodes the frames of a video file as 8-bit grey. Timestamps are the decoder's position
/// when it increases, else frame index / frame rate.
class VideoSource : public FrameSource {
 public:
  /// Throws ldsm::InputError naming the file when it cannot be opened.
  explicit VideoSource(const DatasetDescription& description);
  ~VideoSource() override;
  VideoSource(const VideoSource&) = delete;
  VideoSource& operator=(const VideoSource&) = delete;

  SourceInfo info() const override { return info_; }
  bool next(Frame& frame) override;

 private:
  std::string path_;
  const LdsmVideoPlugin* plugin_ = nullptr;
  LdsmVideo* video_ = nullptr;
  SourceInfo info_;
  std::int64_t next_index_ = 0;
  double last_timestamp_ = 0.0;
  bool ended_ = false;
};

}  // namespace ldsm::drivers::detail
