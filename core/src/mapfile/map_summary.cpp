// ldsm/map_file.h: what a map file holds.
#include <algorithm>
#include <cmath>

#include "ldsm/map_file.h"
#include "mapfile/map_codec.h"
#include "mapfile/map_format.h"
#include "mapfile/map_layout.h"

namespace ldsm {

MapFileSummary summarizeMap(const std::uint8_t* data, std::size_t size, const std::string& where) {
  const mapfile::MapLayout layout = mapfile::readMapLayout(data, size, where);
  const MapData map = decodeMap(data, size, where);
  MapFileSummary s;
  s.version = layout.version;
  s.keyframes = map.keyframes.size();
  s.data_keyframes = map.data.size();
  for (const MarginalizedKeyframe& kf : map.data) {
    s.culled_keyframes += kf.culled ? 1 : 0;
    s.patch_points += kf.points.size();
    s.corners += kf.corners.size();
    s.descriptors += kf.descriptors.size();
  }
  s.points = map.points.size();
  s.graph_edges = map.graph.size();
  s.covisibility_edges = map.covisibility.size();
  s.vocabulary_bytes = map.vocabulary.size();
  s.camera = map.calibration.camera;
  s.radial_k = map.calibration.radial_k;
  s.focal_scale = std::exp(map.calibration.focal_log_scale);
  s.cx_shift = map.calibration.cx_shift;
  s.cy_shift = map.calibration.cy_shift;
  s.has_response = map.calibration.has_response;
  s.has_vignette = map.calibration.has_vignette;
  s.photometric_hash = map.calibration.photometric_hash;
  for (std::size_t i = 0; i < map.keyframes.size(); ++i) {
    const Eigen::Vector3d& c = map.keyframes[i].T_w_c.translation();
    for (int k = 0; k < 3; ++k) {
      s.area_min[k] = i == 0 ? c[k] : std::min(s.area_min[k], c[k]);
      s.area_max[k] = i == 0 ? c[k] : std::max(s.area_max[k], c[k]);
    }
  }
  s.total_bytes = size;
  for (const mapfile::SectionEntry& e : layout.sections)
    s.sections.push_back({mapfile::tagText(e.tag), e.size});
  return s;
}

std::vector<std::uint8_t> mapFileVocabulary(const std::uint8_t* data, std::size_t size,
                                            const std::string& where) {
  return decodeMap(data, size, where).vocabulary;
}

}  // namespace ldsm
