// Offline vocabularies for loop detection: training one from a set of images (the features the
// odometry would pick on keyframes: Shi-Tomasi corners with ORB descriptors) and checking a
// serialised one. Core does no file I/O: vocabularies travel as bytes (read and written by
// ldsm/drivers/vocabulary_file.h). The format is described in docs/loop-closure.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ldsm/image.h"

namespace ldsm::loop {

/// Settings of VocabularyBuilder.
struct VocabularyTrainingOptions {
  int branching = 10;            ///< k: children per node, 2..64
  int levels = 5;                ///< L: depth, 1..10 (at most k^L words)
  int max_iterations = 10;       ///< k-majority rounds per node, 0..100
  std::uint64_t seed = 1;        ///< training is deterministic for a given seed and image order
  int features_per_image = 500;  ///< corners per image, over 5 pyramid levels
};

/// What a serialised vocabulary holds.
struct VocabularySummary {
  int branching = 0;
  int levels = 0;
  std::size_t nodes = 0;
  std::size_t words = 0;
  std::uint32_t training_images = 0;
};

/// Parses and checks a serialised vocabulary (signature, version, sizes, tree, checksum). Throws
/// ldsm::InputError "<where>: <what is wrong>".
VocabularySummary inspectVocabulary(const std::uint8_t* data, std::size_t size,
                                    const std::string& where);

/// Collects features from images, then trains a vocabulary on them.
class VocabularyBuilder {
 public:
  /// Throws ConfigError for out-of-range options.
  explicit VocabularyBuilder(const VocabularyTrainingOptions& options = {});
  ~VocabularyBuilder();
  VocabularyBuilder(const VocabularyBuilder&) = delete;
  VocabularyBuilder& operator=(const VocabularyBuilder&) = delete;

  /// Detects up to features_per_image Shi-Tomasi corners on 5 pyramid levels (scale 1.2) of an
  /// 8-bit grey image (any size of at least 40x40, else InputError) and keeps their ORB
  /// descriptors. Returns the number kept.
  int addImage(ImageView<const std::uint8_t> image);

  std::size_t imageCount() const;
  std::size_t descriptorCount() const;

  /// Trains on everything added and returns the serialised vocabulary. Throws InputError when no
  /// descriptor was collected.
  std::vector<std::uint8_t> train() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldsm::loop
