// What a saved map file holds, for tools (`ldsm map info`): counts, extent, calibration and the
// bytes of each section, read from the file's bytes with every check of the loader
// (docs/map-file.md). Core does no file I/O: ldsm/drivers/map_file_io.h reads the file.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ldsm/camera/calibration.h"

namespace ldsm {

struct MapFileSection {
  std::string tag;          ///< four letters: CALB, KFRM, KFDT, PNTS, COVI, GRPH, VOCB, ...
  std::uint64_t bytes = 0;  ///< the section's size in the file
};

struct MapFileSummary {
  std::uint32_t version = 0;        ///< format version of the file
  std::size_t keyframes = 0;        ///< keyframes with a pose
  std::size_t data_keyframes = 0;   ///< keyframes that keep points, corners and descriptors
  std::size_t culled_keyframes = 0;  ///< data keyframes kept as a pose only (redundant)
  std::size_t patch_points = 0;     ///< points of the data keyframes (direct alignment)
  std::size_t corners = 0;          ///< corners of the data keyframes
  std::size_t descriptors = 0;      ///< ORB descriptors of the data keyframes
  std::size_t points = 0;           ///< the map's point cloud
  std::size_t graph_edges = 0;      ///< pose-graph edges
  std::size_t covisibility_edges = 0;
  std::size_t vocabulary_bytes = 0;  ///< 0: the map has no vocabulary
  PinholeIntrinsics camera;          ///< the rectified camera the map was made with
  double radial_k = 0.0;
  /// The online refinement's correction the map was measured with: fx, fy times focal_scale,
  /// cx, cy shifted by these pixels (1, 0, 0: none).
  double focal_scale = 1.0, cx_shift = 0.0, cy_shift = 0.0;
  bool has_response = false;
  bool has_vignette = false;
  std::uint64_t photometric_hash = 0;
  /// Bounding box of the keyframe centres (map units); both zero without keyframes.
  std::array<double, 3> area_min{};
  std::array<double, 3> area_max{};
  std::uint64_t total_bytes = 0;
  std::vector<MapFileSection> sections;  ///< in the order of the file's table
};

/// Checks a map file's bytes as the loader does and describes them. Throws ldsm::InputError
/// "<where>: ..." naming the section and what is wrong (see docs/map-file.md).
MapFileSummary summarizeMap(const std::uint8_t* data, std::size_t size, const std::string& where);

/// The vocabulary stored in a map file (its serialised bytes, see ldsm/loop/vocabulary_builder.h's
/// inspectVocabulary; empty when the map has none), after the same checks as summarizeMap.
std::vector<std::uint8_t> mapFileVocabulary(const std::uint8_t* data, std::size_t size,
                                            const std::string& where);

}  // namespace ldsm
