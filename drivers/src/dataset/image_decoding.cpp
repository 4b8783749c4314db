// Image decoding to 8-bit grey with OpenCV imgcodecs.
#include "dataset/image_decoding.h"

#include <cstring>
#include <fstream>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ldsm/error.h"

namespace ldsm::drivers::detail {
namespace {

void copyToImage(const cv::Mat& grey8, ImageU8& out) {
  out.resize(grey8.cols, grey8.rows);
  for (int y = 0; y < grey8.rows; ++y) {
    std::memcpy(out.row(y), grey8.ptr<unsigned char>(y), static_cast<std::size_t>(grey8.cols));
  }
}

}  // namespace

void readFileBytes(const std::string& path, std::vector<unsigned char>& bytes) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path + ": cannot open");
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(path + ": read error");
  bytes.resize(static_cast<std::size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size)) {
    throw InputError(path + ": read error");
  }
}

void matToGrey(const cv::Mat& image, const std::string& where, cv::Mat& scratch, ImageU8& out) {
  const int depth = image.depth();
  const int channels = image.channels();
  if ((depth != CV_8U && depth != CV_16U) || (channels != 1 && channels != 3 && channels != 4)) {
    throw InputError(where + ": unsupported pixel type (" + std::to_string(channels) +
                     " channels of depth code " + std::to_string(depth) +
                     "); expected 8- or 16-bit grey or colour");
  }
  const cv::Mat* grey = &image;
  if (channels != 1) {
    cv::cvtColor(image, scratch, channels == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
    grey = &scratch;
  }
  if (depth == CV_16U) {
    grey->convertTo(scratch, CV_8U, 1.0 / 256.0);
    grey = &scratch;
  }
  copyToImage(*grey, out);
}

void decodeToGrey(const std::vector<unsigned char>& bytes, const std::string& where,
                  cv::Mat& scratch, ImageU8& out) {
  if (bytes.empty()) throw InputError(where + ": cannot decode image: the file is empty");
  bool decoded = false;
  try {
    const cv::Mat buffer(1, static_cast<int>(bytes.size()), CV_8U,
                         const_cast<unsigned char*>(bytes.data()));
    // imdecode leaves its output untouched when it finds no decoder, so a failure would look
    // like the previous image: start from an empty matrix (the allocator recycles the block).
    scratch.release();
    decoded = !cv::imdecode(buffer, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH, &scratch).empty();
  } catch (const cv::Exception& e) {
    throw InputError(where + ": cannot decode image: " + e.what());
  }
  if (!decoded) {
    throw InputError(where + ": cannot decode image (not a supported image format or corrupt)");
  }
  if (scratch.depth() == CV_16U) scratch.convertTo(scratch, CV_8U, 1.0 / 256.0);
  if (scratch.depth() != CV_8U || scratch.channels() != 1) {
    throw InputError(where + ": unsupported pixel type after decoding; expected 8- or 16-bit");
  }
  copyToImage(scratch, out);
}

}  // namespace ldsm::drivers::detail
