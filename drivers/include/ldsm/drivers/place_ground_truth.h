// Ground truth of place-recognition datasets: an n x n image whose pixel (column j, row i) is
// white when images i and j show the same place (RTAB-Map's samples_GT.bmp convention). Read from
// an uncompressed 8-bit (palette) or 24-bit BMP file, or any grey image ldsm decodes (PNG, PGM).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/image.h"

namespace ldsm::drivers {

/// Reads a ground-truth matrix: result[i][j] = 1 when pixel (x = j, y = i, top row first) is
/// brighter than mid-grey. Throws ldsm::InputError "<path>: ..." when the file is missing, not a
/// supported image, compressed, or not square.
std::vector<std::vector<std::uint8_t>> readPlaceGroundTruth(const std::string& path);

/// An image collection with its place ground truth.
struct PlaceDataset {
  std::vector<ImageU8> images;                        ///< grey, in natural file-name order
  std::vector<std::vector<std::uint8_t>> same_place;  ///< images.size() squared
};

/// Reads the images of the dataset folder `dir` (as openDataset() finds them, e.g. in a
/// "samples" subfolder) and the ground truth `dir`/`ground_truth_file`. Throws ldsm::InputError
/// when either is unreadable or their sizes disagree.
PlaceDataset readPlaceDataset(const std::string& dir,
                              const std::string& ground_truth_file = "samples_GT.bmp");

}  // namespace ldsm::drivers
