#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "ldsm/error.h"
#include "loop/keyframe_database.h"
#include "loop/vocabulary.h"
#include "synthetic_descriptors.h"

namespace ldsm::loop {
namespace {

/// Places of 150 features from a world of 3000 appearance centres; two visits of each with 70 %
/// of the features seen, 12 bits of noise and 40 clutter features.
struct Places {
  std::vector<std::vector<OrbDescriptor>> first, second;
};

Places makePlaces(int count, std::uint64_t seed) {
  SplitMix64 rng(seed);
  const test::VisualWorld world(3000, rng);
  Places p;
  for (int i = 0; i < count; ++i) {
    const auto place = world.place(150, rng);
    p.first.push_back(world.view(place, 0.7, 12, 40, rng));
    p.second.push_back(world.view(place, 0.7, 12, 40, rng));
  }
  return p;
}

Vocabulary trainOn(const std::vector<std::vector<OrbDescriptor>>& images) {
  VocabularyParams params;
  params.branching = 10;
  params.levels = 3;
  return *Vocabulary::train(images, params);
}

TEST(KeyframeDatabase, RanksTheRevisitedPlaceFirst) {
  const Places places = makePlaces(30, 1);
  const Vocabulary v = trainOn(places.first);
  KeyframeDatabase db;
  for (std::size_t i = 0; i < places.first.size(); ++i) {
    BowVector bow;
    FeatureVector fv;
    v.transform(places.first[i], bow, fv, 1);
    db.add(static_cast<int>(i), bow, fv);
  }
  ASSERT_EQ(db.size(), 30u);
  for (std::size_t i = 0; i < places.second.size(); ++i) {
    BowVector q;
    v.transform(places.second[i], q);
    const auto result = db.query(q, {}, 5);
    ASSERT_FALSE(result.empty());
    EXPECT_EQ(result.front().keyframe_id, static_cast<int>(i));
    EXPECT_LE(result.size(), 5u);
    // Scores are the L1 scores, sorted.
    for (std::size_t r = 0; r < result.size(); ++r) {
      EXPECT_NEAR(result[r].score, bowScore(q, *db.bow(result[r].keyframe_id)), 1e-5);
      if (r > 0) {
        EXPECT_GE(result[r - 1].score, result[r].score);
      }
    }
    // A clear margin over the second best (which only shares chance words).
    ASSERT_GE(result.size(), 2u);
    EXPECT_GT(result[0].score, 1.4f * result[1].score);
  }
}

TEST(KeyframeDatabase, ExcludeRemoveReplaceAndMinScore) {
  const Places places = makePlaces(10, 2);
  const Vocabulary v = trainOn(places.first);
  KeyframeDatabase db;
  std::vector<BowVector> bows(10);
  for (int i = 0; i < 10; ++i) {
    FeatureVector fv;
    v.transform(places.first[static_cast<std::size_t>(i)], bows[static_cast<std::size_t>(i)], fv,
                1);
    db.add(100 + i, bows[static_cast<std::size_t>(i)], fv);
  }
  BowVector q;
  v.transform(places.second[4], q);
  EXPECT_EQ(db.query(q).front().keyframe_id, 104);
  // Excluded keyframes never come back.
  const auto ex = db.query(q, [](int id) { return id == 104 || id == 105; });
  for (const auto& c : ex) {
    EXPECT_NE(c.keyframe_id, 104);
    EXPECT_NE(c.keyframe_id, 105);
  }
  // min_score cuts the tail.
  const float top = db.query(q).front().score;
  const auto strict = db.query(q, {}, 0, top);
  ASSERT_EQ(strict.size(), 1u);
  // Removal.
  EXPECT_TRUE(db.remove(104));
  EXPECT_FALSE(db.remove(104));
  EXPECT_FALSE(db.contains(104));
  EXPECT_EQ(db.bow(104), nullptr);
  for (const auto& c : db.query(q)) EXPECT_NE(c.keyframe_id, 104);
  // The freed slot is reused by a new keyframe; replacing an id keeps one entry.
  db.add(200, bows[4]);
  EXPECT_EQ(db.query(q).front().keyframe_id, 200);
  db.add(200, bows[7]);
  EXPECT_EQ(db.size(), 10u);
  EXPECT_NE(db.query(q).front().keyframe_id, 200);
  EXPECT_EQ(db.keyframeIds().front(), 100);
  EXPECT_NE(db.featureVector(101), nullptr);
  EXPECT_FALSE(db.featureVector(101)->empty());
  db.clear();
  EXPECT_EQ(db.size(), 0u);
  EXPECT_TRUE(db.query(q).empty());
}

TEST(KeyframeDatabase, RejectsUnsortedVectors) {
  KeyframeDatabase db;
  EXPECT_THROW(db.add(1, BowVector{{5, 0.5f}, {2, 0.5f}}), InputError);
  EXPECT_THROW(db.add(1, BowVector{{2, 0.5f}, {2, 0.5f}}), InputError);
  EXPECT_EQ(db.size(), 0u);
}

TEST(KeyframeDatabase, TiesAreBrokenByKeyframeId) {
  KeyframeDatabase db;
  const BowVector b{{1, 0.5f}, {2, 0.5f}};
  db.add(7, b);
  db.add(3, b);
  db.add(5, b);
  const auto r = db.query(b);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].keyframe_id, 3);
  EXPECT_EQ(r[1].keyframe_id, 5);
  EXPECT_EQ(r[2].keyframe_id, 7);
  EXPECT_FLOAT_EQ(r[0].score, 1.f);
}

}  // namespace
}  // namespace ldsm::loop
