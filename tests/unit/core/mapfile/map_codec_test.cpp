// The map file format (docs/map-file.md): round trips, determinism, forward compatibility.
#include "mapfile/map_codec.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "ldsm/error.h"
#include "map_file_bytes.h"
#include "mapfile/pose_codec.h"
#include "synthetic_map.h"

namespace ldsm {
namespace {

using test::Bytes;

TEST(MapCodec, RoundTripGivesTheSameMapAndTheSameBytes) {
  test::SyntheticMapSize size;
  size.keyframes = 30;
  size.data_every = 2;
  const MapData map = test::syntheticMap(size);
  const Bytes bytes = encodeMap(map);
  const MapData back = decodeMap(bytes.data(), bytes.size(), "map.ldsm");
  test::expectSameMap(map, back);
  EXPECT_EQ(encodeMap(back), bytes);
  // And encoding is a function of the map alone.
  EXPECT_EQ(encodeMap(map), bytes);
}

TEST(MapCodec, AnEmptyMapRoundTrips) {
  MapData map;
  map.calibration.camera = PinholeIntrinsics{300, 300, 160, 120, 320, 240};
  const Bytes bytes = encodeMap(map);
  const MapData back = decodeMap(bytes.data(), bytes.size(), "empty.ldsm");
  test::expectSameMap(map, back);
  EXPECT_EQ(encodeMap(back), bytes);
}

TEST(MapCodec, KeepsNanCornerDepthsAndEdgeCases) {
  test::SyntheticMapSize size;
  size.keyframes = 3;
  MapData map = test::syntheticMap(size);
  // Descriptors not yet computed, depths fewer than corners, extreme but valid values.
  map.data[0].descriptors.clear();
  map.data[1].corner_idepth.resize(2);
  map.data[1].corner_idepth[0] = -std::numeric_limits<float>::quiet_NaN();
  map.data[2].points[0].observations = 0x7FFFFFFF;
  map.data[2].points[0].is_corner = true;
  map.keyframes[1].frame_index = -5;
  map.keyframes[2].map = 3;
  map.vocabulary.clear();
  const Bytes bytes = encodeMap(map);
  const MapData back = decodeMap(bytes.data(), bytes.size(), "m");
  test::expectSameMap(map, back);
  EXPECT_EQ(encodeMap(back), bytes);
}

TEST(MapCodec, UnknownSectionsAreSkipped) {
  const MapData map = test::syntheticMap({});
  const Bytes bytes = encodeMap(map);
  auto sections = test::splitSections(bytes);
  // A newer writer's optional section, first and last.
  sections.insert(sections.begin(), {mapfile::tagOf("ZZZ1"), Bytes{1, 2, 3}});
  sections.push_back({mapfile::tagOf("ZZZ2"), Bytes(100, 7)});
  const Bytes extended = test::fileOf(sections);
  const MapData back = decodeMap(extended.data(), extended.size(), "newer.ldsm");
  test::expectSameMap(map, back);
  // Sections in another order read the same.
  auto shuffled = test::splitSections(bytes);
  std::reverse(shuffled.begin(), shuffled.end());
  const Bytes reordered = test::fileOf(shuffled);
  test::expectSameMap(map, decodeMap(reordered.data(), reordered.size(), "reordered.ldsm"));
}

TEST(MapCodec, TheRefinementRoundTripsAndAFileWithoutItReadsAsNone) {
  MapData map = test::syntheticMap({});
  map.calibration.focal_log_scale = 0.0487;
  map.calibration.cx_shift = -9.75;
  map.calibration.cy_shift = 1.0 / 3.0;
  const Bytes bytes = encodeMap(map);
  const MapData back = decodeMap(bytes.data(), bytes.size(), "refined.ldsm");
  test::expectSameMap(map, back);
  EXPECT_EQ(encodeMap(back), bytes);
  // An earlier build's file has no CALR: the same map, measured without a correction.
  auto sections = test::splitSections(bytes);
  sections.erase(std::remove_if(sections.begin(), sections.end(),
                                [](const auto& s) { return s.first == mapfile::kRefinementTag; }),
                 sections.end());
  ASSERT_EQ(sections.size(), 7u);
  const Bytes older = test::fileOf(sections);
  const MapData old = decodeMap(older.data(), older.size(), "older.ldsm");
  MapData expected = map;
  expected.calibration.focal_log_scale = 0.0;
  expected.calibration.cx_shift = 0.0;
  expected.calibration.cy_shift = 0.0;
  test::expectSameMap(expected, old);
}

TEST(MapCodec, TheFileStartsWithItsSignatureAndVersion) {
  const Bytes bytes = encodeMap(test::syntheticMap({}));
  ASSERT_GT(bytes.size(), 20u);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes.data()), 8),
            std::string("LDSMMAP\0", 8));
  EXPECT_EQ(mapfile::loadU32(bytes.data() + 8), 1u);
  EXPECT_EQ(mapfile::loadU32(bytes.data() + 12), 8u);
  const auto sections = test::sectionsOf(bytes);
  ASSERT_EQ(sections.size(), 8u);
  const char* order[] = {"CALB", "KFRM", "KFDT", "PNTS", "COVI", "GRPH", "VOCB", "CALR"};
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(mapfile::tagText(sections[i].tag), order[i]);
}

TEST(MapCodec, SizesPerRecordAreAsDocumented) {
  // docs/map-file.md's tables: a keyframe pose 88 bytes, a data keyframe 141 + 84 per point +
  // 44 per described corner + 65 per link, a cloud point 37, a covisibility edge 12, a graph edge
  // 465, the calibration 60, the calibration refinement 24.
  test::SyntheticMapSize size;
  size.keyframes = 5;
  size.points_per_keyframe = 10;
  size.corners_per_keyframe = 6;
  size.links_per_keyframe = 2;
  size.loop_edges = 0;
  size.vocabulary_bytes = 9;
  const MapData map = test::syntheticMap(size);
  const Bytes bytes = encodeMap(map);
  std::size_t links = 0;
  for (const auto& kf : map.data) links += kf.links.size();
  const auto sections = test::sectionsOf(bytes);
  EXPECT_EQ(sections[0].size, 60u);
  EXPECT_EQ(sections[1].size, 4u + 5 * 88);
  EXPECT_EQ(sections[2].size, 4u + 5 * (141 + 10 * 84 + 6 * 44) + links * 65);
  EXPECT_EQ(sections[3].size, 4u + 50 * 37);
  EXPECT_EQ(sections[4].size, 4u + 4 * 12);
  EXPECT_EQ(sections[5].size, 4u + 4 * 465);
  EXPECT_EQ(sections[6].size, 9u);
  EXPECT_EQ(sections[7].size, 24u);
  EXPECT_EQ(sections[0].offset, 20u + 8 * 24);
}

TEST(MapCodec, TheEncoderRefusesAMapTheDecoderWouldRefuse) {
  MapData map = test::syntheticMap({});
  map.data[1].points[3].idepth = std::numeric_limits<float>::quiet_NaN();
  try {
    encodeMap(map);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "map to save: section KFDT (keyframe data): keyframe 2: point 3: inverse depth "
                 "nan is not a finite positive number");
  }
  map = test::syntheticMap({});
  map.graph[0].to_id = 77;
  EXPECT_THROW(encodeMap(map), Error);
}

TEST(PoseCodec, CanonicalQuaternionsAreFixedPointsOfNormalising) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
    if (i % 3 == 0) q.coeffs() *= 1e-3;
    const Eigen::Quaterniond c = mapfile::canonicalQuaternion(q);
    ASSERT_EQ(SO3d(c).quaternion().coeffs(), c.coeffs()) << i;
    ASSERT_TRUE(c.coeffs().isApprox(q.normalized().coeffs(), 1e-15)) << i;
    ASSERT_EQ(mapfile::canonicalQuaternion(c).coeffs(), c.coeffs()) << i;
  }
}

}  // namespace
}  // namespace ldsm
