#include "scene_builder.h"

#include <algorithm>
#include <cmath>

#include "detail_maps.h"
#include "ldsm/drivers/sim/det_math.h"
#include "texture_library.h"

namespace ldsm::drivers::sim {
namespace {

int segmentCount(double length, double max_segment) {
  return std::max(1, static_cast<int>(std::ceil(length / max_segment - 1e-9)));
}

}  // namespace

std::uint32_t SceneBuilder::hash(std::uint32_t k) const {
  return hash32(seed_, k, 0xb01du);
}

int SceneBuilder::addQuad(const Vec3& origin, const Vec3& axis_u, const Vec3& axis_v, double size_u,
                          double size_v, SurfaceKind kind, int texture, const Margins& m) {
  SimQuad q;
  q.origin = (origin - m.u_begin * axis_u) - m.v_begin * axis_v;
  q.axis_u = axis_u;
  q.axis_v = axis_v;
  q.size_u = (size_u + m.u_begin) + m.u_end;
  q.size_v = (size_v + m.v_begin) + m.v_end;
  q.kind = kind;
  q.texture = texture;
  const std::uint32_t h = nextHash();
  // Offsets on the 5 mm texel grid (whole texels) keep the pattern's edges crisp.
  q.texture_offset_u = static_cast<double>(hash32(h, 1) % 512u) * 0.005;
  q.texture_offset_v = static_cast<double>(hash32(h, 2) % 512u) * 0.005;
  scene_.quads.push_back(q);
  return static_cast<int>(scene_.quads.size()) - 1;
}

void SceneBuilder::addWall(double ax, double ay, double bx, double by, double z0, double z1,
                           const std::vector<int>& textures, double max_segment,
                           double margin_ends) {
  const double dx = bx - ax, dy = by - ay;
  const double length = std::sqrt(dx * dx + dy * dy);
  const Vec3 u{dx / length, dy / length, 0.0};
  const Vec3 v{0, 0, 1};
  const int n = segmentCount(length, max_segment);
  const std::size_t start = nextHash() % textures.size();
  for (int i = 0; i < n; ++i) {
    // Segment ends computed from the same expression on both sides of a joint.
    const double t0 = static_cast<double>(i) / n, t1 = static_cast<double>(i + 1) / n;
    const Vec3 p0{ax + dx * t0, ay + dy * t0, z0};
    const Vec3 p1{ax + dx * t1, ay + dy * t1, z0};
    Margins m;
    m.u_begin = i == 0 ? margin_ends : 0.0;
    m.u_end = i == n - 1 ? margin_ends : 0.0;
    m.v_begin = kWallMargin;
    m.v_end = kWallMargin;
    const double seg = norm(p1 - p0);
    addQuad(p0, u, v, seg, z1 - z0, SurfaceKind::Wall,
            textures[(start + static_cast<std::size_t>(i)) % textures.size()], m);
  }
}

void SceneBuilder::addHorizontal(double x0, double x1, double y0, double y1, double z,
                                 SurfaceKind kind, int texture, double max_segment,
                                 const Margins& margins) {
  const int nx = segmentCount(x1 - x0, max_segment), ny = segmentCount(y1 - y0, max_segment);
  for (int j = 0; j < ny; ++j) {
    const double ya = y0 + (y1 - y0) * j / ny, yb = y0 + (y1 - y0) * (j + 1) / ny;
    for (int i = 0; i < nx; ++i) {
      const double xa = x0 + (x1 - x0) * i / nx, xb = x0 + (x1 - x0) * (i + 1) / nx;
      Margins m;
      m.u_begin = i == 0 ? margins.u_begin : 0.0;
      m.u_end = i == nx - 1 ? margins.u_end : 0.0;
      m.v_begin = j == 0 ? margins.v_begin : 0.0;
      m.v_end = j == ny - 1 ? margins.v_end : 0.0;
      addQuad({xa, ya, z}, {1, 0, 0}, {0, 1, 0}, xb - xa, yb - ya, kind, texture, m);
    }
  }
}

void SceneBuilder::addRoom(double x0, double x1, double y0, double y1, double z0, double z1,
                           const std::vector<int>& wall_textures, int floor_texture,
                           int ceiling_texture, double max_segment) {
  addHorizontal(x0, x1, y0, y1, z0, SurfaceKind::Floor, floor_texture, max_segment, {});
  addHorizontal(x0, x1, y0, y1, z1, SurfaceKind::Ceiling, ceiling_texture, max_segment, {});
  addWall(x0, y0, x1, y0, z0, z1, wall_textures, max_segment, kWallMargin);
  addWall(x1, y0, x1, y1, z0, z1, wall_textures, max_segment, kWallMargin);
  addWall(x1, y1, x0, y1, z0, z1, wall_textures, max_segment, kWallMargin);
  addWall(x0, y1, x0, y0, z0, z1, wall_textures, max_segment, kWallMargin);
}

void SceneBuilder::addBox(double x0, double x1, double y0, double y1, double z0, double z1,
                          int texture, bool top) {
  const Vec3 up{0, 0, 1};
  const double h = z1 - z0;
  addQuad({x0, y0, z0}, {1, 0, 0}, up, x1 - x0, h, SurfaceKind::Box, texture);
  addQuad({x1, y0, z0}, {0, 1, 0}, up, y1 - y0, h, SurfaceKind::Box, texture);
  addQuad({x1, y1, z0}, {-1, 0, 0}, up, x1 - x0, h, SurfaceKind::Box, texture);
  addQuad({x0, y1, z0}, {0, -1, 0}, up, y1 - y0, h, SurfaceKind::Box, texture);
  if (top) addQuad({x0, y0, z1}, {1, 0, 0}, {0, 1, 0}, x1 - x0, y1 - y0, SurfaceKind::Box, texture);
}

void bakeSceneTextures(SimScene& scene, std::uint32_t seed) {
  scene.textures = makeTextureLibrary(seed);
  scene.details.clear();
  scene.details.reserve(scene.quads.size());
  for (std::size_t i = 0; i < scene.quads.size(); ++i) {
    scene.details.push_back(bakeDetailMap(scene, static_cast<int>(i), seed));
    scene.quads[i].detail = static_cast<int>(i);
  }
}

std::vector<Vec3> rectangleControlPoints(double x0, double x1, double y0, double y1, double z,
                                         double spacing) {
  const double w = x1 - x0, h = y1 - y0;
  const int nw = std::max(2, static_cast<int>(std::lround(w / spacing)));
  const int nh = std::max(2, static_cast<int>(std::lround(h / spacing)));
  std::vector<Vec3> corners_walk;
  // Bottom side from its middle to the right corner, then right, top, left, and bottom again.
  const int half = nw / 2;
  for (int i = half; i < nw; ++i) corners_walk.push_back({x0 + w * i / nw, y0, z});
  for (int i = 0; i < nh; ++i) corners_walk.push_back({x1, y0 + h * i / nh, z});
  for (int i = 0; i < nw; ++i) corners_walk.push_back({x1 - w * i / nw, y1, z});
  for (int i = 0; i < nh; ++i) corners_walk.push_back({x0, y1 - h * i / nh, z});
  for (int i = 0; i < half; ++i) corners_walk.push_back({x0 + w * i / nw, y0, z});
  return corners_walk;
}

std::vector<Vec3> ellipseControlPoints(double rx, double ry, double z, int n) {
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) {
    double s, c;
    detSinCos(2.0 * kPi * i / n, s, c);
    pts.push_back({rx * c, ry * s, z});
  }
  return pts;
}

}  // namespace ldsm::drivers::sim
