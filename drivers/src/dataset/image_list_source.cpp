// Image-list frame source: files or zip entries decoded to 8-bit grey.
#include "dataset/image_list_source.h"

#include <cmath>
#include <limits>
#include <utility>

#include "ldsm/calib/image_file.h"
#include "ldsm/error.h"

namespace ldsm::drivers::detail {

DatasetSource::DatasetSource(DatasetDescription description)
    : description_(std::move(description)),
      width_(description_.width),
      height_(description_.height) {
  const std::size_t n = description_.images.size();
  if (description_.timestamps.size() != n ||
      (!description_.exposures_ms.empty() && description_.exposures_ms.size() != n)) {
    throw InputError(description_.root +
                     ": inconsistent dataset description: " + std::to_string(n) + " images, " +
                     std::to_string(description_.timestamps.size()) + " timestamps, " +
                     std::to_string(description_.exposures_ms.size()) + " exposures");
  }
  if (!description_.image_archive.empty()) {
    archive_ = std::make_unique<ZipArchive>(description_.image_archive);
    entry_indices_.reserve(n);
    for (const auto& name : description_.images) entry_indices_.push_back(archive_->indexOf(name));
  }
}

SourceInfo DatasetSource::info() const {
  SourceInfo info;
  info.name = toString(description_.format);
  info.width = width_;
  info.height = height_;
  info.frame_count = static_cast<std::int64_t>(description_.images.size());
  info.nominal_fps = description_.nominal_fps;
  return info;
}

std::string DatasetSource::imageName(std::size_t i) const {
  if (archive_) return archive_->path() + ":" + description_.images[i];
  return description_.images[i];
}

void DatasetSource::decode(std::size_t i, ImageU8& out) {
  const std::string where = imageName(i);
  if (archive_) {
    archive_->read(entry_indices_[i], bytes_);
  } else {
    calib::readFileBytes(description_.images[i], bytes_);
  }
  calib::decodeImage(bytes_.data(), bytes_.size(), where, out);
  if (width_ == 0 && height_ == 0) {
    width_ = out.width();
    height_ = out.height();
  } else if (out.width() != width_ || out.height() != height_) {
    throw InputError(where + ": image is " + std::to_string(out.width()) + "x" +
                     std::to_string(out.height()) + " but the first image is " +
                     std::to_string(width_) + "x" + std::to_string(height_));
  }
}

bool DatasetSource::next(Frame& frame) {
  if (failed_ || next_ >= description_.images.size()) return false;
  const std::size_t i = next_;
  try {
    decode(i, frame.image);
  } catch (...) {
    failed_ = true;
    throw;
  }
  ++next_;
  frame.index = static_cast<std::int64_t>(i);
  frame.timestamp = description_.timestamps[i];
  frame.exposure_ms = description_.exposures_ms.empty() ? std::numeric_limits<double>::quiet_NaN()
                                                        : description_.exposures_ms[i];
  return true;
}

}  // namespace ldsm::drivers::detail
