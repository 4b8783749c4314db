#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "ldsm/error.h"
#include "loop/bow_index.h"
#include "synthetic_descriptors.h"

namespace ldsm::loop {
namespace {

/// A sequence of keyframes: `places` distinct places visited in order, then revisited.
struct Sequence {
  std::vector<std::vector<OrbDescriptor>> keyframes;
  int places = 0;
};

Sequence makeSequence(int places, std::uint64_t seed) {
  SplitMix64 rng(seed);
  const test::VisualWorld world(3000, rng);
  std::vector<std::vector<OrbDescriptor>> place;
  for (int i = 0; i < places; ++i) place.push_back(world.place(200, rng));
  Sequence s;
  s.places = places;
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < places; ++i) {
      s.keyframes.push_back(world.view(place[static_cast<std::size_t>(i)], 0.7, 12, 50, rng));
    }
  }
  return s;
}

BowIndexSettings smallSettings() {
  BowIndexSettings s;
  s.online.min_keyframes = 6;
  s.online.min_descriptors = 1000;
  s.online.growth_factor = 2.0;
  return s;
}

TEST(BowIndex, OnlineVocabularyIsTrainedThenRetrainedAsTheMapGrows) {
  const Sequence seq = makeSequence(20, 3);
  BowIndex index(smallSettings());
  EXPECT_TRUE(index.online());
  std::vector<int> trained_at;
  for (std::size_t i = 0; i < seq.keyframes.size(); ++i) {
    index.add(static_cast<int>(i), seq.keyframes[i]);
    if (index.vocabulary() == nullptr) {
      EXPECT_EQ(index.bow(static_cast<int>(i)), nullptr);
      EXPECT_TRUE(index.query(static_cast<int>(i)).empty());
    }
    if (index.retrainIfDue()) trained_at.push_back(static_cast<int>(i) + 1);
  }
  // 6, 12, 24 keyframes (growth factor 2); 40 keyframes in all.
  EXPECT_EQ(trained_at, (std::vector<int>{6, 12, 24}));
  EXPECT_EQ(index.generation(), 3u);
  EXPECT_EQ(index.lastTrainingKeyframes(), 24u);
  // Every keyframe has been (re-)quantised with the current vocabulary.
  for (std::size_t i = 0; i < seq.keyframes.size(); ++i) {
    const BowVector* b = index.bow(static_cast<int>(i));
    ASSERT_NE(b, nullptr);
    BowVector fresh;
    index.vocabulary()->transform(seq.keyframes[i], fresh);
    EXPECT_EQ(*b, fresh);
    EXPECT_NE(index.featureVector(static_cast<int>(i)), nullptr);
  }
  // Revisits find their first visit (excluding the recent keyframes, as the engine does).
  for (int i = seq.places; i < 2 * seq.places; ++i) {
    const auto r = index.query(
        i, [i](int id) { return id > i - 5; }, 1);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r.front().keyframe_id, i - seq.places);
  }
}

TEST(BowIndex, TrainingJobRunsApartFromTheIndex) {
  const Sequence seq = makeSequence(8, 4);
  BowIndex index(smallSettings());
  for (std::size_t i = 0; i < 8; ++i) index.add(static_cast<int>(i), seq.keyframes[i]);
  ASSERT_TRUE(index.trainingDue());
  const OnlineTrainingJob job = index.prepareTraining();
  // The index may change while the job trains; the job shares only immutable descriptors.
  index.remove(0);
  index.add(50, seq.keyframes[9]);
  auto v = trainOnlineVocabulary(job);
  ASSERT_TRUE(v.has_value());
  // Same data and seed: same vocabulary as training inline from the same keyframes.
  auto again = trainOnlineVocabulary(job);
  EXPECT_TRUE(*v == *again);
  index.install(std::make_shared<const Vocabulary>(std::move(*v)), job.keyframes.size());
  EXPECT_EQ(index.generation(), 1u);
  EXPECT_NE(index.bow(50), nullptr);
  EXPECT_EQ(index.bow(0), nullptr);
  EXPECT_FALSE(index.trainingDue());
  std::atomic<bool> abort{true};
  EXPECT_FALSE(trainOnlineVocabulary(job, &abort).has_value());
}

TEST(BowIndex, TrainingBudgetCapsTheDescriptorsAndSetsTheDepth) {
  OnlineVocabularySettings s;
  s.branching = 8;
  s.max_levels = 4;
  s.descriptors_per_word = 8;
  EXPECT_EQ(onlineVocabularyLevels(s, 8 * 8), 1);
  EXPECT_EQ(onlineVocabularyLevels(s, 8 * 64), 2);
  EXPECT_EQ(onlineVocabularyLevels(s, 8 * 512), 3);
  EXPECT_EQ(onlineVocabularyLevels(s, 8 * 100000), 4);
  const Sequence seq = makeSequence(10, 5);
  OnlineTrainingJob job;
  job.settings = s;
  job.settings.max_training_descriptors = 500;
  for (const auto& kf : seq.keyframes) {
    job.keyframes.push_back(std::make_shared<const std::vector<OrbDescriptor>>(kf));
  }
  const auto v = trainOnlineVocabulary(job);
  ASSERT_TRUE(v.has_value());
  // ~500 descriptors -> 62 words wanted -> 2 levels of 8.
  EXPECT_EQ(v->levels(), 2);
  EXPECT_LE(v->wordCount(), 64u);
  EXPECT_EQ(v->trainingImages(), 20u);
}

TEST(BowIndex, PretrainedVocabularyIndexesAtOnceAndNeverRetrains) {
  const Sequence seq = makeSequence(10, 6);
  VocabularyParams p;
  p.branching = 8;
  p.levels = 3;
  auto v = std::make_shared<const Vocabulary>(*Vocabulary::train(seq.keyframes, p));
  BowIndex index(smallSettings(), v);
  EXPECT_FALSE(index.online());
  for (std::size_t i = 0; i < seq.keyframes.size(); ++i) {
    index.add(static_cast<int>(i), seq.keyframes[i]);
    EXPECT_NE(index.bow(static_cast<int>(i)), nullptr);
    EXPECT_FALSE(index.retrainIfDue());
  }
  EXPECT_EQ(index.vocabulary(), v.get());
  EXPECT_EQ(index.size(), 20u);
  EXPECT_GT(index.score(0, 10), index.score(0, 11));
  EXPECT_TRUE(index.remove(3));
  EXPECT_EQ(index.descriptors(3), nullptr);
  EXPECT_EQ(index.size(), 19u);
}

TEST(BowIndex, RejectsBadSettings) {
  BowIndexSettings s;
  s.online.branching = 1;
  EXPECT_THROW(BowIndex{s}, ConfigError);
  s = BowIndexSettings();
  s.online.growth_factor = 1.0;
  EXPECT_THROW(BowIndex{s}, ConfigError);
  EXPECT_THROW(BowIndex(BowIndexSettings(), std::make_shared<const Vocabulary>()), ConfigError);
}

}  // namespace
}  // namespace ldsm::loop
