// openDataset(): the frame source matching a dataset description.
#include <memory>

#include "dataset/image_list_source.h"
#include "dataset/video_source.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers {

std::unique_ptr<FrameSource> openDataset(const DatasetDescription& description) {
  switch (description.format) {
    case DatasetFormat::Auto:
      throw InputError(description.root +
                       ": dataset description has no format (use describeDataset())");
    case DatasetFormat::Video:
      return std::make_unique<detail::VideoSource>(description);
    case DatasetFormat::TumMono:
    case DatasetFormat::Euroc:
    case DatasetFormat::Kitti:
    case DatasetFormat::TumRgbd:
    case DatasetFormat::Folder:
      break;
  }
  return std::make_unique<detail::DatasetSource>(description);
}

std::unique_ptr<FrameSource> openDataset(const std::string& path, DatasetFormat format) {
  return openDataset(describeDataset(path, format));
}

}  // namespace ldsm::drivers
