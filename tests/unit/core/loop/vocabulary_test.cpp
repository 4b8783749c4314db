#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "ldsm/error.h"
#include "loop/vocabulary.h"
#include "synthetic_descriptors.h"

namespace ldsm::loop {
namespace {

/// Descriptors in 16 clusters with a two-level structure that a k = 4, L = 2 tree must find:
/// 4 random super-centres (~128 bits apart), 4 cluster centres 30 bits from each, members 4 bits
/// from their cluster centre. Image i shows clusters 0 and 1 (in every image) and the clusters c
/// with c % 4 == i % 4, six members of each.
struct WordData {
  std::vector<OrbDescriptor> centers;
  std::vector<std::vector<OrbDescriptor>> images;
  std::vector<std::vector<int>> image_words;
};

WordData makeWordData(int images, std::uint64_t seed) {
  SplitMix64 rng(seed);
  WordData d;
  for (int s = 0; s < 4; ++s) {
    const OrbDescriptor super = test::randomDescriptor(rng);
    for (int j = 0; j < 4; ++j) d.centers.push_back(test::flipBits(super, 30, rng));
  }
  for (int i = 0; i < images; ++i) {
    std::vector<OrbDescriptor> img;
    std::vector<int> ws;
    for (int w = 0; w < 16; ++w) {
      if (w < 2 || w % 4 == i % 4) {
        for (int r = 0; r < 6; ++r) {
          img.push_back(test::flipBits(d.centers[static_cast<std::size_t>(w)], 4, rng));
        }
        ws.push_back(w);
      }
    }
    d.images.push_back(img);
    d.image_words.push_back(ws);
  }
  return d;
}

VocabularyParams hierarchy() {
  VocabularyParams p;
  p.branching = 4;
  p.levels = 2;
  return p;
}

Vocabulary trainOrDie(const std::vector<std::vector<OrbDescriptor>>& images,
                      const VocabularyParams& p) {
  auto v = Vocabulary::train(images, p);
  EXPECT_TRUE(v.has_value());
  return v ? std::move(*v) : Vocabulary();
}

TEST(Vocabulary, NoisyCopiesOfAWordShareALeafAndIdfMatchesDocumentFrequency) {
  const WordData d = makeWordData(16, 5);
  const Vocabulary v = trainOrDie(d.images, hierarchy());
  EXPECT_EQ(v.trainingImages(), 16u);
  EXPECT_EQ(v.branching(), 4);
  EXPECT_EQ(v.levels(), 2);
  // 16 leaves for 16 clusters: only the right hierarchy gives every cluster its own word.
  EXPECT_EQ(v.wordCount(), 16u);
  EXPECT_EQ(v.nodeCount(), 21u);

  // Fresh noisy copies of each centre all fall in the same word, distinct per centre.
  SplitMix64 rng(99);
  std::map<WordId, int> owner;
  for (std::size_t w = 0; w < d.centers.size(); ++w) {
    const WordId word = v.wordOf(d.centers[w]);
    ASSERT_NE(word, Vocabulary::kNoWord);
    for (int r = 0; r < 20; ++r) {
      EXPECT_EQ(v.wordOf(test::flipBits(d.centers[w], 4, rng)), word) << "centre " << w;
    }
    EXPECT_TRUE(owner.emplace(word, static_cast<int>(w)).second) << "two centres share a word";
  }
  // idf = ln(N / n_w): words 0, 1 are in all 16 images (weight 0); the others in 4 of 16.
  for (std::size_t w = 0; w < d.centers.size(); ++w) {
    const float expected = w < 2 ? 0.f : static_cast<float>(std::log(16.0 / 4.0));
    EXPECT_NEAR(v.wordWeight(v.wordOf(d.centers[w])), expected, 1e-6) << "centre " << w;
  }
}

TEST(Vocabulary, TransformGivesNormalisedTfIdfAndADirectIndex) {
  const WordData d = makeWordData(16, 6);
  const Vocabulary v = trainOrDie(d.images, hierarchy());
  BowVector bow;
  FeatureVector fv;
  v.transform(d.images[5], bow, fv, 1);
  // Words 0 and 1 have idf 0 and are left out; the others of image 5 (w % 4 == 1) appear with
  // equal tf, hence equal weights summing to 1.
  std::set<WordId> expected;
  for (int w : d.image_words[5]) {
    if (w >= 2) expected.insert(v.wordOf(d.centers[static_cast<std::size_t>(w)]));
  }
  ASSERT_EQ(bow.size(), expected.size());
  float sum = 0.f;
  for (std::size_t i = 0; i < bow.size(); ++i) {
    EXPECT_TRUE(expected.count(bow[i].first));
    EXPECT_NEAR(bow[i].second, 1.f / static_cast<float>(bow.size()), 1e-6);
    if (i > 0) {
      EXPECT_LT(bow[i - 1].first, bow[i].first);
    }
    sum += bow[i].second;
  }
  EXPECT_NEAR(sum, 1.f, 1e-6);
  // The FeatureVector partitions the features by their level-1 node, sorted by node.
  std::vector<int> seen(d.images[5].size(), 0);
  for (std::size_t i = 0; i < fv.size(); ++i) {
    if (i > 0) {
      EXPECT_LT(fv[i - 1].first, fv[i].first);
    }
    for (std::uint32_t f : fv[i].second) {
      ++seen[f];
      std::uint32_t node = 0;
      v.wordOf(d.images[5][f], 1, &node);
      EXPECT_EQ(node, fv[i].first);
    }
  }
  for (int s : seen) EXPECT_EQ(s, 1);
}

TEST(Vocabulary, ScoreIsOneForIdenticalZeroForDisjointAndSymmetric) {
  const WordData d = makeWordData(16, 7);
  const Vocabulary v = trainOrDie(d.images, hierarchy());
  BowVector a, b, c;
  v.transform(d.images[1], a);
  v.transform(d.images[5], b);  // same words as image 1 (1 % 4 == 5 % 4)
  v.transform(d.images[2], c);  // disjoint informative words
  ASSERT_FALSE(a.empty());
  EXPECT_NEAR(bowScore(a, a), 1.f, 1e-6);
  EXPECT_NEAR(bowScore(a, b), 1.f, 1e-5);
  EXPECT_FLOAT_EQ(bowScore(a, c), 0.f);
  EXPECT_FLOAT_EQ(bowScore(a, BowVector()), 0.f);
  // Partial overlap: hand-made vectors, 1 - 0.5 |x - y|_1.
  const BowVector x{{1, 0.5f}, {2, 0.5f}};
  const BowVector y{{2, 0.25f}, {3, 0.75f}};
  EXPECT_NEAR(bowScore(x, y), 1.f - 0.5f * (0.5f + 0.25f + 0.75f), 1e-6);
  EXPECT_FLOAT_EQ(bowScore(x, y), bowScore(y, x));
}

TEST(Vocabulary, TrainingIsDeterministicForASeed) {
  const WordData d = makeWordData(10, 8);
  VocabularyParams p = hierarchy();
  p.levels = 3;
  p.seed = 17;
  const Vocabulary a = trainOrDie(d.images, p);
  const Vocabulary b = trainOrDie(d.images, p);
  EXPECT_TRUE(a == b);
  EXPECT_EQ(a.serialize(), b.serialize());
  p.seed = 18;
  const Vocabulary c = trainOrDie(d.images, p);
  EXPECT_FALSE(a == c);
}

TEST(Vocabulary, RejectsBadParametersAndEmptyInput) {
  const WordData d = makeWordData(4, 9);
  VocabularyParams p;
  p.branching = 1;
  EXPECT_THROW(Vocabulary::train(d.images, p), ConfigError);
  p.branching = 65;
  EXPECT_THROW(Vocabulary::train(d.images, p), ConfigError);
  p = VocabularyParams();
  p.levels = 0;
  EXPECT_THROW(Vocabulary::train(d.images, p), ConfigError);
  p = VocabularyParams();
  EXPECT_THROW(Vocabulary::train({{}, {}}, p), InputError);
  std::atomic<bool> abort{true};
  EXPECT_FALSE(Vocabulary::train(d.images, p, &abort).has_value());
  // An empty vocabulary quantises nothing.
  const Vocabulary empty;
  BowVector bow{{1, 1.f}};
  empty.transform(d.images[0], bow);
  EXPECT_TRUE(bow.empty());
  EXPECT_EQ(empty.wordOf(d.images[0][0]), Vocabulary::kNoWord);
  EXPECT_THROW(empty.serialize(), Error);
}

// ---- serialisation -------------------------------------------------------------------------

/// FNV-1a over 64-bit little-endian words, tail zero-padded, then the length: the documented
/// checksum, written independently of the implementation.
std::uint64_t specChecksum(const std::vector<std::uint8_t>& b, std::size_t n) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (std::size_t i = 0; i < n; i += 8) {
    std::uint64_t w = 0;
    for (std::size_t k = 0; k < 8 && i + k < n; ++k)
      w |= static_cast<std::uint64_t>(b[i + k]) << (8 * k);
    h = (h ^ w) * 0x100000001B3ull;
  }
  return (h ^ n) * 0x100000001B3ull;
}

void resign(std::vector<std::uint8_t>& b) {
  const std::uint64_t h = specChecksum(b, b.size() - 8);
  for (int k = 0; k < 8; ++k)
    b[b.size() - 8 + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(h >> (8 * k));
}

void putU32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k)
    b[at + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(v >> (8 * k));
}

std::string errorOf(const std::vector<std::uint8_t>& b) {
  try {
    Vocabulary::deserialize(b.data(), b.size(), "voc.bin");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

class VocabularyFormat : public ::testing::Test {
 protected:
  void SetUp() override {
    const WordData d = makeWordData(12, 10);
    VocabularyParams p = hierarchy();
    p.levels = 3;
    vocabulary_ = trainOrDie(d.images, p);
    bytes_ = vocabulary_.serialize();
    probe_ = d.images[3];
  }
  Vocabulary vocabulary_;
  std::vector<std::uint8_t> bytes_;
  std::vector<OrbDescriptor> probe_;
};

TEST_F(VocabularyFormat, RoundTripIsExact) {
  const std::size_t nodes = vocabulary_.nodeCount();
  const std::size_t words = vocabulary_.wordCount();
  EXPECT_EQ(bytes_.size(), 32 + nodes + 32 * (nodes - 1) + 4 * words + 8);
  EXPECT_EQ(std::string(bytes_.begin(), bytes_.begin() + 8), "LDSMVOCB");
  EXPECT_EQ(specChecksum(bytes_, bytes_.size() - 8), [&] {
    std::uint64_t h = 0;
    for (int k = 7; k >= 0; --k)
      h = (h << 8) | bytes_[bytes_.size() - 8 + static_cast<std::size_t>(k)];
    return h;
  }());
  const Vocabulary back = Vocabulary::deserialize(bytes_.data(), bytes_.size(), "voc.bin");
  EXPECT_TRUE(back == vocabulary_);
  BowVector a, b;
  vocabulary_.transform(probe_, a);
  back.transform(probe_, b);
  EXPECT_EQ(a, b);
}

TEST_F(VocabularyFormat, TruncatedDataIsReportedAsTruncated) {
  for (std::size_t n : {std::size_t{0}, std::size_t{5}, std::size_t{20}, std::size_t{40},
                        bytes_.size() / 2, bytes_.size() - 1}) {
    const std::vector<std::uint8_t> cut(bytes_.begin(), bytes_.begin() + static_cast<long>(n));
    const std::string e = errorOf(cut);
    EXPECT_EQ(e.rfind("voc.bin: ", 0), 0u) << e;
    if (n >= 8) {
      EXPECT_NE(e.find("truncated"), std::string::npos) << n << ": " << e;
    } else {
      EXPECT_NE(e.find("not an ldsm vocabulary"), std::string::npos) << e;
    }
  }
}

TEST_F(VocabularyFormat, EverySingleBitFlipIsDetected) {
  // Every byte position (one flipped bit each) must be rejected: header fields by their checks,
  // anything else by the checksum.
  for (std::size_t i = 0; i < bytes_.size(); ++i) {
    std::vector<std::uint8_t> b = bytes_;
    b[i] ^= static_cast<std::uint8_t>(1u << (i % 8));
    EXPECT_NE(errorOf(b), "no error") << "byte " << i;
  }
  std::vector<std::uint8_t> b = bytes_;
  b[bytes_.size() / 2] ^= 0x10;
  EXPECT_NE(errorOf(b).find("checksum mismatch"), std::string::npos);
}

TEST_F(VocabularyFormat, HeaderErrorsNameTheProblem) {
  std::vector<std::uint8_t> b = bytes_;
  b[0] = 'X';
  EXPECT_NE(errorOf(b).find("not an ldsm vocabulary"), std::string::npos);
  b = bytes_;
  putU32(b, 8, 2);
  EXPECT_NE(errorOf(b).find("unsupported vocabulary format version 2"), std::string::npos);
  b = bytes_;
  b.push_back(0);
  EXPECT_NE(errorOf(b).find("unexpected bytes"), std::string::npos);
  b = bytes_;
  putU32(b, 12, 1);
  resign(b);
  EXPECT_NE(errorOf(b).find("branching"), std::string::npos);
}

TEST_F(VocabularyFormat, InconsistentTreesAreRejectedEvenWithAValidChecksum) {
  const std::size_t child_counts = 32;
  // Root with more children than the branching.
  std::vector<std::uint8_t> b = bytes_;
  b[child_counts] = 9;
  resign(b);
  EXPECT_NE(errorOf(b).find("children"), std::string::npos) << errorOf(b);
  // A leaf turned into an inner node: children beyond the table / leaf count mismatch.
  b = bytes_;
  b[child_counts + vocabulary_.nodeCount() - 1] = 2;
  resign(b);
  EXPECT_NE(errorOf(b).find("corrupt vocabulary"), std::string::npos) << errorOf(b);
  // A negative (NaN) word weight.
  b = bytes_;
  const std::size_t weights = 32 + vocabulary_.nodeCount() + 32 * (vocabulary_.nodeCount() - 1);
  putU32(b, weights, 0x7FC00000u);
  resign(b);
  EXPECT_NE(errorOf(b).find("weight of word 0"), std::string::npos) << errorOf(b);
  // Word count disagreeing with the leaves.
  b = bytes_;
  putU32(b, 24, static_cast<std::uint32_t>(vocabulary_.wordCount() - 1));
  b.erase(b.end() - 12, b.end() - 8);
  resign(b);
  EXPECT_NE(errorOf(b).find("leaves"), std::string::npos) << errorOf(b);
}

}  // namespace
}  // namespace ldsm::loop
