// Decoding of encoded images (PNG, JPEG, ...) and of OpenCV matrices to 8-bit grey ldsm images,
// reusing buffers across calls.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "ldsm/image.h"

namespace ldsm::drivers::detail {

/// Reads the whole file `path` into `bytes` (capacity reused). Throws ldsm::InputError
/// "<path>: cannot open" / "<path>: read error".
void readFileBytes(const std::string& path, std::vector<unsigned char>& bytes);

/// Decodes `bytes` to grey into `out`, resizing it only when needed. 16-bit images are scaled by
/// 1/256, colour is converted to grey. `scratch` is reused between calls. Throws
/// ldsm::InputError "<where>: cannot decode image ..." on failure.
void decodeToGrey(const std::vector<unsigned char>& bytes, const std::string& where,
                  cv::Mat& scratch, ImageU8& out);

/// Converts a decoded matrix (8/16-bit, 1/3/4 channels) to 8-bit grey in `out`. `scratch` must
/// not alias `image`. Throws ldsm::InputError naming `where` for an unsupported pixel type.
void matToGrey(const cv::Mat& image, const std::string& where, cv::Mat& scratch, ImageU8& out);

}  // namespace ldsm::drivers::detail
