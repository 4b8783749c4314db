// The seed corpus of the map_file fuzz target (tests/fuzz/corpus/map_file) is generated here:
// tiny valid maps and broken variants of them. The test checks that the committed seeds have the
// layout the generator makes now and still decode (or fail) as they did with this format
// version; run it with LDSM_WRITE_MAP_SEEDS=<folder> to write them again (after a format change).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "ldsm/error.h"
#include "map_file_bytes.h"
#include "mapfile/map_codec.h"
#include "synthetic_map.h"
#include "test_paths.h"

namespace ldsm {
namespace {

using test::Bytes;

struct Seed {
  std::string name;
  Bytes bytes;
  bool valid;
};

Bytes tinyMap(int keyframes, int points, int corners, std::size_t vocabulary, std::uint64_t seed) {
  test::SyntheticMapSize size;
  size.keyframes = keyframes;
  size.points_per_keyframe = points;
  size.corners_per_keyframe = corners;
  size.links_per_keyframe = 2;
  size.loop_edges = 1;
  size.vocabulary_bytes = vocabulary;
  return encodeMap(test::syntheticMap(size, seed));
}

std::vector<Seed> seeds() {
  std::vector<Seed> out;
  MapData empty;
  empty.calibration.camera = PinholeIntrinsics{300, 300, 160, 120, 320, 240};
  out.push_back({"valid-empty.ldsmmap", encodeMap(empty), true});
  out.push_back({"valid-one-keyframe.ldsmmap", tinyMap(1, 1, 1, 0, 2), true});
  const Bytes three = tinyMap(3, 2, 2, 8, 3);
  out.push_back({"valid-three-keyframes.ldsmmap", three, true});
  out.push_back({"valid-six-keyframes.ldsmmap", tinyMap(6, 3, 2, 16, 4), true});
  auto split = test::splitSections(three);
  split.push_back({mapfile::tagOf("NEXT"), Bytes{1, 2, 3, 4}});
  out.push_back({"valid-unknown-section.ldsmmap", test::fileOf(split), true});
  // An earlier build's file: no calibration refinement section.
  split = test::splitSections(three);
  split.erase(std::remove_if(split.begin(), split.end(),
                             [](const auto& s) { return s.first == mapfile::kRefinementTag; }),
              split.end());
  out.push_back({"valid-without-refinement.ldsmmap", test::fileOf(split), true});

  out.push_back({"truncated-header.ldsmmap", Bytes(three.begin(), three.begin() + 14), false});
  out.push_back({"truncated-table.ldsmmap", Bytes(three.begin(), three.begin() + 100), false});
  out.push_back({"truncated-data.ldsmmap",
                 Bytes(three.begin(), three.begin() + static_cast<std::ptrdiff_t>(
                                                          three.size() * 2 / 3)),
                 false});
  Bytes flipped = three;
  flipped[test::sectionOffset(three, mapfile::kKeyframeDataTag) + 30] ^= 0x04;
  out.push_back({"corrupt-checksum.ldsmmap", flipped, false});
  Bytes forged = three;  // a NaN pose with checksums that match
  test::poke<double>(forged, test::sectionOffset(three, mapfile::kKeyframesTag) + 4 + 24,
                     std::numeric_limits<double>::quiet_NaN());
  test::refreshChecksums(forged);
  out.push_back({"forged-nan-pose.ldsmmap", forged, false});
  Bytes refinement = three;  // a focal correction of a factor e^2, checksums matching
  test::poke<double>(refinement, test::sectionOffset(three, mapfile::kRefinementTag), 2.0);
  test::refreshChecksums(refinement);
  out.push_back({"forged-refinement.ldsmmap", refinement, false});
  Bytes counts = three;
  test::poke<std::uint32_t>(counts, test::sectionOffset(three, mapfile::kKeyframeDataTag) + 4 + 121,
                            0x10000000u);
  test::refreshChecksums(counts);
  out.push_back({"forged-point-count.ldsmmap", counts, false});
  Bytes newer = three;
  test::poke<std::uint32_t>(newer, 8, 2);
  out.push_back({"newer-version.ldsmmap", newer, false});
  return out;
}

/// The committed seed has the generated one's layout: the same size, and the same header and
/// section table (magic, version, section tags, offsets and sizes) apart from the checksums. The
/// floating-point contents are not compared: the generator's poses go through libm's sin and cos
/// and Eigen's products, whose last bits differ by machine (fused multiply-adds on AArch64, the
/// FMA variants glibc picks on x86-64 processors that have them).
void expectSameLayout(const Bytes& committed, const Bytes& generated, const std::string& name) {
  ASSERT_EQ(committed.size(), generated.size()) << name;
  const std::size_t table_end =
      generated.size() < 16 ? generated.size()
                            : std::min(generated.size(),
                                       mapfile::layoutBytes(mapfile::loadU32(generated.data() + 12)));
  for (std::size_t i = 0; i < table_end; ++i) {
    const bool header_checksum = i >= 16 && i < 20;
    const bool entry_checksum = i >= mapfile::kHeaderBytes &&
                                (i - mapfile::kHeaderBytes) % mapfile::kTableEntryBytes >= 4 &&
                                (i - mapfile::kHeaderBytes) % mapfile::kTableEntryBytes < 8;
    if (header_checksum || entry_checksum) continue;
    ASSERT_EQ(committed[i], generated[i]) << name << ": byte " << i << " of the header and table";
  }
}

TEST(MapFuzzSeeds, TheCommittedSeedsHaveTheGeneratedLayout) {
  const std::string corpus = std::string(LDSM_SOURCE_DIR) + "/tests/fuzz/corpus/map_file";
  if (const char* dir = std::getenv("LDSM_WRITE_MAP_SEEDS")) {
    for (const Seed& s : seeds())
      std::ofstream(std::string(dir) + "/" + s.name, std::ios::binary)
          .write(reinterpret_cast<const char*>(s.bytes.data()),
                 static_cast<std::streamsize>(s.bytes.size()));
  }
  for (const Seed& s : seeds()) {
    const std::string text = test::readFile(corpus + "/" + s.name);
    const Bytes file(text.begin(), text.end());
    SCOPED_TRACE(s.name + " differs from the generator: LDSM_WRITE_MAP_SEEDS=" + corpus +
                 " test_mapfile --gtest_filter=MapFuzzSeeds.*");
    expectSameLayout(file, s.bytes, s.name);
    for (const Bytes* bytes : {&file, &s.bytes}) {
      if (s.valid) {
        EXPECT_NO_THROW(decodeMap(bytes->data(), bytes->size(), s.name)) << s.name;
      } else {
        EXPECT_THROW(decodeMap(bytes->data(), bytes->size(), s.name), InputError) << s.name;
      }
    }
  }
}

}  // namespace
}  // namespace ldsm
