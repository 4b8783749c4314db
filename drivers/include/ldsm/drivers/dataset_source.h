// Frame sources over recorded sequences: image lists (files or a zip archive) and video files.
#pragma once

#include <memory>
#include <string>

#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/frame_source.h"

namespace ldsm::drivers {

/// Opens a frame source over a described dataset: image-list formats decode each image as 8-bit
/// grey (16-bit images are scaled by 1/256, colour is converted), reusing the frame's buffer;
/// Video decodes with OpenCV. next() throws ldsm::InputError naming the image when it cannot be
/// decoded or its size differs from the first image's.
std::unique_ptr<FrameSource> openDataset(const DatasetDescription& description);

/// describeDataset(path, format) followed by openDataset(description).
std::unique_ptr<FrameSource> openDataset(const std::string& path,
                                         DatasetFormat format = DatasetFormat::Auto);

}  // namespace ldsm::drivers
