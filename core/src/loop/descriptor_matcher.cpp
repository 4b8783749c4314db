#include "loop/descriptor_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "ldsm/error.h"
#include "model/popcount_dispatch.h"

namespace ldsm::loop {
namespace {

constexpr int kNoDistance = std::numeric_limits<int>::max();

void checkSettings(const DescriptorMatchSettings& s) {
  if (s.max_distance < 0 || s.max_distance > 256) {
    throw InputError("descriptor matching: max_distance must be in [0, 256] (got " +
                     std::to_string(s.max_distance) + ")");
  }
  if (!(s.ratio > 0.0f && s.ratio <= 1.0f)) {
    throw InputError("descriptor matching: ratio must be in (0, 1] (got " +
                     std::to_string(s.ratio) + ")");
  }
}

// Best and second-best distances of every query feature and the best query of every train
// feature, accumulated over the groups of features that may match.
class MatchTable {
 public:
  MatchTable(std::size_t n_query, std::size_t n_train)
      : q_best_(n_query, kNoDistance),
        q_second_(n_query, kNoDistance),
        q_best_train_(n_query, 0),
        t_best_(n_train, kNoDistance),
        t_best_query_(n_train, 0) {}

  LDSM_POPCNT_CLONES
  void compare(const std::vector<OrbDescriptor>& qd, const std::vector<std::uint32_t>& qi,
               const std::vector<OrbDescriptor>& td, const std::vector<std::uint32_t>& ti) {
    for (const std::uint32_t q : qi) {
      for (const std::uint32_t t : ti) {
        const int d = hammingDistance(qd[q], td[t]);
        if (d < q_best_[q]) {
          q_second_[q] = q_best_[q];
          q_best_[q] = d;
          q_best_train_[q] = t;
        } else if (d < q_second_[q]) {
          q_second_[q] = d;
        }
        if (d < t_best_[t]) {
          t_best_[t] = d;
          t_best_query_[t] = q;
        }
      }
    }
  }

  std::vector<DescriptorMatch> select(const DescriptorMatchSettings& s) const {
    std::vector<DescriptorMatch> out;
    for (std::uint32_t q = 0; q < q_best_.size(); ++q) {
      const int best = q_best_[q];
      if (best == kNoDistance || best > s.max_distance) continue;
      const int second = q_second_[q];
      if (s.ratio < 1.0f && second != kNoDistance &&
          !(static_cast<float>(best) < s.ratio * static_cast<float>(second))) {
        continue;
      }
      const std::uint32_t t = q_best_train_[q];
      if (s.mutual_check && t_best_query_[t] != q) continue;
      out.push_back({q, t, best});
    }
    // Without the mutual check several queries may pick the same train feature: keep the closest.
    std::sort(out.begin(), out.end(), [](const DescriptorMatch& a, const DescriptorMatch& b) {
      return a.train != b.train ? a.train < b.train : a.distance < b.distance;
    });
    out.erase(std::unique(out.begin(), out.end(),
                          [](const DescriptorMatch& a, const DescriptorMatch& b) {
                            return a.train == b.train;
                          }),
              out.end());
    std::sort(out.begin(), out.end(),
              [](const DescriptorMatch& a, const DescriptorMatch& b) { return a.query < b.query; });
    return out;
  }

 private:
  std::vector<int> q_best_, q_second_;
  std::vector<std::uint32_t> q_best_train_;
  std::vector<int> t_best_;
  std::vector<std::uint32_t> t_best_query_;
};

using FeatureNode = FeatureVector::value_type;

std::vector<const FeatureNode*> sortedNodes(const FeatureVector& fv) {
  std::vector<const FeatureNode*> nodes(fv.size());
  for (std::size_t i = 0; i < fv.size(); ++i) nodes[i] = &fv[i];
  std::stable_sort(nodes.begin(), nodes.end(),
                   [](const FeatureNode* x, const FeatureNode* y) { return x->first < y->first; });
  return nodes;
}

}  // namespace

void validateKeyframeFeatures(const KeyframeFeatures& kf, const char* what) {
  const std::string name = std::string(what) + " " + std::to_string(kf.keyframe_id);
  const std::size_t n = kf.descriptors.size();
  if (kf.pixels.size() != n || kf.idepth.size() != n) {
    throw InputError(name + ": " + std::to_string(kf.pixels.size()) + " pixels, " +
                     std::to_string(kf.idepth.size()) + " inverse depths and " + std::to_string(n) +
                     " descriptors (must be equal)");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!kf.pixels[i].allFinite()) {
      throw InputError(name + ": feature " + std::to_string(i) + " has a non-finite pixel");
    }
  }
  for (const auto& node : kf.feature_vector) {
    for (const std::uint32_t i : node.second) {
      if (i >= n) {
        throw InputError(name + ": feature vector node " + std::to_string(node.first) +
                         " refers to feature " + std::to_string(i) + " of " + std::to_string(n));
      }
    }
  }
}

std::vector<DescriptorMatch> matchDescriptors(const KeyframeFeatures& query,
                                              const KeyframeFeatures& train,
                                              const DescriptorMatchSettings& settings) {
  checkSettings(settings);
  validateKeyframeFeatures(query, "query keyframe");
  validateKeyframeFeatures(train, "train keyframe");
  MatchTable table(query.descriptors.size(), train.descriptors.size());

  const bool by_node =
      settings.use_feature_vector && !query.feature_vector.empty() && !train.feature_vector.empty();
  if (by_node) {
    // Merge-join the nodes present in both FeatureVectors (visited in node order).
    const auto qn = sortedNodes(query.feature_vector);
    const auto tn = sortedNodes(train.feature_vector);
    std::size_t a = 0, b = 0;
    while (a < qn.size() && b < tn.size()) {
      if (qn[a]->first < tn[b]->first) {
        ++a;
      } else if (tn[b]->first < qn[a]->first) {
        ++b;
      } else {
        table.compare(query.descriptors, qn[a]->second, train.descriptors, tn[b]->second);
        ++a;
        ++b;
      }
    }
  } else {
    std::vector<std::uint32_t> all_q(query.descriptors.size());
    std::vector<std::uint32_t> all_t(train.descriptors.size());
    std::iota(all_q.begin(), all_q.end(), 0u);
    std::iota(all_t.begin(), all_t.end(), 0u);
    table.compare(query.descriptors, all_q, train.descriptors, all_t);
  }
  return table.select(settings);
}

}  // namespace ldsm::loop
