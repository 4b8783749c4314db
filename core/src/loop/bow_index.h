// The bag-of-words side of loop detection: the keyframes' descriptors, a vocabulary (pre-trained,
// or trained online from these descriptors, see online_vocabulary.h) and the KeyframeDatabase
// holding every keyframe's BoW vector and FeatureVector.
//
// With a pre-trained vocabulary every keyframe is quantised and indexed as it is added. Without
// one, keyframes are only stored until the online policy asks for a first training; install()
// then quantises them all, and every later retraining re-quantises them again. Until then
// query() finds nothing (no loop can be closed in the first few keyframes anyway).
//
// Not internally synchronised: one task (the loop closer) owns the index. Only
// trainOnlineVocabulary(prepareTraining()) may run elsewhere, since the job shares nothing
// mutable with the index.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "loop/keyframe_database.h"
#include "loop/loop_types.h"
#include "loop/online_vocabulary.h"
#include "loop/vocabulary.h"

namespace ldsm::loop {

/// Settings of a BowIndex.
struct BowIndexSettings {
  OnlineVocabularySettings online;
  /// Depth (from the root) of the FeatureVector nodes; clamped to the vocabulary's levels.
  int direct_index_depth = 2;
};

class BowIndex {
 public:
  using Descriptors = std::shared_ptr<const std::vector<OrbDescriptor>>;

  /// Uses `pretrained` when given (never retrained), else trains online. Throws ConfigError for
  /// out-of-range settings.
  explicit BowIndex(const BowIndexSettings& settings = {},
                    std::shared_ptr<const Vocabulary> pretrained = nullptr);

  /// Stores a keyframe's descriptors (replacing an earlier keyframe of the same id) and indexes
  /// it when a vocabulary exists.
  void add(int keyframe_id, Descriptors descriptors);
  void add(int keyframe_id, std::vector<OrbDescriptor> descriptors);
  /// Forgets a keyframe; false when unknown.
  bool remove(int keyframe_id);

  std::size_t size() const { return descriptors_.size(); }
  std::size_t descriptorCount() const { return descriptor_count_; }
  /// Stored descriptors / BoW vector / FeatureVector of a keyframe; nullptr when unknown (and
  /// for the latter two also while there is no vocabulary).
  const std::vector<OrbDescriptor>* descriptors(int keyframe_id) const;
  const BowVector* bow(int keyframe_id) const { return database_.bow(keyframe_id); }
  const FeatureVector* featureVector(int keyframe_id) const {
    return database_.featureVector(keyframe_id);
  }

  /// Database query with a stored keyframe (empty when it has no BoW vector yet) or any BoW
  /// vector of the current vocabulary. See KeyframeDatabase::query(); the queried keyframe itself
  /// is always left out.
  std::vector<PlaceCandidate> query(int keyframe_id, const std::function<bool(int)>& exclude = {},
                                    int max_results = 0, float min_score = 0.f) const;
  std::vector<PlaceCandidate> query(const BowVector& bow,
                                    const std::function<bool(int)>& exclude = {},
                                    int max_results = 0, float min_score = 0.f) const;
  /// bowScore() of two stored keyframes (0 when either has no BoW vector).
  float score(int keyframe_a, int keyframe_b) const;

  /// The current vocabulary (nullptr before the first online training).
  const Vocabulary* vocabulary() const { return vocabulary_.get(); }
  std::shared_ptr<const Vocabulary> sharedVocabulary() const { return vocabulary_; }
  /// Incremented by every install(): BoW vectors of different generations are not comparable.
  std::uint64_t generation() const { return generation_; }
  bool online() const { return online_; }
  /// Keyframes stored at the last online training (0: none yet).
  std::size_t lastTrainingKeyframes() const { return last_training_keyframes_; }

  // ---- online vocabulary -----------------------------------------------------------------
  /// Whether the online policy asks for a (re)training now (always false with a pre-trained
  /// vocabulary).
  bool trainingDue() const;
  /// A snapshot for trainOnlineVocabulary(): shares the stored descriptors, copies nothing big.
  OnlineTrainingJob prepareTraining() const;
  /// Makes `vocabulary` current, re-quantises every stored keyframe and rebuilds the database.
  /// `trained_keyframes` is the keyframe count of the job it was trained on.
  void install(std::shared_ptr<const Vocabulary> vocabulary, std::size_t trained_keyframes);
  /// prepareTraining() + trainOnlineVocabulary() + install() inline when due. Returns true when a
  /// new vocabulary was installed (false when not due or aborted).
  bool retrainIfDue(const std::atomic<bool>* abort = nullptr);

 private:
  void index(int keyframe_id, const std::vector<OrbDescriptor>& descriptors);

  BowIndexSettings settings_;
  bool online_ = true;
  std::shared_ptr<const Vocabulary> vocabulary_;
  std::uint64_t generation_ = 0;
  std::size_t last_training_keyframes_ = 0;
  std::size_t descriptor_count_ = 0;
  std::map<int, Descriptors> descriptors_;  ///< ordered: deterministic training input
  KeyframeDatabase database_;
};

}  // namespace ldsm::loop
