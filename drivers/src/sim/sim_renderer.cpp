// Scan conversion, deferred shading and edge anti-aliasing of SimScene (see sim_renderer.h).
#include "ldsm/drivers/sim/sim_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "ldsm/error.h"
#include "render_kernels.h"

namespace ldsm::drivers::sim {
namespace {

using render_detail::kNear;
constexpr std::uint16_t kNone = 0xffff;

}  // namespace

SimRenderer::TextureRef SimRendererKernels::makeRef(const MipTexture& t, const std::string& what) {
  SimRenderer::TextureRef r{};
  r.wrap = t.wrap;
  r.texels_per_m = static_cast<float>(1.0 / t.texel_size_m);
  r.count = t.levelCount();
  if (r.count < 1 || r.count > 24)
    throw InputError("sim renderer: " + what + " has " + std::to_string(r.count) +
                     " mip levels (1..24 supported)");
  r.size_u = static_cast<float>(t.levels[0].width);
  r.size_v = static_cast<float>(t.levels[0].height);
  r.inv_size_u = 1.0f / r.size_u;
  r.inv_size_v = 1.0f / r.size_v;
  for (int l = 0; l < r.count; ++l) {
    const MipLevel& level = t.levels[static_cast<std::size_t>(l)];
    if (level.texels.width() != level.width + 1 || level.texels.height() != level.height + 1)
      throw InputError("sim renderer: " + what + " level " + std::to_string(l) + " is not padded");
    r.levels[l] = {level.texels.data(),
                   level.texels.width(),
                   level.width,
                   level.height,
                   static_cast<float>(level.scale_u),
                   static_cast<float>(level.scale_v)};
  }
  return r;
}

namespace {

void validateCamera(const PinholeIntrinsics& c) {
  if (!(c.fx > 0.0 && c.fy > 0.0 && std::isfinite(c.fx) && std::isfinite(c.fy) &&
        std::isfinite(c.cx) && std::isfinite(c.cy)))
    throw ConfigError("sim renderer: camera fx, fy must be positive and cx, cy finite");
  if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384)
    throw ConfigError("sim renderer: camera size " + std::to_string(c.width) + "x" +
                      std::to_string(c.height) + " is outside [1, 16384]");
}

RigidPose toRigid(const Pose& p) {
  const Eigen::Quaterniond& q = p.rotation;
  const double n = std::sqrt(((q.w() * q.w() + q.x() * q.x()) + q.y() * q.y()) + q.z() * q.z());
  RigidPose r;
  r.rotation = matrixFromQuat({q.w() / n, q.x() / n, q.y() / n, q.z() / n});
  r.translation = {p.translation.x(), p.translation.y(), p.translation.z()};
  return r;
}

}  // namespace

SimRenderer::SimRenderer(std::shared_ptr<const SimScene> scene, const PinholeIntrinsics& camera,
                         RenderSettings settings)
    : scene_(std::move(scene)), camera_(camera), settings_(settings) {
  if (!scene_) throw ConfigError("sim renderer: no scene");
  validateCamera(camera_);
  if (settings_.supersampling < 1 || settings_.supersampling > 4)
    throw ConfigError("sim renderer: supersampling = " + std::to_string(settings_.supersampling) +
                      " is outside [1, 4]");
  if (scene_->quads.size() >= kNone)
    throw InputError("sim renderer: scene '" + scene_->name + "' has too many quads");
  for (const MipTexture& t : scene_->textures)
    textures_.push_back(SimRendererKernels::makeRef(t, "a texture"));
  for (const MipTexture& t : scene_->details)
    details_.push_back(SimRendererKernels::makeRef(t, "a detail map"));
  for (std::size_t i = 0; i < scene_->quads.size(); ++i) {
    const SimQuad& q = scene_->quads[i];
    if (q.texture < 0 || q.texture >= static_cast<int>(textures_.size()) || q.detail < -1 ||
        q.detail >= static_cast<int>(details_.size()))
      throw InputError("sim renderer: quad " + std::to_string(i) + " of scene '" + scene_->name +
                       "' refers to a missing texture or detail map");
  }
  frame_quads_.resize(scene_->quads.size());
}

void SimRenderer::renderIrradiance(const Pose& T_wc, ImageF& irradiance, ImageF* inverse_depth) {
  renderIrradiance(toRigid(T_wc), irradiance, inverse_depth);
}

void SimRenderer::renderIrradiance(const RigidPose& T_wc, ImageF& irradiance,
                                   ImageF* inverse_depth) {
  const int k = settings_.supersampling;
  if (k == 1) {
    renderAt(T_wc, camera_, irradiance, inverse_depth);
    return;
  }
  // Sub-pixel j of pixel x (j = 0..k-1) is centred at x + (j + 0.5) / k - 0.5.
  PinholeIntrinsics hi = camera_;
  hi.fx = camera_.fx * k;
  hi.fy = camera_.fy * k;
  hi.cx = (camera_.cx + 0.5) * k - 0.5;
  hi.cy = (camera_.cy + 0.5) * k - 0.5;
  hi.width = camera_.width * k;
  hi.height = camera_.height * k;
  renderAt(T_wc, hi, hires_, inverse_depth != nullptr ? &hires_depth_ : nullptr);
  const float norm = 1.0f / static_cast<float>(k * k);
  auto reduce = [&](const ImageF& src, ImageF& dst) {
    dst.resize(camera_.width, camera_.height);
    for (int y = 0; y < camera_.height; ++y) {
      float* out = dst.row(y);
      for (int x = 0; x < camera_.width; ++x) {
        float sum = 0.0f;
        for (int j = 0; j < k; ++j) {
          const float* in = src.row(y * k + j) + x * k;
          for (int i = 0; i < k; ++i) sum += in[i];
        }
        out[x] = sum * norm;
      }
    }
  };
  reduce(hires_, irradiance);
  if (inverse_depth != nullptr) reduce(hires_depth_, *inverse_depth);
}

void SimRenderer::renderAt(const RigidPose& T_wc, const PinholeIntrinsics& cam, ImageF& out,
                           ImageF* inverse_depth) {
  out.resize(cam.width, cam.height);
  wbuf_.resize(cam.width, cam.height);
  ids_.resize(cam.width, cam.height);
  xc_.resize(static_cast<std::size_t>(cam.width));
  for (int x = 0; x < cam.width; ++x)
    xc_[static_cast<std::size_t>(x)] = static_cast<float>(x - cam.cx);
  setupQuads(T_wc, cam);
  rasterize(cam);
  shade(cam, out);
  if (settings_.antialias_edges) antialiasEdges(cam, out);
  if (inverse_depth != nullptr) inverse_depth->copyFrom(wbuf_.view());
}

void SimRenderer::setupQuads(const RigidPose& T_wc, const PinholeIntrinsics& cam) {
  const Mat3 Rcw = T_wc.rotation.transposed();
  const Vec3& t = T_wc.translation;
  polygons_.clear();
  for (std::size_t qi = 0; qi < scene_->quads.size(); ++qi) {
    const SimQuad& q = scene_->quads[qi];
    FrameQuad& f = frame_quads_[qi];
    f.visible = false;
    // Corners in camera coordinates.
    const Vec3 corners[4] = {q.origin, q.origin + q.size_u * q.axis_u,
                             (q.origin + q.size_u * q.axis_u) + q.size_v * q.axis_v,
                             q.origin + q.size_v * q.axis_v};
    Vec3 c[4];
    bool any_front = false;
    for (int k = 0; k < 4; ++k) {
      c[k] = Rcw * (corners[k] - t);
      any_front = any_front || c[k].z >= kNear;
    }
    if (!any_front) continue;
    const Vec3 n = q.normal();
    const double h = dot(n, q.origin - t);  // plane: n_c . P = h in camera coordinates
    if (!(std::fabs(h) > 1e-9)) continue;   // camera in the plane: the quad is edge-on

    // Clip against z >= kNear (Sutherland-Hodgman, one plane).
    Polygon poly;
    poly.quad = static_cast<int>(qi);
    poly.count = 0;
    for (int k = 0; k < 4; ++k) {
      const Vec3& a = c[k];
      const Vec3& b = c[(k + 1) % 4];
      const bool ain = a.z >= kNear, bin = b.z >= kNear;
      if (ain) {
        poly.x[poly.count] = cam.fx * (a.x / a.z) + cam.cx;
        poly.y[poly.count] = cam.fy * (a.y / a.z) + cam.cy;
        ++poly.count;
      }
      if (ain != bin) {
        const double s = (kNear - a.z) / (b.z - a.z);
        const Vec3 p = a + s * (b - a);
        poly.x[poly.count] = cam.fx * (p.x / kNear) + cam.cx;
        poly.y[poly.count] = cam.fy * (p.y / kNear) + cam.cy;
        ++poly.count;
      }
    }
    if (poly.count < 3) continue;
    polygons_.push_back(poly);

    const Vec3 nc = Rcw * n, au = Rcw * q.axis_u, av = Rcw * q.axis_v;
    f.wx = static_cast<float>(nc.x / (cam.fx * h));
    f.wy = static_cast<float>(nc.y / (cam.fy * h));
    f.w0 = static_cast<float>(nc.z / h);
    f.ux = static_cast<float>(au.x / cam.fx);
    f.uy = static_cast<float>(au.y / cam.fy);
    f.u0 = static_cast<float>(au.z);
    f.vx = static_cast<float>(av.x / cam.fx);
    f.vy = static_cast<float>(av.y / cam.fy);
    f.v0 = static_cast<float>(av.z);
    f.bu = static_cast<float>(dot(q.axis_u, t - q.origin));
    f.bv = static_cast<float>(dot(q.axis_v, t - q.origin));
    f.size_u = static_cast<float>(q.size_u);
    f.size_v = static_cast<float>(q.size_v);
    f.off_u = static_cast<float>(q.texture_offset_u);
    f.off_v = static_cast<float>(q.texture_offset_v);
    f.texture = q.texture;
    f.detail = q.detail;
    f.visible = true;
  }
}

void SimRenderer::rasterize(const PinholeIntrinsics& cam) {
  wbuf_.fill(0.0f);
  ids_.fill(kNone);
  const int W = cam.width, H = cam.height;
  for (const Polygon& p : polygons_) {
    const FrameQuad& f = frame_quads_[static_cast<std::size_t>(p.quad)];
    double area2 = 0.0, ymin = p.y[0], ymax = p.y[0];
    for (int k = 0; k < p.count; ++k) {
      const int k1 = (k + 1) % p.count;
      area2 += p.x[k] * p.y[k1] - p.x[k1] * p.y[k];
      ymin = std::min(ymin, p.y[k]);
      ymax = std::max(ymax, p.y[k]);
    }
    if (!(std::fabs(area2) > 1e-12)) continue;
    const double sg = area2 > 0.0 ? 1.0 : -1.0;
    // Edge k: a x + b y + c >= 0 inside. c uses both end points symmetrically, so the shared edge
    // of two neighbouring polygons gets exactly opposite equations and leaves no crack.
    double ea[8], eb[8], ec[8];
    for (int k = 0; k < p.count; ++k) {
      const int k1 = (k + 1) % p.count;
      ea[k] = (p.y[k] - p.y[k1]) * sg;
      eb[k] = (p.x[k1] - p.x[k]) * sg;
      ec[k] = -(ea[k] * (p.x[k] + p.x[k1]) + eb[k] * (p.y[k] + p.y[k1])) * 0.5;
    }
    const int y0 = static_cast<int>(std::ceil(std::max(ymin, -1.0)));
    const int y1 = static_cast<int>(std::floor(std::min(ymax, static_cast<double>(H))));
    const std::uint16_t id = static_cast<std::uint16_t>(p.quad);
    for (int y = std::max(y0, 0); y <= std::min(y1, H - 1); ++y) {
      const double yd = static_cast<double>(y);
      double lo = -1.0, hi = static_cast<double>(W);
      bool empty = false;
      for (int k = 0; k < p.count; ++k) {
        const double r = eb[k] * yd + ec[k];
        if (ea[k] > 0.0) {
          lo = std::max(lo, -r / ea[k]);
        } else if (ea[k] < 0.0) {
          hi = std::min(hi, -r / ea[k]);
        } else if (r < 0.0) {
          empty = true;
        }
      }
      if (empty || !(lo <= hi)) continue;
      const int x0 = std::max(0, static_cast<int>(std::ceil(lo)));
      const int x1 = std::min(W - 1, static_cast<int>(std::floor(hi)));
      const float rowpart = f.wy * static_cast<float>(y - cam.cy) + f.w0;
      float* wr = wbuf_.row(y);
      std::uint16_t* ir = ids_.row(y);
      const float* xc = xc_.data();
      for (int x = x0; x <= x1; ++x) {
        const float w = f.wx * xc[x] + rowpart;
        if (w > wr[x]) {
          wr[x] = w;
          ir[x] = id;
        }
      }
    }
  }
}

void SimRenderer::shade(const PinholeIntrinsics& cam, ImageF& out) {
  const int W = cam.width;
  for (int y = 0; y < cam.height; ++y) {
    const float yc = static_cast<float>(y - cam.cy);
    const std::uint16_t* ir = ids_.row(y);
    float* o = out.row(y);
    const float* xc = xc_.data();
    // Runs of pixels that see the same quad share its equations and textures.
    for (int x = 0; x < W;) {
      const std::uint16_t id = ir[x];
      int end = x + 1;
      while (end < W && ir[end] == id) ++end;
      if (id == kNone) {
        for (; x < end; ++x) o[x] = 0.0f;
        continue;
      }
      const FrameQuad f = frame_quads_[id];
      const TextureRef& tex = textures_[static_cast<std::size_t>(f.texture)];
      const TextureRef* det =
          f.detail >= 0 ? &details_[static_cast<std::size_t>(f.detail)] : nullptr;
      while (x < end) {
        const int n = std::min(end - x, SimRendererKernels::kChunk);
        SimRendererKernels::shadeRun(f, tex, det, xc + x, n, yc, o + x);
        x += n;
      }
    }
  }
}

void SimRenderer::antialiasEdges(const PinholeIntrinsics& cam, ImageF& out) {
  // Rotated-grid sub-sample offsets.
  static constexpr float kOffsets[4][2] = {
      {0.125f, 0.375f}, {0.375f, -0.125f}, {-0.125f, -0.375f}, {-0.375f, 0.125f}};
  const int W = cam.width, H = cam.height;
  edge_mask_.resize(static_cast<std::size_t>(W));
  std::uint8_t* mask = edge_mask_.data();
  for (int y = 0; y < H; ++y) {
    const std::uint16_t* ir = ids_.row(y);
    const std::uint16_t* up = y > 0 ? ids_.row(y - 1) : ir;
    const std::uint16_t* down = y + 1 < H ? ids_.row(y + 1) : ir;
    const float yc = static_cast<float>(y - cam.cy);
    // Edge pixels: the quad differs from a 4-neighbour's (vectorisable pass over the row).
    mask[0] = ir[0] != up[0] || ir[0] != down[0] || (W > 1 && ir[0] != ir[1]);
    for (int x = 1; x + 1 < W; ++x)
      mask[x] = static_cast<std::uint8_t>((ir[x] != up[x]) | (ir[x] != down[x]) |
                                          (ir[x] != ir[x - 1]) | (ir[x] != ir[x + 1]));
    if (W > 1)
      mask[W - 1] = ir[W - 1] != up[W - 1] || ir[W - 1] != down[W - 1] || ir[W - 1] != ir[W - 2];
    for (int x = 0; x < W; ++x) {
      if (mask[x] == 0) continue;
      const std::uint16_t id = ir[x];
      // Candidates: the quads seen in the 3x3 neighbourhood.
      std::uint16_t cand[9];
      int nc = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= H) continue;
        const std::uint16_t* r = ids_.row(yy);
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= W || r[xx] == kNone) continue;
          bool seen = false;
          for (int k = 0; k < nc; ++k) seen = seen || cand[k] == r[xx];
          if (!seen) cand[nc++] = r[xx];
        }
      }
      const float xc = xc_[static_cast<std::size_t>(x)];
      // Sub-samples that see the centre's quad reuse the centre's value (already shaded, with
      // the same texture footprint); the others are shaded from the quad they see.
      float sum = 0.0f;
      for (const auto& o : kOffsets) {
        const float sx = xc + o[0], sy = yc + o[1];
        int best = -1;
        float best_w = 0.0f;
        for (int k = 0; k < nc; ++k) {
          float w = 0.0f;
          if (SimRendererKernels::hits(frame_quads_[cand[k]], sx, sy, w) && w > best_w) {
            best_w = w;
            best = cand[k];
          }
        }
        if (best < 0 || best == id) {
          sum += id == kNone ? 0.0f : out(x, y);
          continue;
        }
        const FrameQuad& f = frame_quads_[static_cast<std::size_t>(best)];
        const TextureRef* det =
            f.detail >= 0 ? &details_[static_cast<std::size_t>(f.detail)] : nullptr;
        sum += SimRendererKernels::shade(f, textures_[static_cast<std::size_t>(f.texture)], det, sx,
                                         sy);
      }
      out(x, y) = sum * 0.25f;
    }
  }
}

}  // namespace ldsm::drivers::sim
