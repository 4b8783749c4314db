// Helpers of the map file tests: finding a section in a file's bytes, patching values and
// recomputing the checksums (to reach the checks behind them), comparing maps.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "mapfile/byte_order.h"
#include "mapfile/crc32.h"
#include "mapfile/map_data.h"
#include "mapfile/map_format.h"
#include "mapfile/map_layout.h"

namespace ldsm::test {

using Bytes = std::vector<std::uint8_t>;

/// The table entries of a (sound) file.
inline std::vector<mapfile::SectionEntry> sectionsOf(const Bytes& file) {
  std::vector<mapfile::SectionEntry> out;
  const std::uint32_t n = mapfile::loadU32(file.data() + 12);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint8_t* e = file.data() + mapfile::kHeaderBytes + i * mapfile::kTableEntryBytes;
    out.push_back({mapfile::loadU32(e), mapfile::loadU32(e + 4), mapfile::loadU64(e + 8),
                   mapfile::loadU64(e + 16)});
  }
  return out;
}

/// Byte offset of a section in the file.
inline std::size_t sectionOffset(const Bytes& file, std::uint32_t tag) {
  for (const auto& s : sectionsOf(file))
    if (s.tag == tag) return static_cast<std::size_t>(s.offset);
  ADD_FAILURE() << "no section " << mapfile::tagText(tag);
  return 0;
}

/// Recomputes the checksum of the header and table only (the table may point anywhere).
inline void refreshHeaderChecksum(Bytes& file) {
  const std::size_t n = mapfile::loadU32(file.data() + 12);
  const std::uint32_t c = mapfile::crc32(file.data(), 16);
  mapfile::storeU32(file.data() + 16, mapfile::crc32(file.data() + mapfile::kHeaderBytes,
                                                     n * mapfile::kTableEntryBytes, c));
}

/// Recomputes every checksum, as a writer of a forged file would.
inline void refreshChecksums(Bytes& file) {
  mapfile::writeMapLayout(file, sectionsOf(file));
}

/// A file of the given sections, in order (tags need not be the known ones).
inline Bytes fileOf(const std::vector<std::pair<std::uint32_t, Bytes>>& sections) {
  Bytes file(mapfile::layoutBytes(sections.size()));
  std::vector<mapfile::SectionEntry> entries;
  for (const auto& [tag, bytes] : sections) {
    entries.push_back({tag, 0, file.size(), bytes.size()});
    file.insert(file.end(), bytes.begin(), bytes.end());
  }
  mapfile::writeMapLayout(file, entries);
  return file;
}

/// The sections of a file as (tag, bytes).
inline std::vector<std::pair<std::uint32_t, Bytes>> splitSections(const Bytes& file) {
  std::vector<std::pair<std::uint32_t, Bytes>> out;
  for (const auto& s : sectionsOf(file)) {
    const auto begin = file.begin() + static_cast<std::ptrdiff_t>(s.offset);
    out.emplace_back(s.tag, Bytes(begin, begin + static_cast<std::ptrdiff_t>(s.size)));
  }
  return out;
}

template <typename T>
void poke(Bytes& file, std::size_t at, T value) {
  ASSERT_LE(at + sizeof(T), file.size());
  std::memcpy(file.data() + at, &value, sizeof(T));  // tests run on little-endian hosts only
}

inline bool sameBits(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}

inline void expectSamePose(const SE3d& a, const SE3d& b) {
  EXPECT_TRUE(a.quaternion().coeffs().isApprox(b.quaternion().coeffs(), 1e-15));
  EXPECT_EQ(a.translation(), b.translation());
}

/// Field by field: everything exact (NaN bits included) but rotations (to the last bits: the
/// file holds the nearest quaternion that normalising leaves unchanged).
inline void expectSameMap(const MapData& a, const MapData& b) {
  EXPECT_EQ(a.calibration.camera.width, b.calibration.camera.width);
  EXPECT_EQ(a.calibration.camera.height, b.calibration.camera.height);
  EXPECT_EQ(a.calibration.camera.fx, b.calibration.camera.fx);
  EXPECT_EQ(a.calibration.camera.fy, b.calibration.camera.fy);
  EXPECT_EQ(a.calibration.camera.cx, b.calibration.camera.cx);
  EXPECT_EQ(a.calibration.camera.cy, b.calibration.camera.cy);
  EXPECT_EQ(a.calibration.radial_k, b.calibration.radial_k);
  EXPECT_EQ(a.calibration.focal_log_scale, b.calibration.focal_log_scale);
  EXPECT_EQ(a.calibration.cx_shift, b.calibration.cx_shift);
  EXPECT_EQ(a.calibration.cy_shift, b.calibration.cy_shift);
  EXPECT_EQ(a.calibration.has_response, b.calibration.has_response);
  EXPECT_EQ(a.calibration.has_vignette, b.calibration.has_vignette);
  EXPECT_EQ(a.calibration.photometric_hash, b.calibration.photometric_hash);
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (std::size_t i = 0; i < a.keyframes.size(); ++i) {
    const KeyframeRecord& x = a.keyframes[i];
    const KeyframeRecord& y = b.keyframes[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.frame_index, y.frame_index);
    EXPECT_EQ(x.timestamp, y.timestamp);
    expectSamePose(x.T_w_c, y.T_w_c);
    EXPECT_EQ(x.scale, y.scale);
    EXPECT_EQ(x.map, y.map);
  }
  ASSERT_EQ(a.data.size(), b.data.size());
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const MarginalizedKeyframe& x = a.data[i];
    const MarginalizedKeyframe& y = b.data[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.frame_index, y.frame_index);
    EXPECT_EQ(x.timestamp, y.timestamp);
    EXPECT_EQ(x.exposure, y.exposure);
    EXPECT_EQ(x.aff.a, y.aff.a);
    EXPECT_EQ(x.aff.b, y.aff.b);
    expectSamePose(x.T_w_c, y.T_w_c);
    EXPECT_EQ(x.radial_k, y.radial_k);
    EXPECT_EQ(x.map_points_in_view, y.map_points_in_view);
    EXPECT_EQ(x.path_length, y.path_length);
    EXPECT_EQ(x.newest_when_left, y.newest_when_left);
    EXPECT_EQ(x.culled, y.culled);
    ASSERT_EQ(x.points.size(), y.points.size());
    for (std::size_t j = 0; j < x.points.size(); ++j) {
      const PatchPoint& p = x.points[j];
      const PatchPoint& q = y.points[j];
      EXPECT_EQ(p.u, q.u);
      EXPECT_EQ(p.v, q.v);
      EXPECT_EQ(p.idepth, q.idepth);
      EXPECT_EQ(p.idepth_hessian, q.idepth_hessian);
      for (int k = 0; k < kPatternSize; ++k) {
        EXPECT_EQ(p.colors[k], q.colors[k]);
        EXPECT_EQ(p.grad_weights[k], q.grad_weights[k]);
      }
      EXPECT_EQ(p.observations, q.observations);
      EXPECT_EQ(p.is_corner, q.is_corner);
    }
    EXPECT_EQ(x.corners, y.corners);
    ASSERT_EQ(x.corner_idepth.size(), y.corner_idepth.size());
    for (std::size_t j = 0; j < x.corner_idepth.size(); ++j)
      EXPECT_TRUE(sameBits(x.corner_idepth[j], y.corner_idepth[j])) << j;
    EXPECT_EQ(x.descriptors, y.descriptors);
    ASSERT_EQ(x.links.size(), y.links.size());
    for (std::size_t j = 0; j < x.links.size(); ++j) {
      EXPECT_EQ(x.links[j].other, y.links[j].other);
      expectSamePose(x.links[j].T_this_other, y.links[j].T_this_other);
      EXPECT_EQ(x.links[j].shared_points, y.links[j].shared_points);
      EXPECT_EQ(x.links[j].map_keyframe, y.links[j].map_keyframe);
    }
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t j = 0; j < a.points.size(); ++j) {
    EXPECT_EQ(a.points[j].position, b.points[j].position);
    EXPECT_EQ(a.points[j].intensity, b.points[j].intensity);
    EXPECT_EQ(a.points[j].is_corner, b.points[j].is_corner);
    EXPECT_EQ(a.points[j].map, b.points[j].map);
    EXPECT_EQ(a.points[j].host, b.points[j].host);
  }
  ASSERT_EQ(a.covisibility.size(), b.covisibility.size());
  for (std::size_t j = 0; j < a.covisibility.size(); ++j) {
    EXPECT_EQ(a.covisibility[j].a, b.covisibility[j].a);
    EXPECT_EQ(a.covisibility[j].b, b.covisibility[j].b);
    EXPECT_EQ(a.covisibility[j].weight, b.covisibility[j].weight);
  }
  ASSERT_EQ(a.graph.size(), b.graph.size());
  for (std::size_t j = 0; j < a.graph.size(); ++j) {
    const MapGraphEdge& x = a.graph[j];
    const MapGraphEdge& y = b.graph[j];
    EXPECT_EQ(x.from_id, y.from_id);
    EXPECT_EQ(x.to_id, y.to_id);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_TRUE(
        x.S_from_to.quaternion().coeffs().isApprox(y.S_from_to.quaternion().coeffs(), 1e-15));
    EXPECT_EQ(x.S_from_to.translation(), y.S_from_to.translation());
    EXPECT_EQ(x.S_from_to.scale(), y.S_from_to.scale());
    EXPECT_EQ(x.information, y.information);
  }
  EXPECT_EQ(a.vocabulary, b.vocabulary);
}

}  // namespace ldsm::test
