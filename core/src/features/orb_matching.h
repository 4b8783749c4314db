// Brute-force matching of two sets of ORB descriptors: for each query descriptor the nearest train
// descriptor by Hamming distance, kept when it is close enough, clearly better than the second
// nearest (ratio test) and mutual (the query is also the train descriptor's nearest).
#pragma once

#include <utility>
#include <vector>

#include "model/orb_descriptor.h"

namespace ldsm {

struct OrbMatchSettings {
  int max_distance = 64;  ///< of 256 bits
  float ratio = 0.8f;     ///< best < ratio * second best
  bool mutual = true;
};

/// (query index, train index) pairs.
std::vector<std::pair<int, int>> matchOrb(const std::vector<OrbDescriptor>& query,
                                          const std::vector<OrbDescriptor>& train,
                                          const OrbMatchSettings& settings = {});

}  // namespace ldsm
