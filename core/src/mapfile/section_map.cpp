// CALB (calibration), CALR (calibration refinement), PNTS (points), COVI (covisibility) and GRPH
// (pose graph): docs/map-file.md.
#include <cmath>
#include <limits>
#include <string>

#include "mapfile/map_checks.h"
#include "mapfile/map_sections.h"
#include "mapfile/pose_codec.h"

namespace ldsm::mapfile {
namespace {

constexpr std::uint32_t kResponseFlag = 1;
constexpr std::uint32_t kVignetteFlag = 2;
constexpr std::size_t kPointBytes = 3 * 8 + 4 + 4 + 4 + 1;
constexpr std::uint8_t kCornerFlag = 1;
constexpr std::size_t kCovisibilityBytes = 3 * 4;
constexpr std::size_t kGraphEdgeBytes = 4 + 4 + 1 + kSim3Bytes + 49 * 8;

}  // namespace

void writeCalibration(ByteWriter& w, const MapCalibration& c) {
  w.i32(c.camera.width);
  w.i32(c.camera.height);
  w.f64(c.camera.fx);
  w.f64(c.camera.fy);
  w.f64(c.camera.cx);
  w.f64(c.camera.cy);
  w.f64(c.radial_k);
  w.u32((c.has_response ? kResponseFlag : 0u) | (c.has_vignette ? kVignetteFlag : 0u));
  w.u64(c.photometric_hash);
}

MapCalibration readCalibration(ByteReader& r) {
  MapCalibration c;
  c.camera.width = r.i32();
  c.camera.height = r.i32();
  c.camera.fx = r.f64();
  c.camera.fy = r.f64();
  c.camera.cx = r.f64();
  c.camera.cy = r.f64();
  c.radial_k = r.f64();
  const std::uint32_t flags = r.u32();
  if ((flags & ~(kResponseFlag | kVignetteFlag)) != 0)
    r.fail("photometric flags " + std::to_string(flags) + " have unknown bits");
  c.has_response = (flags & kResponseFlag) != 0;
  c.has_vignette = (flags & kVignetteFlag) != 0;
  c.photometric_hash = r.u64();
  return c;
}

void writeRefinement(ByteWriter& w, const MapCalibration& c) {
  w.f64(c.focal_log_scale);
  w.f64(c.cx_shift);
  w.f64(c.cy_shift);
}

void readRefinement(ByteReader& r, MapCalibration& c) {
  c.focal_log_scale = r.f64();
  c.cx_shift = r.f64();
  c.cy_shift = r.f64();
}

void writePoints(ByteWriter& w, const std::vector<HostedPoint>& points) {
  w.count(points.size());
  for (const HostedPoint& p : points) {
    for (int i = 0; i < 3; ++i) w.f64(p.position[i]);
    w.f32(p.intensity);
    w.i32(p.host);
    w.i32(p.map);
    w.u8(p.is_corner ? kCornerFlag : 0);
  }
}

std::vector<HostedPoint> readPoints(ByteReader& r) {
  std::vector<HostedPoint> points(r.count("points", kPointBytes));
  for (std::size_t j = 0; j < points.size(); ++j) {
    HostedPoint& p = points[j];
    // Held in float (HostedPoint): a finite coordinate beyond float's range is refused here
    // (it would become infinite); NaN and infinities are named by the checks.
    for (int i = 0; i < 3; ++i) {
      const double v = r.f64();
      if (std::isfinite(v) && std::fabs(v) > std::numeric_limits<float>::max())
        r.fail("point " + std::to_string(j) + ": coordinate " + numberText(v) +
               " is beyond the range the map holds points in (float, " +
               numberText(std::numeric_limits<float>::max()) + ")");
      p.position[i] = static_cast<float>(v);
    }
    p.intensity = r.f32();
    p.host = r.i32();
    p.map = r.i32();
    const std::uint8_t flags = r.u8();
    if ((flags & ~kCornerFlag) != 0)
      r.fail("point " + std::to_string(j) + ": flags " + std::to_string(flags) +
             " have unknown bits");
    p.is_corner = (flags & kCornerFlag) != 0;
  }
  return points;
}

void writeCovisibility(ByteWriter& w, const std::vector<MapCovisibility>& edges) {
  w.count(edges.size());
  for (const MapCovisibility& e : edges) {
    w.i32(e.a);
    w.i32(e.b);
    w.i32(e.weight);
  }
}

std::vector<MapCovisibility> readCovisibility(ByteReader& r) {
  std::vector<MapCovisibility> edges(r.count("edges", kCovisibilityBytes));
  for (MapCovisibility& e : edges) {
    e.a = r.i32();
    e.b = r.i32();
    e.weight = r.i32();
  }
  return edges;
}

void writeGraph(ByteWriter& w, const std::vector<MapGraphEdge>& edges) {
  w.count(edges.size());
  for (const MapGraphEdge& e : edges) {
    w.i32(e.from_id);
    w.i32(e.to_id);
    w.u8(static_cast<std::uint8_t>(e.kind));  // 0..2, checked before encoding
    writeSim3(w, e.S_from_to);
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j) w.f64(e.information(i, j));
  }
}

std::vector<MapGraphEdge> readGraph(ByteReader& r) {
  std::vector<MapGraphEdge> edges(r.count("edges", kGraphEdgeBytes));
  for (MapGraphEdge& e : edges) {
    e.from_id = r.i32();
    e.to_id = r.i32();
    r.setContext("edge " + std::to_string(e.from_id) + " -> " + std::to_string(e.to_id));
    e.kind = r.u8();
    e.S_from_to = readSim3(r, "Sim(3)");
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j) e.information(i, j) = r.f64();
  }
  r.setContext("");
  return edges;
}

}  // namespace ldsm::mapfile
