#include "loop/vocabulary.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>
#include <utility>

#include "ldsm/error.h"
#include "loop/binary_kmajority.h"
#include "model/popcount_dispatch.h"

namespace ldsm::loop {
namespace {

void checkParams(const VocabularyParams& p) {
  if (p.branching < 2 || p.branching > Vocabulary::kMaxBranching) {
    throw ConfigError("vocabulary: branching must be in [2, " +
                      std::to_string(Vocabulary::kMaxBranching) + "] (got " +
                      std::to_string(p.branching) + ")");
  }
  if (p.levels < 1 || p.levels > Vocabulary::kMaxLevels) {
    throw ConfigError("vocabulary: levels must be in [1, " +
                      std::to_string(Vocabulary::kMaxLevels) + "] (got " +
                      std::to_string(p.levels) + ")");
  }
  if (p.max_iterations < 0 || p.max_iterations > 100) {
    throw ConfigError("vocabulary: max_iterations must be in [0, 100] (got " +
                      std::to_string(p.max_iterations) + ")");
  }
}

/// Descends the tree for n descriptors: the leaf's word and, optionally, the node at `depth`.
LDSM_POPCNT_CLONES
void descend(const OrbDescriptor* descriptors, std::size_t n, const OrbDescriptor* node_descriptor,
             const std::uint32_t* first_child, const std::uint8_t* child_count,
             const WordId* node_word, int depth, WordId* words, std::uint32_t* nodes) {
  for (std::size_t i = 0; i < n; ++i) {
    const OrbDescriptor& d = descriptors[i];
    std::uint32_t node = 0;
    std::uint32_t at_depth = 0;
    int level = 0;
    while (child_count[node] != 0) {
      const std::uint32_t first = first_child[node];
      const int count = child_count[node];
      int best = 0;
      int best_distance = 257;
      for (int c = 0; c < count; ++c) {
        const int dist = hammingDistance(d, node_descriptor[first + static_cast<std::uint32_t>(c)]);
        if (dist < best_distance) {
          best_distance = dist;
          best = c;
        }
      }
      node = first + static_cast<std::uint32_t>(best);
      if (++level <= depth) at_depth = node;
    }
    words[i] = node_word[node];
    if (nodes != nullptr) nodes[i] = at_depth;
  }
}

}  // namespace

std::optional<Vocabulary> Vocabulary::train(const std::vector<std::vector<OrbDescriptor>>& images,
                                            const VocabularyParams& params,
                                            const std::atomic<bool>* abort) {
  checkParams(params);
  std::vector<OrbDescriptor> all;
  std::size_t total = 0;
  std::uint32_t documents = 0;
  for (const auto& image : images) {
    total += image.size();
    if (!image.empty()) ++documents;
  }
  if (total == 0) throw InputError("vocabulary: no descriptors to train on");
  if (total > 0xFFFFFFF0u) throw InputError("vocabulary: too many training descriptors");
  all.reserve(total);
  for (const auto& image : images) all.insert(all.end(), image.begin(), image.end());

  Vocabulary v;
  v.branching_ = params.branching;
  v.levels_ = params.levels;
  v.training_images_ = documents;
  auto addNode = [&v](const OrbDescriptor& d) {
    v.node_descriptor_.push_back(d);
    v.first_child_.push_back(0);
    v.child_count_.push_back(0);
  };
  addNode(OrbDescriptor{});

  struct Pending {
    std::uint32_t node;
    int depth;
    std::vector<std::uint32_t> members;
  };
  std::deque<Pending> queue;
  {
    Pending root{0, 0, std::vector<std::uint32_t>(total)};
    for (std::size_t i = 0; i < total; ++i) root.members[i] = static_cast<std::uint32_t>(i);
    queue.push_back(std::move(root));
  }
  SplitMix64 rng(params.seed);
  KMajorityResult clusters;
  // Breadth-first: nodes are appended in the order they are dequeued, so the children of a node
  // are contiguous and the node array is in breadth-first order.
  while (!queue.empty()) {
    Pending p = std::move(queue.front());
    queue.pop_front();
    if (p.depth >= params.levels || p.members.size() <= 1) continue;
    if (!kMajority(all.data(), p.members.data(), p.members.size(), params.branching,
                   params.max_iterations, rng, clusters, abort)) {
      return std::nullopt;
    }
    if (clusters.centers.size() <= 1) continue;
    const auto first = static_cast<std::uint32_t>(v.node_descriptor_.size());
    v.first_child_[p.node] = first;
    v.child_count_[p.node] = static_cast<std::uint8_t>(clusters.centers.size());
    std::vector<std::vector<std::uint32_t>> split(clusters.centers.size());
    for (std::size_t i = 0; i < p.members.size(); ++i) {
      split[clusters.assignment[i]].push_back(p.members[i]);
    }
    for (std::size_t c = 0; c < clusters.centers.size(); ++c) {
      addNode(clusters.centers[c]);
      queue.push_back(
          Pending{first + static_cast<std::uint32_t>(c), p.depth + 1, std::move(split[c])});
    }
  }
  v.buildWordIndex();

  // idf weights from the training images.
  std::vector<std::uint32_t> documents_with_word(v.wordCount(), 0u);
  std::vector<std::uint32_t> last_document(v.wordCount(), 0xFFFFFFFFu);
  std::vector<WordId> words;
  std::uint32_t doc = 0;
  for (const auto& image : images) {
    if (image.empty()) continue;
    v.quantize(image, 0, words, nullptr);
    for (WordId w : words) {
      if (last_document[w] != doc) {
        last_document[w] = doc;
        ++documents_with_word[w];
      }
    }
    ++doc;
  }
  for (std::size_t w = 0; w < v.wordCount(); ++w) {
    const double n_w = std::max<std::uint32_t>(documents_with_word[w], 1u);
    v.word_weight_[w] = static_cast<float>(std::log(static_cast<double>(documents) / n_w));
  }
  return v;
}

void Vocabulary::buildWordIndex() {
  node_word_.assign(child_count_.size(), kNoWord);
  WordId next = 0;
  for (std::size_t i = 0; i < child_count_.size(); ++i) {
    if (child_count_[i] == 0) node_word_[i] = next++;
  }
  word_weight_.assign(next, 0.f);
}

void Vocabulary::quantize(const std::vector<OrbDescriptor>& descriptors, int depth,
                          std::vector<WordId>& words, std::vector<std::uint32_t>* nodes) const {
  words.resize(descriptors.size());
  if (nodes != nullptr) nodes->resize(descriptors.size());
  if (descriptors.empty()) return;
  descend(descriptors.data(), descriptors.size(), node_descriptor_.data(), first_child_.data(),
          child_count_.data(), node_word_.data(), depth, words.data(),
          nodes != nullptr ? nodes->data() : nullptr);
}

WordId Vocabulary::wordOf(const OrbDescriptor& d, int depth, std::uint32_t* node_at_depth) const {
  if (empty()) {
    if (node_at_depth != nullptr) *node_at_depth = 0;
    return kNoWord;
  }
  WordId word = kNoWord;
  std::uint32_t node = 0;
  descend(&d, 1, node_descriptor_.data(), first_child_.data(), child_count_.data(),
          node_word_.data(), std::max(depth, 0), &word, &node);
  if (node_at_depth != nullptr) *node_at_depth = node;
  return word;
}

namespace {

/// tf-idf BoW vector of a list of words, L1-normalised; sorts `words`.
void bowOfWords(std::vector<WordId>& words, const std::vector<float>& weights, BowVector& bow) {
  std::sort(words.begin(), words.end());
  double total = 0.0;
  for (std::size_t i = 0; i < words.size();) {
    std::size_t j = i;
    while (j < words.size() && words[j] == words[i]) ++j;
    const float w = weights[words[i]] * static_cast<float>(j - i);
    if (w > 0.f) {
      bow.emplace_back(words[i], w);
      total += w;
    }
    i = j;
  }
  if (total > 0.0) {
    const float inv = static_cast<float>(1.0 / total);
    for (auto& entry : bow) entry.second *= inv;
  }
}

}  // namespace

void Vocabulary::transform(const std::vector<OrbDescriptor>& descriptors, BowVector& bow) const {
  bow.clear();
  if (empty() || descriptors.empty()) return;
  std::vector<WordId> words;
  quantize(descriptors, 0, words, nullptr);
  bowOfWords(words, word_weight_, bow);
}

void Vocabulary::transform(const std::vector<OrbDescriptor>& descriptors, BowVector& bow,
                           FeatureVector& features, int direct_index_depth) const {
  bow.clear();
  features.clear();
  if (empty() || descriptors.empty()) return;
  const int depth = std::clamp(direct_index_depth, 0, levels_);
  std::vector<WordId> words;
  std::vector<std::uint32_t> nodes;
  quantize(descriptors, depth, words, &nodes);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> by_node(descriptors.size());
  for (std::size_t i = 0; i < descriptors.size(); ++i) {
    by_node[i] = {nodes[i], static_cast<std::uint32_t>(i)};
  }
  std::sort(by_node.begin(), by_node.end());
  for (const auto& [node, index] : by_node) {
    if (features.empty() || features.back().first != node) {
      features.emplace_back(node, std::vector<std::uint32_t>());
    }
    features.back().second.push_back(index);
  }
  bowOfWords(words, word_weight_, bow);
}

bool Vocabulary::operator==(const Vocabulary& o) const {
  return branching_ == o.branching_ && levels_ == o.levels_ &&
         training_images_ == o.training_images_ && node_descriptor_ == o.node_descriptor_ &&
         first_child_ == o.first_child_ && child_count_ == o.child_count_ &&
         node_word_ == o.node_word_ && word_weight_ == o.word_weight_;
}

float bowScore(const BowVector& a, const BowVector& b) {
  double score = 0.0;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first < ib->first) {
      ++ia;
    } else if (ib->first < ia->first) {
      ++ib;
    } else {
      score += std::min(ia->second, ib->second);
      ++ia;
      ++ib;
    }
  }
  return static_cast<float>(std::clamp(score, 0.0, 1.0));
}

}  // namespace ldsm::loop
