// `ldsm map info` end to end, on map files written here.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ldsm/drivers/map_file_io.h"
#include "loop/vocabulary.h"
#include "mapfile/map_codec.h"
#include "synthetic_descriptors.h"
#include "synthetic_map.h"
#include "test_paths.h"

namespace ldsm {
namespace {

#ifdef LDSM_EXE

std::vector<std::uint8_t> smallVocabulary() {
  loop::SplitMix64 rng(5);
  std::vector<std::vector<OrbDescriptor>> images;
  for (int i = 0; i < 4; ++i) images.push_back(loop::test::randomDescriptors(60, rng));
  loop::VocabularyParams p;
  p.branching = 4;
  p.levels = 2;
  return loop::Vocabulary::train(images, p)->serialize();
}

void expectLine(const std::string& log, const std::string& text) {
  EXPECT_NE(log.find(text), std::string::npos) << "no \"" << text << "\" in:\n" << log;
}

TEST(MapCommand, InfoPrintsWhatTheMapHolds) {
  const std::string dir = test::scratchDir("map_command_info");
  test::SyntheticMapSize size;
  size.keyframes = 20;
  size.data_every = 2;
  size.points_per_keyframe = 30;
  size.corners_per_keyframe = 10;
  MapData map = test::syntheticMap(size);
  map.vocabulary = smallVocabulary();
  const std::vector<std::uint8_t> bytes = encodeMap(map);
  const std::string path = dir + "/office.ldsmmap";
  drivers::writeMapFile(path, bytes);

  std::string log;
  ASSERT_EQ(test::runCommand(std::string(LDSM_EXE) + " map info " + path, &log), 0) << log;
  expectLine(log, path + ": ldsm map, format version 1, checked in ");
  expectLine(log, "keyframes:    20 (10 with points and features, 1 of them culled)");
  expectLine(log, "points:       300 in the cloud; 300 patch points, 100 corners, 100 descriptors");
  expectLine(log, "area:         8.00 x 3.");
  expectLine(log, "calibration:  752x480, fx 458.500 fy 457.250 cx 367.200 cy 248.400, radial k "
                  "-0.0125");
  expectLine(log, "photometric:  response and vignette (hash 1234567890abcdef)");
  const loop::Vocabulary v =
      loop::Vocabulary::deserialize(map.vocabulary.data(), map.vocabulary.size(), "v");
  expectLine(log, "vocabulary:   " + std::to_string(v.wordCount()) +
                      " words (branching 4, levels 2)");
  expectLine(log, "graph:        " + std::to_string(map.graph.size()) + " pose-graph edges, " +
                      std::to_string(map.covisibility.size()) + " covisibility edges");
  expectLine(log, "size:         " + std::to_string(bytes.size()) + " bytes");
  expectLine(log, "KiB per keyframe with data");
  expectLine(log, "sections:     CALB 60 KFRM 1764 KFDT ");
}

TEST(MapCommand, ABadFileFailsNamingTheFileAndTheSection) {
  const std::string dir = test::scratchDir("map_command_bad");
  std::string log;
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " map info " + dir + "/none.ldsmmap", &log),
            1);
  expectLine(log, "ldsm: error: " + dir + "/none.ldsmmap: cannot open (no such file)");

  std::vector<std::uint8_t> bytes = encodeMap(test::syntheticMap({}));
  bytes.resize(bytes.size() - 30);  // all of the last section (CALR, 24 bytes) and some of VOCB
  const std::string cut = dir + "/cut.ldsmmap";
  drivers::writeMapFile(cut, bytes);
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " map info " + cut, &log), 1);
  expectLine(log, "ldsm: error: " + cut + ": section VOCB (vocabulary): bytes ");

  // Sound as a map, but its vocabulary is not one.
  const std::string junk = dir + "/junk_vocabulary.ldsmmap";
  drivers::writeMapFile(junk, encodeMap(test::syntheticMap({})));
  EXPECT_EQ(test::runCommand(std::string(LDSM_EXE) + " map info " + junk, &log), 1);
  expectLine(log, "ldsm: error: " + junk + ": section VOCB (vocabulary): not an ldsm vocabulary");

  EXPECT_NE(test::runCommand(std::string(LDSM_EXE) + " map info", &log), 0);
}

#endif

}  // namespace
}  // namespace ldsm
