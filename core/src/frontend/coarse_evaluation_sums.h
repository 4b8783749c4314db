// What one evaluation of the coarse tracker adds up over a level's warped and weighed points
// (kernels/coarse_warp.h, kernels/coarse_weigh.h), in point order: the number of points in the
// frame, the base outliers and outliers, the energy and Huber sums, and the inliers' rows
// (WarpedResiduals, compacted) for the normal equations.
//
// The energy and Huber terms are added one point at a time in float and moved into double when
// an inlier makes the count in the frame a multiple of 256 (and at the end). addBlock() takes a
// SIMD block of four points: the common block, four inliers with no move into double among them,
// adds the same terms in the same order and copies its rows as vectors; any other block goes
// point by point through addPoint(). Both give the same bits (tested).
#pragma once

#include "frontend/coarse_residuals.h"
#include "kernels/coarse_warp.h"
#include "kernels/coarse_weigh.h"
#include "math/simd/vec4f.h"

namespace ldsm {

class CoarseEvaluationSums {
 public:
  /// Writes the inliers' rows into `rows` (sized for every point of the level).
  explicit CoarseEvaluationSums(WarpedResiduals& rows) : rows_(rows) {}

  /// Adds one point that is inside the frame.
  void addPoint(const simd::CoarseWarpedPoint& wp, const simd::CoarseWeightedPoint& wt) {
    ++in_image_;
    base_outliers_ += wt.base_outlier ? 1 : 0;
    energy_ += wt.energy;
    huber_ += wt.huber;
    if (!wt.inlier) {
      ++outliers_;
      return;  // (the partial sums move into double after inliers only)
    }
    const int n = inliers_++;
    rows_.dx_fx[n] = wp.dx_fx;
    rows_.dy_fy[n] = wp.dy_fy;
    rows_.nx[n] = wp.nx;
    rows_.ny[n] = wp.ny;
    rows_.iz[n] = wp.iz;
    rows_.ref_term[n] = wp.ref_term;
    rows_.residual[n] = wp.residual;
    rows_.weight[n] = wt.weight;
    if ((in_image_ & 255) == 0) moveToDouble();
  }

  /// Adds the points of a block whose `inside` bits are set.
  void addBlock(const simd::CoarseWarp4& b, const simd::CoarseWeights4& w) {
    if (b.inside == 0xF && w.inlier == 0xF && (in_image_ & 255) < 252) {
      in_image_ += 4;
      const int o = w.base_outlier;
      base_outliers_ += (o & 1) + ((o >> 1) & 1) + ((o >> 2) & 1) + ((o >> 3) & 1);
      for (int l = 0; l < 4; ++l) {
        energy_ += w.energy[l];
        huber_ += w.huber[l];
      }
      using V = simd::Vec4;
      const int n = inliers_;  // n + 4 <= the points so far <= the rows' size
      V::load(b.dx_fx).storeu(&rows_.dx_fx[n]);
      V::load(b.dy_fy).storeu(&rows_.dy_fy[n]);
      V::load(b.nx).storeu(&rows_.nx[n]);
      V::load(b.ny).storeu(&rows_.ny[n]);
      V::load(b.iz).storeu(&rows_.iz[n]);
      V::load(b.ref_term).storeu(&rows_.ref_term[n]);
      V::load(b.residual).storeu(&rows_.residual[n]);
      V::load(w.weight).storeu(&rows_.weight[n]);
      inliers_ += 4;
      return;
    }
    for (int l = 0; l < 4; ++l) {
      if (((b.inside >> l) & 1) == 0) continue;
      addPoint({b.dx_fx[l], b.dy_fy[l], b.nx[l], b.ny[l], b.iz[l], b.ref_term[l], b.residual[l]},
               {w.energy[l], w.huber[l], w.weight[l], ((w.inlier >> l) & 1) != 0,
                ((w.base_outlier >> l) & 1) != 0});
    }
  }

  /// Moves what is left into double and sets the rows' count; call once, after the last point.
  void finish() {
    moveToDouble();
    rows_.count = inliers_;
  }

  double energy() const { return energy_sum_; }   ///< after finish()
  double huberSum() const { return huber_sum_; }  ///< after finish()
  int inImage() const { return in_image_; }
  int inliers() const { return inliers_; }
  int outliers() const { return outliers_; }
  int baseOutliers() const { return base_outliers_; }

 private:
  void moveToDouble() {
    energy_sum_ += energy_;
    huber_sum_ += huber_;
    energy_ = huber_ = 0.f;
  }

  WarpedResiduals& rows_;
  float energy_ = 0.f, huber_ = 0.f;  // partial sums
  double energy_sum_ = 0.0, huber_sum_ = 0.0;
  int in_image_ = 0, inliers_ = 0, outliers_ = 0, base_outliers_ = 0;
};

}  // namespace ldsm
