#include "loop/bow_index.h"

#include <utility>

#include "ldsm/error.h"

namespace ldsm::loop {

BowIndex::BowIndex(const BowIndexSettings& settings, std::shared_ptr<const Vocabulary> pretrained)
    : settings_(settings), online_(pretrained == nullptr), vocabulary_(std::move(pretrained)) {
  validate(settings_.online);
  if (vocabulary_ && vocabulary_->empty()) {
    throw ConfigError("BowIndex: the pre-trained vocabulary is empty");
  }
  if (vocabulary_) generation_ = 1;
}

void BowIndex::add(int keyframe_id, std::vector<OrbDescriptor> descriptors) {
  add(keyframe_id, std::make_shared<const std::vector<OrbDescriptor>>(std::move(descriptors)));
}

void BowIndex::add(int keyframe_id, Descriptors descriptors) {
  if (!descriptors) descriptors = std::make_shared<const std::vector<OrbDescriptor>>();
  remove(keyframe_id);
  descriptor_count_ += descriptors->size();
  const std::vector<OrbDescriptor>& d = *descriptors;
  descriptors_.emplace(keyframe_id, std::move(descriptors));
  if (vocabulary_) index(keyframe_id, d);
}

bool BowIndex::remove(int keyframe_id) {
  const auto it = descriptors_.find(keyframe_id);
  if (it == descriptors_.end()) return false;
  descriptor_count_ -= it->second->size();
  descriptors_.erase(it);
  database_.remove(keyframe_id);
  return true;
}

const std::vector<OrbDescriptor>* BowIndex::descriptors(int keyframe_id) const {
  const auto it = descriptors_.find(keyframe_id);
  return it == descriptors_.end() ? nullptr : it->second.get();
}

void BowIndex::index(int keyframe_id, const std::vector<OrbDescriptor>& descriptors) {
  BowVector bow;
  FeatureVector features;
  vocabulary_->transform(descriptors, bow, features, settings_.direct_index_depth);
  database_.add(keyframe_id, bow, std::move(features));
}

std::vector<PlaceCandidate> BowIndex::query(int keyframe_id,
                                            const std::function<bool(int)>& exclude,
                                            int max_results, float min_score) const {
  const BowVector* b = bow(keyframe_id);
  if (b == nullptr) return {};
  return database_.query(
      *b, [&](int id) { return id == keyframe_id || (exclude && exclude(id)); }, max_results,
      min_score);
}

std::vector<PlaceCandidate> BowIndex::query(const BowVector& b,
                                            const std::function<bool(int)>& exclude,
                                            int max_results, float min_score) const {
  return database_.query(b, exclude, max_results, min_score);
}

float BowIndex::score(int keyframe_a, int keyframe_b) const {
  const BowVector* a = bow(keyframe_a);
  const BowVector* b = bow(keyframe_b);
  return a != nullptr && b != nullptr ? bowScore(*a, *b) : 0.f;
}

bool BowIndex::trainingDue() const {
  return online_ && onlineTrainingDue(settings_.online, descriptors_.size(), descriptor_count_,
                                      last_training_keyframes_);
}

OnlineTrainingJob BowIndex::prepareTraining() const {
  OnlineTrainingJob job;
  job.settings = settings_.online;
  job.keyframes.reserve(descriptors_.size());
  for (const auto& [id, d] : descriptors_) job.keyframes.push_back(d);
  return job;
}

void BowIndex::install(std::shared_ptr<const Vocabulary> vocabulary,
                       std::size_t trained_keyframes) {
  if (!vocabulary || vocabulary->empty()) {
    throw ConfigError("BowIndex::install: the vocabulary is empty");
  }
  vocabulary_ = std::move(vocabulary);
  ++generation_;
  last_training_keyframes_ = trained_keyframes;
  database_.clear();
  for (const auto& [id, d] : descriptors_) index(id, *d);
}

bool BowIndex::retrainIfDue(const std::atomic<bool>* abort) {
  if (!trainingDue()) return false;
  const OnlineTrainingJob job = prepareTraining();
  std::optional<Vocabulary> v = trainOnlineVocabulary(job, abort);
  if (!v || v->empty()) return false;
  install(std::make_shared<const Vocabulary>(std::move(*v)), job.keyframes.size());
  return true;
}

}  // namespace ldsm::loop
