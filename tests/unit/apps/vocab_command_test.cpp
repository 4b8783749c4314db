// `ldsm vocab train` / `ldsm vocab info` end to end, on a small folder of synthetic images.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/vocabulary_file.h"
#include "loop/binary_kmajority.h"
#include "test_paths.h"

namespace ldsm {
namespace {

#ifdef LDSM_EXE

/// Blocky random texture: plenty of corners.
ImageU8 texture(int w, int h, std::uint64_t seed) {
  loop::SplitMix64 rng(seed);
  ImageU8 img(w, h, 0);
  for (int by = 0; by < h; by += 8) {
    for (int bx = 0; bx < w; bx += 8) {
      const auto v = static_cast<std::uint8_t>(rng.below(256));
      for (int y = by; y < std::min(by + 8, h); ++y) {
        for (int x = bx; x < std::min(bx + 8, w); ++x) img(x, y) = v;
      }
    }
  }
  return img;
}

TEST(VocabCommand, TrainsWritesAndDescribesAVocabulary) {
  const std::string dir = test::scratchDir("loop_bow_vocab_cli");
  std::filesystem::create_directories(dir + "/a");
  std::filesystem::create_directories(dir + "/b");
  for (int i = 0; i < 4; ++i) {
    calib::writePng(dir + "/a/" + std::to_string(i) + ".png",
                    texture(160, 120, 10 + static_cast<std::uint64_t>(i)).view());
    calib::writePng(dir + "/b/" + std::to_string(i) + ".png",
                    texture(200, 150, 20 + static_cast<std::uint64_t>(i)).view());
  }
  const std::string out = dir + "/voc.bin";
  std::string log;
  const int rc = test::runCommand(std::string(LDSM_EXE) + " vocab train --images " + dir + "/a " +
                                      dir + "/b --out " + out + " --k 4 --levels 3 --features 200",
                                  &log);
  ASSERT_EQ(rc, 0) << log;
  EXPECT_NE(log.find("wrote " + out), std::string::npos) << log;
  const drivers::VocabularyFile f = drivers::readVocabularyFile(out);
  EXPECT_EQ(f.summary.branching, 4);
  EXPECT_EQ(f.summary.levels, 3);
  EXPECT_EQ(f.summary.training_images, 8u);
  EXPECT_GT(f.summary.words, 16u);
  EXPECT_LE(f.summary.words, 64u);

  ASSERT_EQ(test::runCommand(std::string(LDSM_EXE) + " vocab info " + out, &log), 0) << log;
  EXPECT_NE(log.find("branching 4, levels 3"), std::string::npos) << log;

  // The same input and seed give the same file.
  const std::string again = dir + "/again.bin";
  ASSERT_EQ(test::runCommand(std::string(LDSM_EXE) + " vocab train --images " + dir + "/a " + dir +
                                 "/b --out " + again + " --k 4 --levels 3 --features 200",
                             &log),
            0)
      << log;
  EXPECT_EQ(drivers::readVocabularyFile(again).bytes, f.bytes);
}

TEST(VocabCommand, BadInputFailsWithAClearMessage) {
  const std::string dir = test::scratchDir("loop_bow_vocab_cli_bad");
  std::string log;
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " vocab train --images " + dir +
                                 "/nowhere --out " + dir + "/v.bin",
                             &log),
            1);
  EXPECT_NE(log.find("ldsm: error: "), std::string::npos) << log;
  EXPECT_NE(log.find(dir + "/nowhere"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(dir + "/v.bin"));

  std::filesystem::create_directories(dir + "/flat");
  for (int i = 0; i < 3; ++i) {
    calib::writePng(dir + "/flat/" + std::to_string(i) + ".png", ImageU8(100, 80, 128).view());
  }
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " vocab train --images " + dir +
                                 "/flat --out " + dir + "/v.bin",
                             &log),
            1);
  EXPECT_NE(log.find("no features found"), std::string::npos) << log;

  const std::string junk = dir + "/junk.bin";
  calib::writePng(junk, ImageU8(10, 10, 1).view());
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " vocab info " + junk, &log), 1);
  EXPECT_NE(log.find(junk + ": not an ldsm vocabulary"), std::string::npos) << log;

  EXPECT_NE(test::runCommand(std::string(LDSM_EXE) + " vocab train --images " + dir +
                                 "/flat --out " + dir + "/v.bin --k 1",
                             &log),
            0);
}

#endif

}  // namespace
}  // namespace ldsm
