// Bad map files (issue 17): each is an InputError naming the file, the section and what is
// wrong; never a crash, never a silently wrong map.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "ldsm/error.h"
#include "map_file_bytes.h"
#include "mapfile/map_codec.h"
#include "synthetic_map.h"

namespace ldsm {
namespace {

using test::Bytes;
namespace mf = mapfile;

const char* kWhere = "/maps/office.ldsm";

/// The message decodeMap throws (fails the test when it accepts the bytes).
std::string errorOf(const Bytes& bytes) {
  try {
    decodeMap(bytes.data(), bytes.size(), kWhere);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

#define EXPECT_MESSAGE(bytes, text)                                           \
  do {                                                                        \
    const std::string message_ = errorOf(bytes);                              \
    EXPECT_EQ(message_.rfind(std::string(kWhere) + ": ", 0), 0u) << message_; \
    EXPECT_NE(message_.find(text), std::string::npos) << message_;            \
  } while (0)

Bytes goodFile() {
  test::SyntheticMapSize size;
  size.keyframes = 8;
  return encodeMap(test::syntheticMap(size));
}

TEST(MapCodecBadInput, ForeignFiles) {
  EXPECT_MESSAGE(Bytes{}, "not an ldsm map");
  EXPECT_MESSAGE(Bytes(3, 'L'), "not an ldsm map");
  const std::string png = "\x89PNG\r\n\x1a\n rest of an image";
  EXPECT_MESSAGE(Bytes(png.begin(), png.end()), "not an ldsm map");
  Bytes vocabulary = goodFile();
  std::memcpy(vocabulary.data(), "LDSMVOCB", 8);
  EXPECT_MESSAGE(vocabulary, "not an ldsm map (no \"LDSMMAP\" signature)");
  EXPECT_THROW(decodeMap(nullptr, 0, kWhere), InputError);
}

TEST(MapCodecBadInput, ANewerVersionNamesBothVersions) {
  Bytes bytes = goodFile();
  test::poke<std::uint32_t>(bytes, 8, 2);
  EXPECT_EQ(errorOf(bytes), std::string(kWhere) +
                                ": format version 2 is newer than this build reads (1): it was "
                                "written by a newer ldsm");
  test::poke<std::uint32_t>(bytes, 8, 0);
  EXPECT_MESSAGE(bytes, "format version 0");
}

TEST(MapCodecBadInput, TruncatedAnywhere) {
  const Bytes good = goodFile();
  const auto sections = test::sectionsOf(good);
  std::vector<std::size_t> cuts = {8, 12, 19, 20, 21, 43, 20 + 8 * 24 - 1};
  for (const auto& s : sections) {
    cuts.push_back(static_cast<std::size_t>(s.offset + s.size / 2));
    cuts.push_back(static_cast<std::size_t>(s.offset + s.size) - 1);
  }
  cuts.push_back(good.size() - 1);
  for (std::size_t cut : cuts) {
    const Bytes bytes(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut));
    const std::string message = errorOf(bytes);
    EXPECT_NE(message.find("truncated"), std::string::npos) << cut << ": " << message;
  }
  // Cut inside a section: the section is named.
  const auto& kfdt = sections[2];
  const Bytes cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(kfdt.offset + 10));
  EXPECT_MESSAGE(cut, "section KFDT (keyframe data): bytes ");
  EXPECT_MESSAGE(cut, "lie outside the file");
}

TEST(MapCodecBadInput, AFlippedByteInEachSectionIsAChecksumError) {
  const Bytes good = goodFile();
  for (const auto& s : test::sectionsOf(good)) {
    if (s.size == 0) continue;
    for (const std::uint64_t at : {s.offset, s.offset + s.size / 2, s.offset + s.size - 1}) {
      Bytes bytes = good;
      bytes[static_cast<std::size_t>(at)] ^= 0x10;
      EXPECT_EQ(errorOf(bytes), std::string(kWhere) + ": " + mf::sectionLabel(s.tag) +
                                    ": checksum mismatch (the file is corrupt)");
    }
  }
}

TEST(MapCodecBadInput, AFlippedByteInTheHeaderOrTable) {
  const Bytes good = goodFile();
  for (std::size_t at : {12u, 16u, 20u, 25u, 40u, 20u + 8 * 24 - 1}) {
    Bytes bytes = good;
    bytes[at] ^= 0x01;
    const std::string message = errorOf(bytes);
    EXPECT_NE(message.find("corrupt header"), std::string::npos) << at << ": " << message;
  }
}

TEST(MapCodecBadInput, ATableEntryPointingOutsideTheFile) {
  const Bytes good = goodFile();
  const std::size_t entry = 20 + 3 * 24;  // PNTS
  Bytes bytes = good;
  test::poke<std::uint64_t>(bytes, entry + 8, good.size() + 100);
  test::refreshHeaderChecksum(bytes);
  EXPECT_MESSAGE(bytes, "section PNTS (points): bytes ");
  EXPECT_MESSAGE(bytes, "lie outside the file");
  bytes = good;
  test::poke<std::uint64_t>(bytes, entry + 16, std::numeric_limits<std::uint64_t>::max());
  test::refreshHeaderChecksum(bytes);
  EXPECT_MESSAGE(bytes, "section PNTS (points): bytes ");
  bytes = good;
  test::poke<std::uint64_t>(bytes, entry + 8, 4);  // into the header
  test::refreshHeaderChecksum(bytes);
  EXPECT_MESSAGE(bytes, "lie outside the file");
}

TEST(MapCodecBadInput, SectionsMustTileTheFile) {
  Bytes good = goodFile();
  Bytes trailing = good;
  trailing.push_back(0);
  EXPECT_MESSAGE(trailing, "1 unexpected bytes after the last section");
  // Two sections over the same bytes.
  Bytes overlap = good;
  const auto sections = test::sectionsOf(good);
  test::poke<std::uint64_t>(overlap, 20 + 4 * 24 + 8, sections[3].offset);
  test::refreshHeaderChecksum(overlap);
  EXPECT_MESSAGE(overlap, "overlaps the section before it");
  // A tag twice.
  auto split = test::splitSections(good);
  split.push_back(split[0]);
  EXPECT_MESSAGE(test::fileOf(split), "section CALB (calibration): appears twice in the table");
}

TEST(MapCodecBadInput, AbsurdCountsAreRefusedBeforeAllocating) {
  const Bytes good = goodFile();
  const std::size_t kfdt = test::sectionOffset(good, mf::kKeyframeDataTag);
  Bytes bytes = good;
  test::poke<std::uint32_t>(bytes, kfdt, 0xFFFFFFFFu);
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section KFDT (keyframe data): 4294967295 data keyframes need at least");
  // The point count of the first data keyframe.
  bytes = good;
  test::poke<std::uint32_t>(bytes, kfdt + 4 + 121, 0x40000000u);
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section KFDT (keyframe data): keyframe 0: 1073741824 points need");
  for (std::uint32_t tag :
       {mf::kKeyframesTag, mf::kPointsTag, mf::kCovisibilityTag, mf::kGraphTag}) {
    bytes = good;
    test::poke<std::uint32_t>(bytes, test::sectionOffset(good, tag), 0x7FFFFFFFu);
    test::refreshChecksums(bytes);
    EXPECT_MESSAGE(bytes, mf::sectionLabel(tag) + ": 2147483647 ");
  }
}

TEST(MapCodecBadInput, NanInAPoseNamesTheSectionAndTheKeyframe) {
  const Bytes good = goodFile();
  const std::size_t kfrm = test::sectionOffset(good, mf::kKeyframesTag);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Bytes bytes = good;
  // Second keyframe (id 2): count, then 88 bytes per keyframe; the quaternion after 24 bytes.
  test::poke<double>(bytes, kfrm + 4 + 88 + 24, nan);
  test::refreshChecksums(bytes);
  EXPECT_EQ(errorOf(bytes), std::string(kWhere) +
                                ": section KFRM (keyframes): keyframe 2: pose: rotation is not "
                                "finite");
  bytes = good;
  test::poke<double>(bytes, kfrm + 4 + 88 + 24 + 32 + 8, std::numeric_limits<double>::infinity());
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section KFRM (keyframes): keyframe 2: pose: translation is not finite");
  bytes = good;
  test::poke<double>(bytes, kfrm + 4 + 88 + 24, 0.9);  // no longer a unit quaternion
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "keyframe 2: pose: rotation is not a unit quaternion");
  bytes = good;
  test::poke<double>(bytes, kfrm + 4 + 16, nan);  // the first keyframe's timestamp
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section KFRM (keyframes): keyframe 0: timestamp nan is not finite");
  bytes = good;
  test::poke<double>(bytes, kfrm + 4 + 80, -1.0);  // the first keyframe's scale
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "keyframe 0: scale -1 is not a finite positive number");
}

TEST(MapCodecBadInput, NanInKeyframeData) {
  const Bytes good = goodFile();
  const std::size_t first = test::sectionOffset(good, mf::kKeyframeDataTag) + 4;
  Bytes bytes = good;
  // Point 0's inverse depth: after the 121-byte header and the point count, u and v.
  test::poke<float>(bytes, first + 121 + 4 + 8, std::numeric_limits<float>::quiet_NaN());
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section KFDT (keyframe data): keyframe 0: point 0: inverse depth nan");
  bytes = good;
  test::poke<double>(bytes, first + 4 + 8 + 8, 0.0);  // exposure
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section KFDT (keyframe data): keyframe 0: exposure 0 is not a finite");
  bytes = good;
  test::poke<std::uint8_t>(bytes, first + 120, 6);  // flags
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "keyframe 0: keyframe flags 6 have unknown bits");
}

TEST(MapCodecBadInput, APointPositionThatIsNoNumberOrBeyondFloat) {
  const Bytes good = goodFile();
  // Point 1's z: after the count, 37 bytes per point, then x and y.
  const std::size_t z = test::sectionOffset(good, mf::kPointsTag) + 4 + 37 + 16;
  Bytes bytes = good;
  test::poke<double>(bytes, z, std::numeric_limits<double>::quiet_NaN());
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section PNTS (points): point 1: position is not finite");
  bytes = good;
  test::poke<double>(bytes, z, -std::numeric_limits<double>::infinity());
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section PNTS (points): point 1: position is not finite");
  // Finite, but no float holds it: named as such, not as "not finite".
  bytes = good;
  test::poke<double>(bytes, z, 1e39);
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "point 1: coordinate 1e+39 is beyond the range the map holds points in");
  // The largest float is still a position.
  bytes = good;
  test::poke<double>(bytes, z, static_cast<double>(std::numeric_limits<float>::max()));
  test::refreshChecksums(bytes);
  EXPECT_NO_THROW(decodeMap(bytes.data(), bytes.size(), kWhere));
}

TEST(MapCodecBadInput, InconsistentIds) {
  const Bytes good = goodFile();
  const std::size_t kfdt = test::sectionOffset(good, mf::kKeyframeDataTag);
  Bytes bytes = good;
  test::poke<std::int32_t>(bytes, kfdt + 4, 5);  // the first data keyframe: id 0 -> 5 (odd)
  test::refreshChecksums(bytes);
  EXPECT_EQ(errorOf(bytes), std::string(kWhere) +
                                ": section KFDT (keyframe data): keyframe 5: not among the "
                                "keyframes");
  bytes = good;
  const std::size_t kfrm = test::sectionOffset(good, mf::kKeyframesTag);
  test::poke<std::int32_t>(bytes, kfrm + 4 + 88, 0);  // keyframe ids 0, 0, 4, ...
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section KFRM (keyframes): keyframe 0: ids not increasing");
  bytes = good;
  const std::size_t grph = test::sectionOffset(good, mf::kGraphTag);
  test::poke<std::int32_t>(bytes, grph + 4 + 4, 99);  // first edge 0 -> 99
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section GRPH (pose graph): edge 0 -> 99: keyframe 99 does not exist");
  bytes = good;
  test::poke<std::uint8_t>(bytes, grph + 4 + 8, 7);  // kind
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "edge 0 -> 2: kind 7 is none of");
  bytes = good;
  test::poke<double>(bytes, grph + 4 + 9 + 56, -2.0);  // Sim(3) scale
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section GRPH (pose graph): edge 0 -> 2: Sim(3): scale -2 is not");
  bytes = good;
  const std::size_t covi = test::sectionOffset(good, mf::kCovisibilityTag);
  test::poke<std::int32_t>(bytes, covi + 4, -3);
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section COVI (covisibility): edge -3 - 2: keyframe -3 does not exist");
  bytes = good;
  const std::size_t pnts = test::sectionOffset(good, mf::kPointsTag);
  test::poke<std::int32_t>(bytes, pnts + 4 + 28, 1);  // point 0's host
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section PNTS (points): point 0: host keyframe 1 does not exist");
  // A link to a keyframe that does not exist.
  MapData map = test::syntheticMap({});
  ASSERT_FALSE(map.data[3].links.empty());
  map.data[3].links[0].other = 1;
  EXPECT_THROW(encodeMap(map), Error);
}

TEST(MapCodecBadInput, AMissingRequiredSection) {
  const Bytes good = goodFile();
  auto split = test::splitSections(good);
  split.erase(split.begin() + 4);  // COVI
  EXPECT_EQ(errorOf(test::fileOf(split)),
            std::string(kWhere) + ": section COVI (covisibility): missing (required)");
  split = test::splitSections(good);
  split[6].first = mf::tagOf("VOCX");  // renamed: skipped as unknown, VOCB is missing
  EXPECT_MESSAGE(test::fileOf(split), "section VOCB (vocabulary): missing (required)");
}

TEST(MapCodecBadInput, ExtraBytesInASection) {
  auto split = test::splitSections(goodFile());
  split[0].second.push_back(0);
  EXPECT_MESSAGE(test::fileOf(split),
                 "section CALB (calibration): 1 unexpected bytes at the end of the section");
  split = test::splitSections(goodFile());
  split[0].second.pop_back();
  EXPECT_MESSAGE(test::fileOf(split), "section CALB (calibration): data ends early");
}

TEST(MapCodecBadInput, ABadCalibration) {
  const Bytes good = goodFile();
  Bytes bytes = good;
  test::poke<double>(bytes, test::sectionOffset(good, mf::kCalibrationTag) + 8, -458.0);
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section CALB (calibration): fx -458 is not a finite positive number");
  bytes = good;
  test::poke<std::int32_t>(bytes, test::sectionOffset(good, mf::kCalibrationTag), 0);
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes, "section CALB (calibration): image size 0x480 is not positive");
}

TEST(MapCodecBadInput, ABadCalibrationRefinement) {
  const Bytes good = goodFile();
  const std::size_t at = test::sectionOffset(good, mf::kRefinementTag);
  Bytes bytes = good;
  test::poke<double>(bytes, at, std::numeric_limits<double>::quiet_NaN());
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes,
                 "section CALR (calibration refinement): focal_log_scale nan is not in [-1, 1]");
  bytes = good;
  test::poke<double>(bytes, at + 16, -4000.0);
  test::refreshChecksums(bytes);
  EXPECT_MESSAGE(bytes,
                 "section CALR (calibration refinement): cy_shift -4000 is not within the image "
                 "height");
  auto split = test::splitSections(good);
  split[7].second.resize(16);
  EXPECT_MESSAGE(test::fileOf(split), "section CALR (calibration refinement): data ends early");
}

TEST(MapCodecBadInput, EveryPrefixAndEverySingleByteChangeIsRejectedCleanly) {
  test::SyntheticMapSize size;
  size.keyframes = 3;
  size.points_per_keyframe = 2;
  size.corners_per_keyframe = 2;
  size.vocabulary_bytes = 4;
  const Bytes good = encodeMap(test::syntheticMap(size));
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_THROW(decodeMap(good.data(), n, kWhere), InputError) << n;
  for (std::size_t at = 0; at < good.size(); ++at) {
    Bytes bytes = good;
    bytes[at] ^= 0x80;
    EXPECT_THROW(decodeMap(bytes.data(), bytes.size(), kWhere), InputError) << at;
  }
}

}  // namespace
}  // namespace ldsm
