#include "loop/online_vocabulary.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ldsm/error.h"

namespace ldsm::loop {

void validate(const OnlineVocabularySettings& s) {
  auto bad = [](const std::string& what) { throw ConfigError("online vocabulary: " + what); };
  if (s.branching < 2 || s.branching > Vocabulary::kMaxBranching) {
    bad("branching must be in [2, " + std::to_string(Vocabulary::kMaxBranching) + "]");
  }
  if (s.max_levels < 1 || s.max_levels > Vocabulary::kMaxLevels) {
    bad("max_levels must be in [1, " + std::to_string(Vocabulary::kMaxLevels) + "]");
  }
  if (!(s.descriptors_per_word >= 1.0 && s.descriptors_per_word <= 1e4)) {
    bad("descriptors_per_word must be in [1, 10000]");
  }
  if (s.min_keyframes < 2) bad("min_keyframes must be at least 2");
  if (!(s.growth_factor > 1.0 && s.growth_factor <= 100.0)) {
    bad("growth_factor must be in (1, 100]");
  }
  if (s.max_training_descriptors < 100) bad("max_training_descriptors must be at least 100");
  if (s.max_iterations < 0 || s.max_iterations > 100) bad("max_iterations must be in [0, 100]");
}

bool onlineTrainingDue(const OnlineVocabularySettings& s, std::size_t keyframes,
                       std::size_t descriptors, std::size_t last_trained_keyframes) {
  if (keyframes < static_cast<std::size_t>(s.min_keyframes) || descriptors < s.min_descriptors) {
    return false;
  }
  if (last_trained_keyframes == 0) return true;
  return static_cast<double>(keyframes) >=
         s.growth_factor * static_cast<double>(last_trained_keyframes);
}

int onlineVocabularyLevels(const OnlineVocabularySettings& s, std::size_t descriptors) {
  const double words = static_cast<double>(descriptors) / s.descriptors_per_word;
  if (words <= 1.0) return 1;
  const int levels =
      static_cast<int>(std::lround(std::log(words) / std::log(static_cast<double>(s.branching))));
  return std::clamp(levels, 1, s.max_levels);
}

std::optional<Vocabulary> trainOnlineVocabulary(const OnlineTrainingJob& job,
                                                const std::atomic<bool>* abort) {
  validate(job.settings);
  std::size_t total = 0;
  for (const auto& kf : job.keyframes) {
    if (kf) total += kf->size();
  }
  if (total == 0) return std::nullopt;
  // Even subsample of every keyframe down to the budget.
  const double keep = std::min(
      1.0, static_cast<double>(job.settings.max_training_descriptors) / static_cast<double>(total));
  std::vector<std::vector<OrbDescriptor>> images;
  images.reserve(job.keyframes.size());
  std::size_t used = 0;
  for (const auto& kf : job.keyframes) {
    if (!kf || kf->empty()) continue;
    const std::size_t n = kf->size();
    const auto take = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::floor(keep * static_cast<double>(n))));
    std::vector<OrbDescriptor> sample;
    sample.reserve(take);
    for (std::size_t i = 0; i < take; ++i) sample.push_back((*kf)[i * n / take]);
    used += sample.size();
    images.push_back(std::move(sample));
  }
  VocabularyParams params;
  params.branching = job.settings.branching;
  params.levels = onlineVocabularyLevels(job.settings, used);
  params.max_iterations = job.settings.max_iterations;
  params.seed = job.settings.seed;
  return Vocabulary::train(images, params, abort);
}

}  // namespace ldsm::loop
