// Per-pixel kernels of SimRenderer: texture coordinates and level of detail from a quad's plane
// equations, trilinear mip-mapped lookups, shading and the sub-sample hit test. Internal to
// sim_renderer.cpp (a header only to keep that file small).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

#include "ldsm/drivers/sim/sim_renderer.h"

namespace ldsm::drivers::sim {
namespace render_detail {

constexpr double kNear = 0.02;  // metres
constexpr float kMaxInverseDepth = static_cast<float>(1.0 / kNear);
constexpr float kInsideTolerance = 1e-3f;  // metres, for edge sub-samples

// Clamps to [lo, hi]; NaN becomes lo (so no NaN ever reaches a float-to-int conversion, whose
// result would differ between architectures). Two plain selects vectorise; a nested one does not.
inline float clampTo(float s, float lo, float hi) {
  const float a = s > lo ? s : lo;
  return a < hi ? a : hi;
}

inline float clampCoord(float s) {
  return clampTo(s, -1e7f, 1e7f);
}

// log2 of a positive normal float, piecewise linear between powers of two (error < 0.09);
// exact at powers of two and continuous, so mip blending stays smooth.
inline float fastLog2(float x) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  return static_cast<float>(static_cast<std::int32_t>(bits)) * (1.0f / 8388608.0f) - 127.0f;
}

}  // namespace render_detail

// The kernels, as static members of a friend of SimRenderer (they need its private types).
struct SimRendererKernels {
  using TextureRef = SimRenderer::TextureRef;
  using FrameQuad = SimRenderer::FrameQuad;

  static TextureRef makeRef(const MipTexture& t, const std::string& what);

  // Bilinear lookup in level L at canonical level-0 coordinates (s, t >= 0: wrapped into the
  // period or clamped to the border). The padding column/row makes i + 1, j + 1 always valid.
  static float bilinear(const SimRenderer::Level& L, float s, float t) {
    const float x = s * L.scale_u, y = t * L.scale_v;
    int i = static_cast<int>(x), j = static_cast<int>(y);
    i = i < L.width - 1 ? i : L.width - 1;
    j = j < L.height - 1 ? j : L.height - 1;
    const float a = x - static_cast<float>(i), b = y - static_cast<float>(j);
    const float* p = L.data + static_cast<std::ptrdiff_t>(j) * L.stride + i;
    const float* q = p + L.stride;
    const float top = p[0] + a * (p[1] - p[0]);
    const float bottom = q[0] + a * (q[1] - q[0]);
    return top + b * (bottom - top);
  }

  // Trilinear lookup at canonical level-0 coordinates (s, t) with level of detail lambda.
  static float sample(const TextureRef& T, float s, float t, float lambda) {
    if (!(lambda > 0.0f)) return bilinear(T.levels[0], s, t);
    const int last = T.count - 1;
    if (lambda >= static_cast<float>(last)) return bilinear(T.levels[last], s, t);
    const int l = static_cast<int>(lambda);
    const float f = lambda - static_cast<float>(l);
    const float va = bilinear(T.levels[l], s, t);
    const float vb = bilinear(T.levels[l + 1], s, t);
    return va + f * (vb - va);
  }

  // Coordinate s (level-0 texels) of texture T made canonical: wrapped into [0, size) or clamped
  // to [0, size - 1]. |s| <= 1e7 (see render_detail::clampCoord).
  template <bool kWrap>
  static inline float canonical(float s, float size, float inv_size) {
    if constexpr (kWrap) {
      const float r = s * inv_size;
      int k = static_cast<int>(r);
      k -= static_cast<int>(r < static_cast<float>(k));  // floor (integer form vectorises)
      const float m = s - static_cast<float>(k) * size;
      return render_detail::clampTo(m, 0.0f, size - (1.0f / 256.0f));
    }
    (void)inv_size;
    return render_detail::clampTo(s, 0.0f, size - 1.0f);
  }

  static float inverseDepth(const FrameQuad& q, float xc, float yc) {
    return q.wx * xc + (q.wy * yc + q.w0);
  }

  // Canonical texture coordinates (level-0 texels) and levels of detail of the albedo pattern B
  // (sb, tb, lb) and the detail map D (sd, td, ld) where the ray through (xc, yc) meets quad q.
  template <bool kWrapB, bool kWrapD>
  static inline void lookupCoords(const FrameQuad& q, const TextureRef& B, const TextureRef& D,
                                  float xc, float yc, float& sb, float& tb, float& lb, float& sd,
                                  float& td, float& ld) {
    const float kb = B.texels_per_m, kd = D.texels_per_m;
    const float w = inverseDepth(q, xc, yc);
    const float inv = 1.0f / w;
    const float nu = q.ux * xc + (q.uy * yc + q.u0);
    const float nv = q.vx * xc + (q.vy * yc + q.v0);
    const float up = nu * inv, vp = nv * inv;
    // Derivatives of (u, v) per pixel from the homography, for the footprint.
    const float dudx = (q.ux - up * q.wx) * inv, dudy = (q.uy - up * q.wy) * inv;
    const float dvdx = (q.vx - vp * q.wx) * inv, dvdy = (q.vy - vp * q.wy) * inv;
    const float fx2 = dudx * dudx + dvdx * dvdx, fy2 = dudy * dudy + dvdy * dvdy;
    const float rho2 = fx2 > fy2 ? fx2 : fy2;  // squared metres per pixel
    const float u = up + q.bu, v = vp + q.bv;
    sb = canonical<kWrapB>(render_detail::clampCoord((u + q.off_u) * kb), B.size_u, B.inv_size_u);
    tb = canonical<kWrapB>(render_detail::clampCoord((v + q.off_v) * kb), B.size_v, B.inv_size_v);
    lb = 0.5f * render_detail::fastLog2(rho2 * (kb * kb) + 1e-30f);
    sd = canonical<kWrapD>(render_detail::clampCoord(u * kd), D.size_u, D.inv_size_u);
    td = canonical<kWrapD>(render_detail::clampCoord(v * kd), D.size_v, D.inv_size_v);
    ld = 0.5f * render_detail::fastLog2(rho2 * (kd * kd) + 1e-30f);
  }

  // Irradiance of quad q at centred pixel coordinates (xc, yc).
  static float shade(const FrameQuad& q, const TextureRef& tex, const TextureRef* det, float xc,
                     float yc) {
    float sb, tb, lb, sd, td, ld;
    const TextureRef& D = det != nullptr ? *det : tex;
    if (tex.wrap && D.wrap)
      lookupCoords<true, true>(q, tex, D, xc, yc, sb, tb, lb, sd, td, ld);
    else if (tex.wrap)
      lookupCoords<true, false>(q, tex, D, xc, yc, sb, tb, lb, sd, td, ld);
    else if (D.wrap)
      lookupCoords<false, true>(q, tex, D, xc, yc, sb, tb, lb, sd, td, ld);
    else
      lookupCoords<false, false>(q, tex, D, xc, yc, sb, tb, lb, sd, td, ld);
    float value = sample(tex, sb, tb, lb);
    if (det != nullptr) value *= sample(*det, sd, td, ld);
    return value;
  }

  // shade() for n <= kChunk consecutive pixels of one row: the coordinate computations run as a
  // separate (vectorisable) loop before the texture fetches.
  static constexpr int kChunk = 64;
  template <bool kWrapB, bool kWrapD>
  static void coordsLoop(const FrameQuad& q, const TextureRef& B, const TextureRef& D,
                         const float* xc, int n, float yc, float* sb, float* tb, float* lb,
                         float* sd, float* td, float* ld) {
    for (int i = 0; i < n; ++i)
      lookupCoords<kWrapB, kWrapD>(q, B, D, xc[i], yc, sb[i], tb[i], lb[i], sd[i], td[i], ld[i]);
  }
  static void shadeRun(const FrameQuad& q, const TextureRef& tex, const TextureRef* det,
                       const float* xc, int n, float yc, float* out) {
    alignas(32) float sb[kChunk], tb[kChunk], lb[kChunk], sd[kChunk], td[kChunk], ld[kChunk];
    const TextureRef& D = det != nullptr ? *det : tex;
    if (tex.wrap && D.wrap)
      coordsLoop<true, true>(q, tex, D, xc, n, yc, sb, tb, lb, sd, td, ld);
    else if (tex.wrap)
      coordsLoop<true, false>(q, tex, D, xc, n, yc, sb, tb, lb, sd, td, ld);
    else if (D.wrap)
      coordsLoop<false, true>(q, tex, D, xc, n, yc, sb, tb, lb, sd, td, ld);
    else
      coordsLoop<false, false>(q, tex, D, xc, n, yc, sb, tb, lb, sd, td, ld);
    if (det != nullptr) {
      for (int i = 0; i < n; ++i)
        out[i] = sample(tex, sb[i], tb[i], lb[i]) * sample(*det, sd[i], td[i], ld[i]);
    } else {
      for (int i = 0; i < n; ++i) out[i] = sample(tex, sb[i], tb[i], lb[i]);
    }
  }

  // True if the ray through (xc, yc) hits quad q in front of the camera within its bounds; w is
  // its inverse depth there.
  static bool hits(const FrameQuad& q, float xc, float yc, float& w) {
    w = inverseDepth(q, xc, yc);
    if (!(w > 0.0f) || w > render_detail::kMaxInverseDepth) return false;
    const float inv = 1.0f / w;
    const float u = (q.ux * xc + (q.uy * yc + q.u0)) * inv + q.bu;
    const float v = (q.vx * xc + (q.vy * yc + q.v0)) * inv + q.bv;
    return u >= -render_detail::kInsideTolerance &&
           u <= q.size_u + render_detail::kInsideTolerance &&
           v >= -render_detail::kInsideTolerance && v <= q.size_v + render_detail::kInsideTolerance;
  }
};

}  // namespace ldsm::drivers::sim
