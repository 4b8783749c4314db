#include "pipeline/map_persistence.h"

#include <algorithm>
#include <cstring>
#include <memory>

#include "camera/radial_distortion.h"
#include "ldsm/error.h"
#include "map/map_depth.h"
#include "mapfile/map_calibration.h"

namespace ldsm {
namespace {

/// FNV-1a over the bytes of a float array.
void hashFloats(const float* data, std::size_t n, std::uint64_t& h) {
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &data[i], sizeof(bits));
    for (int b = 0; b < 4; ++b) {
      h ^= (bits >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  }
}

Sim3d sim3Of(const KeyframeRecord& r) {
  return Sim3d(r.T_w_c.so3(), r.T_w_c.translation(), r.scale);
}

/// A keyframe record moved by S (into the frame poses are reported in).
KeyframeRecord moved(KeyframeRecord r, const Sim3d& S) {
  const Sim3d S_w_c = S * sim3Of(r);
  r.T_w_c = SE3d(S_w_c.so3(), S_w_c.translation());
  r.scale = S_w_c.scale();
  r.map = 0;
  return r;
}

MapGraphEdge toSaved(const loop::PoseGraphEdge& e) {
  return {e.from_id, e.to_id, static_cast<int>(e.kind), e.S_from_to, e.information};
}

loop::PoseGraphEdge fromSaved(const MapGraphEdge& e) {
  return {e.from_id, e.to_id, e.S_from_to, e.information,
          static_cast<loop::PoseGraphEdgeKind>(e.kind)};
}

}  // namespace

MapCalibration mapCalibration(const LevelCamera& camera, const PhotometricCalibration& photometric,
                              double radial_k) {
  MapCalibration c;
  c.camera = {camera.fx, camera.fy, camera.cx, camera.cy, camera.width, camera.height};
  c.radial_k = radial_k;
  c.has_response = photometric.has_response;
  c.has_vignette = !photometric.vignette.empty();
  if (c.has_response || c.has_vignette) {
    std::uint64_t h = 1469598103934665603ull;
    if (c.has_response)
      hashFloats(photometric.inverse_response.data(), photometric.inverse_response.size(), h);
    if (c.has_vignette)
      for (int y = 0; y < photometric.vignette.height(); ++y)
        hashFloats(&photometric.vignette(0, y),
                   static_cast<std::size_t>(photometric.vignette.width()), h);
    c.photometric_hash = h;
  }
  return c;
}

MapData exportMap(const MapStore& store, MappingStage& mapping, const loop::LoopCloser* loop,
                  const LevelCamera& camera, const MapCalibration& calibration,
                  const MapExportScope& scope) {
  MapData out;
  out.calibration = calibration;
  const StoredMap stored = store.firstMap();
  const Sim3d& S = stored.S_report_world;
  std::vector<int> ids;
  for (const KeyframeRecord& r : stored.keyframes) {
    if (r.id >= scope.keyframes_below) continue;
    out.keyframes.push_back(moved(r, S));
    ids.push_back(r.id);
  }
  const auto saved = [&](int id) { return std::binary_search(ids.begin(), ids.end(), id); };
  // Only a limited scope drops what hangs on keyframes it leaves out.
  const bool limited = scope.keyframes_below != MapExportScope{}.keyframes_below;
  const auto kept = [&](int id) { return !limited || saved(id); };
  const auto record = [&](int id) {
    return *std::lower_bound(out.keyframes.begin(), out.keyframes.end(), id,
                             [](const KeyframeRecord& r, int k) { return r.id < k; });
  };
  for (const auto& data : stored.data)
    if (kept(data->id)) out.data.push_back(*data);
  for (const HostedPoint& p : stored.points) {
    if (!kept(p.host)) continue;
    HostedPoint q = p;
    q.position = (S * p.position.cast<double>()).cast<float>();
    q.map = 0;
    out.points.push_back(q);
  }
  // The window's keyframes join the map as they would if they left it now, with their points.
  std::vector<std::pair<int, Sim3d>> window;
  std::vector<MarginalizedKeyframe> window_keyframes;
  if (scope.window) window_keyframes = mapping.windowForMap();
  for (MarginalizedKeyframe& kf : window_keyframes) {
    if (!saved(kf.id) || store.keyframeData(kf.id)) continue;
    const KeyframeRecord r = record(kf.id);
    window.emplace_back(kf.id, S.inverse() * sim3Of(r));
    for (const PatchPoint& p : kf.points) {
      const Eigen::Vector3d ray = radialRay(camera, kf.radial_k, p.u, p.v).cast<double>();
      HostedPoint q;
      q.host = kf.id;
      q.position = (r.T_w_c * (r.scale * ray / static_cast<double>(p.idepth))).cast<float>();
      q.intensity = p.colors[0];
      q.is_corner = p.is_corner;
      out.points.push_back(q);
    }
    out.data.push_back(std::move(kf));
  }
  for (MarginalizedKeyframe& kf : out.data) {
    const KeyframeRecord r = record(kf.id);
    kf.T_w_c = r.T_w_c;
    kf.image = ImageF();
  }
  std::sort(
      out.data.begin(), out.data.end(),
      [](const MarginalizedKeyframe& a, const MarginalizedKeyframe& b) { return a.id < b.id; });
  for (const auto& e : stored.covisibility)
    if (kept(e[0]) && kept(e[1])) out.covisibility.push_back({e[0], e[1], e[2]});
  if (loop) {
    const loop::LoopCloser::GraphExport g = loop->exportGraph(ids, window);
    for (const loop::PoseGraphEdge& e : g.edges) out.graph.push_back(toSaved(e));
    if (g.vocabulary && !g.vocabulary->empty()) out.vocabulary = g.vocabulary->serialize();
  }
  return out;
}

void importMap(const MapData& map, const MapCalibration& now, const std::string& where,
               MapStore& store, MappingStage& mapping, loop::LoopCloser* loop,
               TrackingStage& tracking) {
  if (const std::string why = mapCalibrationMismatch(map.calibration, now); !why.empty())
    throw InputError(where + ": made with another camera: " + why);
  StoredMap stored;
  stored.keyframes = map.keyframes;
  for (const MarginalizedKeyframe& kf : map.data)
    stored.data.push_back(std::make_shared<const MarginalizedKeyframe>(kf));
  stored.points = map.points;
  for (const MapCovisibility& c : map.covisibility)
    stored.covisibility.push_back({c.a, c.b, c.weight});
  store.loadMap(stored);
  if (loop) {
    std::vector<std::pair<int, Sim3d>> vertices;
    for (const KeyframeRecord& r : map.keyframes) vertices.emplace_back(r.id, sim3Of(r));
    std::vector<loop::PoseGraphEdge> edges;
    for (const MapGraphEdge& e : map.graph) edges.push_back(fromSaved(e));
    std::shared_ptr<const loop::Vocabulary> vocabulary;
    if (!map.vocabulary.empty())
      vocabulary = std::make_shared<const loop::Vocabulary>(loop::Vocabulary::deserialize(
          map.vocabulary.data(), map.vocabulary.size(), where + ": vocabulary"));
    loop->importMap(vertices, edges, std::move(vocabulary), stored.data);
  }
  int next_id = 0;
  for (const KeyframeRecord& r : map.keyframes) next_id = std::max(next_id, r.id + 1);
  mapping.continueAfterLoadedMap(next_id, map.calibration, medianKeyframeDepth(stored));
  tracking.startInLoadedMap();
}

}  // namespace ldsm
