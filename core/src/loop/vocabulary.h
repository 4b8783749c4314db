// A vocabulary tree of binary descriptors (Nister & Stewenius 2006; Galvez-Lopez & Tardos,
// "Bags of Binary Words", T-RO 2012): hierarchical k-majority clustering with branching k and
// depth L, the leaves are the visual words, each weighted by its inverse document frequency
// idf(w) = ln(N / n_w) over the N training images (n_w of which contain w).
//
// transform() quantises a keyframe's descriptors by descending from the root to the nearest child
// at each level, and returns
//  * the BowVector: per word, tf * idf (tf = occurrences / descriptors), L1-normalised; words of
//    weight 0 (seen in every training image) are left out;
//  * the FeatureVector (direct index): per node at a chosen depth, the features below it.
// bowScore() is DBoW's L1 score 1 - 0.5 |a - b|_1 (1 for identical vectors, 0 for disjoint).
//
// Binary format (little-endian), see serialize():
//   "LDSMVOCB" | u32 version=1 | u32 k | u32 L | u32 nodes N | u32 words W | u32 training images
//   | u8 child count x N (breadth-first order, node 0 = root) | 32-byte descriptor x (N - 1)
//   | f32 word weight x W (words = leaves in breadth-first order) | u64 checksum
// The checksum is FNV-1a over the preceding bytes taken as 64-bit little-endian words (the tail
// zero-padded). Loading a 1M-word vocabulary takes tens of milliseconds (bench_loop_features).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "loop/loop_types.h"

namespace ldsm::loop {

/// Training settings of a Vocabulary.
struct VocabularyParams {
  int branching = 10;       ///< k, children per node: 2..Vocabulary::kMaxBranching
  int levels = 5;           ///< L, depth of the tree: 1..Vocabulary::kMaxLevels
  int max_iterations = 10;  ///< k-majority update rounds per node, 0..100
  std::uint64_t seed = 1;   ///< training is a deterministic function of data and seed
};

class Vocabulary {
 public:
  static constexpr int kMaxBranching = 64;
  static constexpr int kMaxLevels = 10;
  static constexpr std::uint32_t kFormatVersion = 1;
  static constexpr WordId kNoWord = 0xFFFFFFFFu;

  /// An empty vocabulary: no words; transform() gives empty vectors.
  Vocabulary() = default;

  /// Trains on the descriptors of a set of images (one vector per image; empty ones are skipped
  /// and do not count as documents). Returns std::nullopt when `abort` becomes true. Throws
  /// ConfigError for out-of-range params and InputError when there is no descriptor at all.
  static std::optional<Vocabulary> train(const std::vector<std::vector<OrbDescriptor>>& images,
                                         const VocabularyParams& params,
                                         const std::atomic<bool>* abort = nullptr);

  bool empty() const { return word_weight_.empty(); }
  int branching() const { return branching_; }
  int levels() const { return levels_; }
  std::size_t wordCount() const { return word_weight_.size(); }
  std::size_t nodeCount() const { return child_count_.size(); }
  /// Number of images (documents) the idf weights were computed on.
  std::uint32_t trainingImages() const { return training_images_; }
  /// idf weight of a word (0 for an out-of-range id).
  float wordWeight(WordId word) const {
    return word < word_weight_.size() ? word_weight_[word] : 0.f;
  }

  /// Word of a descriptor (kNoWord when empty). When `node_at_depth` is given it receives the node
  /// at `depth` on the descriptor's path (the leaf when the path is shorter; the root for 0).
  WordId wordOf(const OrbDescriptor& d, int depth = 0,
                std::uint32_t* node_at_depth = nullptr) const;

  /// BoW vector of a set of descriptors (cleared first).
  void transform(const std::vector<OrbDescriptor>& descriptors, BowVector& bow) const;
  /// BoW vector and FeatureVector with nodes at `direct_index_depth` (0..levels(); clamped).
  void transform(const std::vector<OrbDescriptor>& descriptors, BowVector& bow,
                 FeatureVector& features, int direct_index_depth) const;

  /// The binary format above. Throws Error for an empty vocabulary (or a lone root).
  std::vector<std::uint8_t> serialize() const;
  /// Parses serialize()'s output. Throws InputError "<where>: ..." naming what is wrong
  /// (not a vocabulary, unsupported version, truncated, inconsistent tree, checksum mismatch).
  static Vocabulary deserialize(const std::uint8_t* data, std::size_t size,
                                const std::string& where);

  /// Identical trees and weights.
  bool operator==(const Vocabulary& o) const;
  bool operator!=(const Vocabulary& o) const { return !(*this == o); }

 private:
  void quantize(const std::vector<OrbDescriptor>& descriptors, int depth,
                std::vector<WordId>& words, std::vector<std::uint32_t>* nodes) const;
  void buildWordIndex();

  int branching_ = 0;
  int levels_ = 0;
  std::uint32_t training_images_ = 0;
  // Nodes in breadth-first order; node 0 is the root (its descriptor is unused); the children of
  // node i are first_child_[i] .. first_child_[i] + child_count_[i] - 1.
  std::vector<OrbDescriptor> node_descriptor_;
  std::vector<std::uint32_t> first_child_;
  std::vector<std::uint8_t> child_count_;
  std::vector<WordId> node_word_;  ///< word of a leaf, kNoWord for inner nodes
  std::vector<float> word_weight_;
};

/// DBoW's L1 score of two L1-normalised BoW vectors (sorted by word): 1 - 0.5 |a - b|_1, which
/// for positive weights is the sum over shared words of min(a_w, b_w). In [0, 1].
float bowScore(const BowVector& a, const BowVector& b);

}  // namespace ldsm::loop
