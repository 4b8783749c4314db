// A vocabulary trained from the session's own keyframes, so that loop detection works on a fresh
// machine without a pre-trained vocabulary file (see docs/loop-closure.md, "Vocabulary").
//
// Policy: the first vocabulary is trained once min_keyframes keyframes with min_descriptors
// descriptors in total have been collected; it is retrained whenever the number of keyframes has
// grown by growth_factor since the last training (2: after 2x, 4x, 8x... the first count), and
// every stored keyframe is then re-quantised (BowIndex::install()). The depth adapts to the data:
// levels = round(log_k(descriptors / descriptors_per_word)), clamped to [1, max_levels].
//
// Cost budget: training uses at most max_training_descriptors descriptors (an even subsample of
// every keyframe's descriptors; every keyframe stays a document for the idf weights) and at most
// max_iterations k-majority rounds per node: one training costs 57 ms of CPU for a 148-keyframe
// session and 140 ms at the full budget (bench_loop_features). Training is a
// pure function of an OnlineTrainingJob, meant to run in the loop closer's background task; it
// can be aborted through an atomic flag.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "loop/loop_types.h"
#include "loop/vocabulary.h"

namespace ldsm::loop {

/// Settings of the online vocabulary.
struct OnlineVocabularySettings {
  int branching = 8;                   ///< k
  int max_levels = 4;                  ///< upper bound of the adaptive depth L
  double descriptors_per_word = 8;     ///< target training descriptors per leaf (sets L)
  int min_keyframes = 8;               ///< first training once this many keyframes are stored...
  std::size_t min_descriptors = 1500;  ///< ...holding at least this many descriptors in total
  double growth_factor = 2.0;          ///< retrain when keyframes >= growth_factor * last count
  std::size_t max_training_descriptors = 60000;  ///< cost budget of one training
  int max_iterations = 8;                        ///< k-majority rounds per node
  std::uint64_t seed = 1;
};

/// Throws ConfigError when a setting is out of range.
void validate(const OnlineVocabularySettings& settings);

/// Everything one training needs: shared, immutable descriptor sets and the settings.
struct OnlineTrainingJob {
  std::vector<std::shared_ptr<const std::vector<OrbDescriptor>>> keyframes;
  OnlineVocabularySettings settings;
};

/// Whether the policy wants a (re)training with `keyframes` keyframes holding `descriptors`
/// descriptors, the last training having seen `last_trained_keyframes` (0: never trained).
bool onlineTrainingDue(const OnlineVocabularySettings& settings, std::size_t keyframes,
                       std::size_t descriptors, std::size_t last_trained_keyframes);

/// The adaptive depth for `descriptors` training descriptors.
int onlineVocabularyLevels(const OnlineVocabularySettings& settings, std::size_t descriptors);

/// Trains the vocabulary of a job (subsampled to the budget). std::nullopt when aborted or when
/// the job holds no descriptor.
std::optional<Vocabulary> trainOnlineVocabulary(const OnlineTrainingJob& job,
                                                const std::atomic<bool>* abort = nullptr);

}  // namespace ldsm::loop
