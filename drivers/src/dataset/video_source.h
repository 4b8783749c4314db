// The frame source of video files (OpenCV videoio), and the description of a video file.
#pragma once

#include <opencv2/core/mat.hpp>
#include <opencv2/videoio.hpp>

#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/frame_source.h"

namespace ldsm::drivers::detail {

/// Fills the video fields of `description` (root = the video file): size of the first frame,
/// container frame count and rate. Throws ldsm::InputError naming the file when it cannot be
/// opened or has no decodable frame.
void describeVideo(DatasetDescription& description);

/// Decodes the frames of a video file as 8-bit grey. Timestamps are the decoder's position
/// (CAP_PROP_POS_MSEC) when it increases, else frame index / frame rate.
class VideoSource : public FrameSource {
 public:
  /// Throws ldsm::InputError naming the file when it cannot be opened.
  explicit VideoSource(const DatasetDescription& description);

  SourceInfo info() const override { return info_; }
  bool next(Frame& frame) override;

 private:
  std::string path_;
  cv::VideoCapture capture_;
  SourceInfo info_;
  std::int64_t next_index_ = 0;
  double last_timestamp_ = 0.0;
  bool ended_ = false;
  cv::Mat decoded_;
  cv::Mat scratch_;
};

}  // namespace ldsm::drivers::detail
