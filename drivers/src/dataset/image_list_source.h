// The frame source of the image-list dataset layouts (TUM-Mono, EuRoC, KITTI, TUM RGB-D, folder):
// decodes one image per next() call from files or a zip archive.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dataset/zip_archive.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/frame_source.h"

namespace ldsm::drivers::detail {

class DatasetSource : public FrameSource {
 public:
  /// Throws ldsm::InputError when the description is inconsistent (list sizes differ) or its
  /// archive cannot be opened.
  explicit DatasetSource(DatasetDescription description);

  SourceInfo info() const override;
  bool next(Frame& frame) override;

 private:
  std::string imageName(std::size_t i) const;
  void decode(std::size_t i, ImageU8& out);

  DatasetDescription description_;
  std::unique_ptr<ZipArchive> archive_;
  std::vector<std::uint64_t> entry_indices_;  ///< archive index of each image (zip only)
  std::size_t next_ = 0;
  bool failed_ = false;
  int width_ = 0;  ///< expected size (first image's)
  int height_ = 0;
  std::vector<unsigned char> bytes_;  ///< encoded image (capacity reused)
};

}  // namespace ldsm::drivers::detail
