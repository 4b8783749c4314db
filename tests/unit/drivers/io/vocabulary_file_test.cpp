#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ldsm/drivers/vocabulary_file.h"
#include "ldsm/error.h"
#include "ldsm/loop/vocabulary_builder.h"
#include "loop/vocabulary.h"
#include "synthetic_descriptors.h"
#include "test_paths.h"

namespace ldsm {
namespace {

std::vector<std::uint8_t> smallVocabulary() {
  loop::SplitMix64 rng(12);
  std::vector<std::vector<OrbDescriptor>> images;
  for (int i = 0; i < 6; ++i) images.push_back(loop::test::randomDescriptors(80, rng));
  loop::VocabularyParams p;
  p.branching = 5;
  p.levels = 3;
  return loop::Vocabulary::train(images, p)->serialize();
}

std::string expectInputError(const std::string& path) {
  try {
    drivers::readVocabularyFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return {};
}

TEST(VocabularyFile, WriteThenReadRoundTrip) {
  const std::string dir = test::scratchDir("loop_bow_vocabulary_file");
  const std::vector<std::uint8_t> bytes = smallVocabulary();
  const std::string path = dir + "/voc.ldsmvoc";
  drivers::writeVocabularyFile(path, bytes);
  const drivers::VocabularyFile f = drivers::readVocabularyFile(path);
  EXPECT_EQ(f.bytes, bytes);
  EXPECT_EQ(f.summary.branching, 5);
  EXPECT_EQ(f.summary.levels, 3);
  EXPECT_EQ(f.summary.training_images, 6u);
  const loop::Vocabulary v = loop::Vocabulary::deserialize(f.bytes.data(), f.bytes.size(), path);
  EXPECT_EQ(f.summary.words, v.wordCount());
  EXPECT_EQ(f.summary.nodes, v.nodeCount());
}

TEST(VocabularyFile, BadFilesNameThePathAndTheProblem) {
  const std::string dir = test::scratchDir("loop_bow_vocabulary_bad");
  const std::vector<std::uint8_t> bytes = smallVocabulary();
  auto write = [&](const std::string& name, const std::vector<std::uint8_t>& b) {
    std::ofstream(dir + "/" + name, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    return dir + "/" + name;
  };
  std::string e = expectInputError(dir + "/missing.voc");
  EXPECT_NE(e.find(dir + "/missing.voc"), std::string::npos) << e;
  EXPECT_NE(e.find("no such file"), std::string::npos) << e;

  const std::string truncated = write("truncated.voc", {bytes.begin(), bytes.end() - 100});
  e = expectInputError(truncated);
  EXPECT_EQ(e.rfind(truncated + ": truncated vocabulary", 0), 0u) << e;

  std::vector<std::uint8_t> flipped = bytes;
  flipped[flipped.size() / 3] ^= 4;
  const std::string corrupt = write("corrupt.voc", flipped);
  e = expectInputError(corrupt);
  EXPECT_EQ(e.rfind(corrupt + ": corrupt vocabulary: checksum mismatch", 0), 0u) << e;

  const std::string text = write("text.voc", {'h', 'e', 'l', 'l', 'o', '\n', 0, 0, 0, 0});
  e = expectInputError(text);
  EXPECT_NE(e.find("not an ldsm vocabulary"), std::string::npos) << e;

  const std::string empty = write("empty.voc", {});
  e = expectInputError(empty);
  EXPECT_NE(e.find("not an ldsm vocabulary"), std::string::npos) << e;

  e = expectInputError(dir);
  EXPECT_NE(e.find("folder"), std::string::npos) << e;
}

TEST(VocabularyFile, InvalidBytesAreNeverWritten) {
  const std::string dir = test::scratchDir("loop_bow_vocabulary_write");
  std::vector<std::uint8_t> bytes = smallVocabulary();
  bytes.resize(bytes.size() - 1);
  EXPECT_THROW(drivers::writeVocabularyFile(dir + "/x.voc", bytes), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.voc"));
  EXPECT_THROW(drivers::writeVocabularyFile(dir + "/no/such/dir/x.voc", smallVocabulary()), Error);
}

}  // namespace
}  // namespace ldsm
