// ORB descriptor matching: correct correspondences under bit noise, max distance, ratio test,
// mutual check, FeatureVector restriction and bad input.
#include <gtest/gtest.h>

#include <map>

#include "ldsm/error.h"
#include "loop/descriptor_matcher.h"
#include "synthetic_keyframes.h"

namespace ldsm::loop {
namespace {

using test::SceneRandom;

KeyframeFeatures withDescriptors(const std::vector<OrbDescriptor>& d) {
  KeyframeFeatures kf;
  kf.descriptors = d;
  kf.pixels.assign(d.size(), Eigen::Vector2f(10.0f, 20.0f));
  kf.idepth.assign(d.size(), 0.0f);
  return kf;
}

OrbDescriptor flipBits(OrbDescriptor d, std::initializer_list<int> bits) {
  for (const int b : bits) d[b / 64] ^= std::uint64_t{1} << (b % 64);
  return d;
}

// 200 descriptors, the train copies permuted and with up to 12 flipped bits, plus 100 unrelated.
struct NoisyCopies {
  KeyframeFeatures query, train;
  std::map<std::uint32_t, std::uint32_t> truth;  // query -> train
};

NoisyCopies makeNoisyCopies(int max_flips) {
  SceneRandom rnd(7);
  std::vector<OrbDescriptor> q, t(300);
  for (int i = 0; i < 200; ++i) q.push_back(rnd.descriptor());
  NoisyCopies nc;
  for (int i = 0; i < 200; ++i) {
    const auto j = static_cast<std::uint32_t>((i * 37 + 11) % 300);
    t[j] = rnd.flipped(q[i], max_flips);
    nc.truth[static_cast<std::uint32_t>(i)] = j;
  }
  for (int j = 0; j < 300; ++j) {
    if (std::none_of(nc.truth.begin(), nc.truth.end(),
                     [&](const auto& kv) { return kv.second == static_cast<std::uint32_t>(j); })) {
      t[j] = rnd.descriptor();
    }
  }
  nc.query = withDescriptors(q);
  nc.train = withDescriptors(t);
  return nc;
}

TEST(DescriptorMatcher, FindsTheTrueCorrespondences) {
  const NoisyCopies nc = makeNoisyCopies(12);
  const auto matches = matchDescriptors(nc.query, nc.train, DescriptorMatchSettings{});
  EXPECT_EQ(matches.size(), 200u);
  for (const DescriptorMatch& m : matches) {
    EXPECT_EQ(nc.truth.at(m.query), m.train);
    EXPECT_EQ(m.distance,
              hammingDistance(nc.query.descriptors[m.query], nc.train.descriptors[m.train]));
    EXPECT_LE(m.distance, 12);
  }
  for (std::size_t k = 1; k < matches.size(); ++k)
    EXPECT_LT(matches[k - 1].query, matches[k].query);
}

TEST(DescriptorMatcher, MaxDistanceRejectsFarDescriptors) {
  KeyframeFeatures q = withDescriptors({OrbDescriptor{}});
  KeyframeFeatures t = withDescriptors({flipBits(OrbDescriptor{}, {1, 5, 70, 130, 200, 255})});
  DescriptorMatchSettings s;
  s.max_distance = 6;
  EXPECT_EQ(matchDescriptors(q, t, s).size(), 1u);
  s.max_distance = 5;
  EXPECT_TRUE(matchDescriptors(q, t, s).empty());
}

TEST(DescriptorMatcher, RatioTestRejectsAmbiguousMatches) {
  const OrbDescriptor a{};
  KeyframeFeatures q = withDescriptors({a});
  // Two train descriptors at distances 4 and 5: ambiguous at ratio 0.8, accepted at ratio 1.
  KeyframeFeatures t =
      withDescriptors({flipBits(a, {1, 2, 3, 4}), flipBits(a, {100, 101, 102, 103, 104})});
  DescriptorMatchSettings s;
  s.mutual_check = false;
  s.ratio = 0.8f;
  EXPECT_TRUE(matchDescriptors(q, t, s).empty());
  s.ratio = 1.0f;
  const auto m = matchDescriptors(q, t, s);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].train, 0u);
  EXPECT_EQ(m[0].distance, 4);
}

TEST(DescriptorMatcher, MutualCheckDropsOneSidedMatches) {
  // q0 -> t0 (5), but t0's best is q1 (2); q1's best is t1 (1).
  const OrbDescriptor t0{};
  const OrbDescriptor q1 = flipBits(t0, {10, 11});
  const OrbDescriptor t1 = flipBits(q1, {12});
  const OrbDescriptor q0 = flipBits(t0, {200, 201, 202, 203, 204});
  KeyframeFeatures q = withDescriptors({q0, q1});
  KeyframeFeatures t = withDescriptors({t0, t1});
  DescriptorMatchSettings s;
  s.ratio = 1.0f;
  s.mutual_check = false;
  auto m = matchDescriptors(q, t, s);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].query, 0u);
  EXPECT_EQ(m[0].train, 0u);
  s.mutual_check = true;
  m = matchDescriptors(q, t, s);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].query, 1u);
  EXPECT_EQ(m[0].train, 1u);
}

TEST(DescriptorMatcher, WithoutMutualCheckEachTrainFeatureIsUsedOnce) {
  const OrbDescriptor t0{};
  KeyframeFeatures q = withDescriptors({flipBits(t0, {1, 2, 3}), flipBits(t0, {9})});
  KeyframeFeatures t = withDescriptors({t0});
  DescriptorMatchSettings s;
  s.mutual_check = false;
  const auto m = matchDescriptors(q, t, s);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].query, 1u);  // the closer one
}

TEST(DescriptorMatcher, FeatureVectorRestrictsTheSearchToSharedNodes) {
  NoisyCopies nc = makeNoisyCopies(6);
  // Node 1 holds queries 0..99, node 2 queries 100..199; on the train side the partners of
  // queries 0..49 sit under node 1 and everything else under node 3 (absent from the query).
  FeatureVector fq{{1, {}}, {2, {}}}, ft{{3, {}}, {1, {}}};  // train side deliberately unsorted
  for (std::uint32_t i = 0; i < 200; ++i) fq[i < 100 ? 0 : 1].second.push_back(i);
  std::vector<bool> in_node1(300, false);
  for (std::uint32_t i = 0; i < 50; ++i) in_node1[nc.truth.at(i)] = true;
  for (std::uint32_t j = 0; j < 300; ++j) ft[in_node1[j] ? 1 : 0].second.push_back(j);
  nc.query.feature_vector = fq;
  nc.train.feature_vector = ft;
  DescriptorMatchSettings s;
  const auto m = matchDescriptors(nc.query, nc.train, s);
  ASSERT_EQ(m.size(), 50u);
  for (const DescriptorMatch& x : m) {
    EXPECT_LT(x.query, 50u);
    EXPECT_EQ(nc.truth.at(x.query), x.train);
  }
  s.use_feature_vector = false;
  EXPECT_EQ(matchDescriptors(nc.query, nc.train, s).size(), 200u);
}

TEST(DescriptorMatcher, BadInputThrows) {
  KeyframeFeatures good = withDescriptors({OrbDescriptor{}, OrbDescriptor{}});
  KeyframeFeatures bad = good;
  bad.idepth.pop_back();
  EXPECT_THROW(matchDescriptors(good, bad, {}), InputError);
  bad = good;
  bad.pixels[1] = Eigen::Vector2f(std::nanf(""), 1.0f);
  EXPECT_THROW(matchDescriptors(bad, good, {}), InputError);
  bad = good;
  bad.feature_vector = {{4, {0, 2}}};
  try {
    matchDescriptors(good, bad, {});
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("refers to feature 2"), std::string::npos) << e.what();
  }
  DescriptorMatchSettings s;
  s.max_distance = 300;
  EXPECT_THROW(matchDescriptors(good, good, s), InputError);
  s = {};
  s.ratio = 0.0f;
  EXPECT_THROW(matchDescriptors(good, good, s), InputError);
}

TEST(DescriptorMatcher, EmptyKeyframesGiveNoMatches) {
  const KeyframeFeatures empty;
  const KeyframeFeatures one = withDescriptors({OrbDescriptor{}});
  EXPECT_TRUE(matchDescriptors(empty, one, {}).empty());
  EXPECT_TRUE(matchDescriptors(one, empty, {}).empty());
}

}  // namespace
}  // namespace ldsm::loop
