// The coarse tracker's warp of its reference points into a frame: per point (x, y, inverse depth,
// reference intensity) of a pyramid level,
//   p = K R K^-1 (x, y, 1) + K t idepth,  (u, v) = (p_x, p_y) / p_z,
// inside when p_z > 0 and (u, v) lies `margin` inside the bilinear region; then the frame's
// (intensity, dx, dy) at (u, v) (bilinear) and what the residual and its Jacobian need:
//   dx_fx = dx fx, dy_fy = dy fy, nx = u / fx - cx / fx, ny likewise, iz = idepth / p_z,
//   ref_term = scale (I_ref - b_ref), residual = I - ref_term - b.
// With kRadial, the images carry the residual radial distortion k of the calibration refinement
// (camera/radial_distortion.h): (x, y) are then the pinhole pixels of the reference rays, the
// frame is sampled at the distorted pixel K D(n), n = (nx, ny), D(n) = n (1 + k |n|^2), and the
// gradient moves through D's Jacobian: (dx_fx, dy_fy) = (dx fx, dy fy) (f I + 2 k n n^T) with
// f = 1 + k |n|^2, so that the Jacobian rows (coarse_residuals.h) stay those of the pinhole n.
// Rays beyond the radius where the distortion turns back (1 + 3 k |n|^2 <= 0, k < 0) are outside.
// warpCoarse4<V> does four points per vector (one 2x2 block load per point, transposed into
// intensity, dx and dy rows); reference::warpCoarsePoint is the per-point formulation. Both use
// the same operations in the same order (no fused multiply-add: -ffp-contract=off), so their
// results are bit-identical, which the tests check for every vector type.
#pragma once

#include <cstdint>
#include <type_traits>

#include "image/gradient_pixel.h"
#include "image/interpolation.h"
#include "ldsm/image.h"
#include "math/simd/vec4f.h"

namespace ldsm {
namespace simd {

/// What the points of one level share.
struct CoarseWarpParams {
  float KRKi[9] = {};  ///< K R K^-1, row-major
  float Kt[3] = {};    ///< K t
  float fx = 1.f, fy = 1.f, fxi = 1.f, fyi = 1.f, cxi = 0.f, cyi = 0.f;
  float cx = 0.f, cy = 0.f;  ///< principal point (pixels), used with kRadial only
  float radial_k = 0.f;      ///< residual radial distortion, used with kRadial only
  float margin = 2.f;        ///< points stay this far inside the bilinear region (pixels)
  float scale = 1.f;         ///< affine transfer reference -> frame
  float b_ref = 0.f, b = 0.f;
  ImageView<const GradientPixel> image;  ///< the frame's level
};

/// One point's warp.
struct CoarseWarpedPoint {
  float dx_fx, dy_fy, nx, ny, iz, ref_term, residual;
};

/// Four points' warps as rows; `inside` has bit i set when point i is inside.
struct alignas(16) CoarseWarp4 {
  float dx_fx[4], dy_fy[4], nx[4], ny[4], iz[4], ref_term[4], residual[4];
  int inside = 0;
};

namespace reference {

/// Warps one point; false when it is behind the camera or outside the frame (with margin).
template <bool kRadial = false>
[[gnu::always_inline]] inline bool warpCoarsePoint(const CoarseWarpParams& w, float x, float y,
                                                   float idepth, float ref_intensity,
                                                   CoarseWarpedPoint& out) {
  const float* K = w.KRKi;
  const float px = K[0] * x + (K[1] * y + K[2]) + w.Kt[0] * idepth;
  const float py = K[3] * x + (K[4] * y + K[5]) + w.Kt[1] * idepth;
  const float pz = K[6] * x + (K[7] * y + K[8]) + w.Kt[2] * idepth;
  if (!(pz > 0.f)) return false;
  const float zi = 1.f / pz;
  const float u = px * zi;
  const float v = py * zi;
  if constexpr (kRadial) {
    const float nx = w.fxi * u + w.cxi;
    const float ny = w.fyi * v + w.cyi;
    const float r2 = nx * nx + ny * ny;
    const float f = 1.f + w.radial_k * r2;
    // Beyond the radius where the distortion turns back (k < 0) a ray has no image.
    if (!(1.f + (3.f * w.radial_k) * r2 > 0.f)) return false;
    const float ud = w.fx * (nx * f) + w.cx;
    const float vd = w.fy * (ny * f) + w.cy;
    if (!isInsideForBilinear(w.image, ud, vd, w.margin)) return false;
    const GradientPixel g = interpolateBilinear(w.image, ud, vd);
    const float gx = g.dx * w.fx, gy = g.dy * w.fy;
    const float k2 = 2.f * w.radial_k;
    const float cross = k2 * (nx * ny);
    out.dx_fx = gx * (f + k2 * (nx * nx)) + gy * cross;
    out.dy_fy = gx * cross + gy * (f + k2 * (ny * ny));
    out.nx = nx;
    out.ny = ny;
    out.iz = idepth * zi;
    out.ref_term = w.scale * (ref_intensity - w.b_ref);
    out.residual = g.intensity - out.ref_term - w.b;
    return true;
  } else {
    if (!isInsideForBilinear(w.image, u, v, w.margin)) return false;
    const GradientPixel g = interpolateBilinear(w.image, u, v);
    out.dx_fx = g.dx * w.fx;
    out.dy_fy = g.dy * w.fy;
    out.nx = w.fxi * u + w.cxi;
    out.ny = w.fyi * v + w.cyi;
    out.iz = idepth * zi;
    out.ref_term = w.scale * (ref_intensity - w.b_ref);
    out.residual = g.intensity - out.ref_term - w.b;
    return true;
  }
}

}  // namespace reference

namespace detail {

/// (intensity, dx, dy, -) at the 2x2 block with top-left pixel (x, y), weights from lane K, summed
/// in interpolateBilinear's order ((w00 p00 + w10 p10) + w01 p01) + w11 p11 (pattern_sampling.h's
/// bilinearPixel sums the columns first: the same loads, another rounding).
template <class V, int K>
inline V coarseBilinear(const ImageView<const GradientPixel>& img, std::int32_t x, std::int32_t y,
                        V w00, V w10, V w01, V w11) {
  const float* p = &img.data[static_cast<std::ptrdiff_t>(y) * img.stride + x].intensity;
  const float* q = p + 3 * img.stride;
  const V p0 = V::loadu(p) * broadcast<K>(w00);
  const V p1 = shiftDown1(V::loadu(p + 2)) * broadcast<K>(w10);
  const V q0 = V::loadu(q) * broadcast<K>(w01);
  const V q1 = shiftDown1(V::loadu(q + 2)) * broadcast<K>(w11);
  return ((p0 + p1) + q0) + q1;
}

}  // namespace detail

/// Warps the four points x[0..3], ... into `out` (every row written when one is inside; lanes
/// outside hold unspecified values).
template <class V, bool kRadial = false>
[[gnu::always_inline]] inline void warpCoarse4(const CoarseWarpParams& w, const float* x,
                                               const float* y, const float* idepth,
                                               const float* ref_intensity, CoarseWarp4& out) {
  const float* K = w.KRKi;
  const V X = V::loadu(x), Y = V::loadu(y), D = V::loadu(idepth);
  const V px = V::set1(K[0]) * X + (V::set1(K[1]) * Y + V::set1(K[2])) + V::set1(w.Kt[0]) * D;
  const V py = V::set1(K[3]) * X + (V::set1(K[4]) * Y + V::set1(K[5])) + V::set1(w.Kt[1]) * D;
  const V pz = V::set1(K[6]) * X + (V::set1(K[7]) * Y + V::set1(K[8])) + V::set1(w.Kt[2]) * D;
  const V one = V::set1(1.f);
  const V zi = one / pz;
  const V pu = px * zi;  // the pinhole pixel
  const V pv = py * zi;
  V u = pu, v = pv;                           // the pixel sampled
  V nx = V::zero(), ny = V::zero(), f = one;  // n and f: with kRadial
  V r2 = V::zero();
  if constexpr (kRadial) {
    nx = V::set1(w.fxi) * pu + V::set1(w.cxi);
    ny = V::set1(w.fyi) * pv + V::set1(w.cyi);
    r2 = nx * nx + ny * ny;
    f = one + V::set1(w.radial_k) * r2;
    u = V::set1(w.fx) * (nx * f) + V::set1(w.cx);
    v = V::set1(w.fy) * (ny * f) + V::set1(w.cy);
  }
  const V lo = V::set1(w.margin);
  const V u_hi = V::set1(static_cast<float>(w.image.width - 1) - w.margin);
  const V v_hi = V::set1(static_cast<float>(w.image.height - 1) - w.margin);
  // Ordered comparisons: NaN fails them all.
  typename V::Mask inside = (pz > V::zero()) & (u >= lo) & (v >= lo) & (u < u_hi) & (v < v_hi);
  if constexpr (kRadial)  // inside the radius where the distortion turns back (k < 0)
    inside = inside & (one + V::set1(3.f * w.radial_k) * r2 > V::zero());
  out.inside = laneBits(inside);
  if (out.inside == 0) return;
  // Lanes outside are truncated at 0 instead (their u, v may be anything, NaN included).
  const V u_in = select(inside, u, V::zero());
  const V v_in = select(inside, v, V::zero());
  alignas(16) std::int32_t ix[4], iy[4];
  const V fx = u_in - truncate(u_in, ix);  // u >= margin >= 0 where inside: the floor
  const V fy = v_in - truncate(v_in, iy);
  const V w00 = (one - fx) * (one - fy);
  const V w10 = fx * (one - fy);
  const V w01 = (one - fx) * fy;
  const V w11 = fx * fy;
  const auto pixel = [&](auto lane) {
    constexpr int k = decltype(lane)::value;
    return (out.inside >> k) & 1
               ? detail::coarseBilinear<V, k>(w.image, ix[k], iy[k], w00, w10, w01, w11)
               : V::zero();
  };
  V I = pixel(std::integral_constant<int, 0>{});
  V dx = pixel(std::integral_constant<int, 1>{});
  V dy = pixel(std::integral_constant<int, 2>{});
  V unused = pixel(std::integral_constant<int, 3>{});
  transpose4(I, dx, dy, unused);
  if constexpr (kRadial) {
    const V gx = dx * V::set1(w.fx), gy = dy * V::set1(w.fy);
    const V k2 = V::set1(2.f * w.radial_k);
    const V cross = k2 * (nx * ny);
    (gx * (f + k2 * (nx * nx)) + gy * cross).store(out.dx_fx);
    (gx * cross + gy * (f + k2 * (ny * ny))).store(out.dy_fy);
    nx.store(out.nx);
    ny.store(out.ny);
  } else {
    (dx * V::set1(w.fx)).store(out.dx_fx);
    (dy * V::set1(w.fy)).store(out.dy_fy);
    (V::set1(w.fxi) * u + V::set1(w.cxi)).store(out.nx);
    (V::set1(w.fyi) * v + V::set1(w.cyi)).store(out.ny);
  }
  (D * zi).store(out.iz);
  const V ref = V::set1(w.scale) * (V::loadu(ref_intensity) - V::set1(w.b_ref));
  ref.store(out.ref_term);
  (I - ref - V::set1(w.b)).store(out.residual);
}

}  // namespace simd
}  // namespace ldsm
