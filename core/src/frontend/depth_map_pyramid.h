// Sparse inverse-depth maps of the tracking reference over the pyramid, and the point lists the
// coarse tracker iterates over (DSO's "coarse depth" of the newest keyframe).
//
// Level 0 is filled by splatting the window's points projected into the reference (inverse depth
// averaged with the points' weights at the nearest pixel; where the points of a map keyframe
// brought back into the window, seen from elsewhere, and the window's own points meet at a pixel
// on both sides of a depth discontinuity, only the nearer surface is kept: the farther points are
// occluded in the reference); level l+1 is the weighted average of
// the 2x2 children at level l; then every level is dilated once (an empty pixel takes the
// weighted average of its known neighbours: diagonal ones on levels 0 and 1, the 4-neighbourhood
// on coarser levels; not across depth discontinuities), so that coarse levels become dense enough
// to track with. Every known pixel becomes a reference point (x, y, inverse depth, reference
// intensity, squared gradient).
#pragma once

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "camera/pyramid_camera.h"
#include "frontend/pixel_sums.h"
#include "image/image_pyramid.h"
#include "ldsm/image.h"
#include "model/depth_point.h"

namespace ldsm {

/// The reference points of one level as a struct of arrays. The arrays grow to the largest point
/// count seen so far; only the first `count` entries are valid.
struct LevelPoints {
  std::vector<float> x;          ///< pixel column at this level (integer valued)
  std::vector<float> y;          ///< pixel row at this level (integer valued)
  std::vector<float> idepth;     ///< inverse depth in the reference frame
  std::vector<float> intensity;  ///< reference intensity at (x, y)
  std::vector<float> grad_sq;    ///< squared reference gradient dx^2 + dy^2 at (x, y)
  int count = 0;
};

/// The per-level sums a build splats into and dilates: scratch that matters only while
/// DepthMapPyramid::build runs. Level 0 keeps cells for the pixels that have sums alone
/// (PixelSums), the coarser levels, which dilation makes dense, a plane each (DensePixelSums):
/// 1.9 MB at 1232x368 where dense planes on every level took 5.3 MB, with their results bit for
/// bit. Pyramids built on one thread can share one canvas (the mapping stage builds every
/// tracking reference into its own), so that the coarse trackers between builds hold only their
/// point lists.
class DepthMapCanvas {
 public:
  /// A pixel the dilation fills (or, rejected, leaves empty) and its neighbours' sums.
  struct Fill {
    int index;
    float sum, weight;
  };

  /// A canvas for width x height images and `levels` levels. Throws InputError/ConfigError like
  /// ImagePyramid for bad sizes.
  DepthMapCanvas(int width, int height, int levels);

  int levels() const { return static_cast<int>(sizes_.size()); }
  int width(int level) const { return sizes_[level].first; }
  int height(int level) const { return sizes_[level].second; }
  /// Inverse depth of pixel (x, y) of a level as the last build into this canvas left it (after
  /// dilation); 0 where unknown.
  float idepthAt(int level, int x, int y) const;
  /// Bytes of the cells and lists.
  std::size_t bytes() const;

 private:
  friend class DepthMapPyramid;

  std::vector<std::pair<int, int>> sizes_;  ///< per level, width and height
  /// The weighted sums, sum = sum(w * idepth), weight = sum(w); 0 weight or no cell = unknown.
  /// Level 0's cells also say whether the pixel's surface came from map keyframes' points
  /// (DepthPoint::from_map).
  PixelSums level0_;
  std::vector<DensePixelSums> coarse_;  ///< levels 1, 2, ...
  /// Per level, the pixels (y * width + x) of non-zero weight: a window's points cover a few
  /// percent of the image, so downsampling, dilating and extracting visit only these and their
  /// neighbours, never the whole level.
  std::vector<std::vector<int>> known_;
  std::vector<Fill> fills_;  ///< scratch of dilate()
};

class DepthMapPyramid {
 public:
  /// Sizes the point lists' levels for width x height images and `levels` levels (the sizes of
  /// ImagePyramid); the sums are a DepthMapCanvas, the caller's or, when build() is given
  /// none, one this pyramid allocates at its first such build. Throws InputError/ConfigError like
  /// ImagePyramid for bad sizes. Dilation leaves a pixel empty when its known neighbours' inverse
  /// depths differ by more than the factor `max_idepth_ratio` (a depth discontinuity), and
  /// splatting keeps only the nearer of a map point (DepthPoint::from_map) and the window's points
  /// at one pixel whose inverse depths differ by more than that factor.
  DepthMapPyramid(int width, int height, int levels, float max_idepth_ratio = 1.25f);

  /// Rebuilds every level from `count` points and the reference pyramid (which must have at
  /// least levels() levels of the constructed size; InputError otherwise), splatting into
  /// `canvas` (of the same sizes; InputError otherwise). Points outside the image or with a
  /// non-finite or non-positive inverse depth or weight are skipped. Returns the number of valid
  /// points (occluded ones included). Allocates only when a level gets more points than ever
  /// before.
  int build(const DepthPoint* points, std::size_t count, const ImagePyramid& reference,
            DepthMapCanvas& canvas);
  /// The same into this pyramid's own canvas (allocated at the first call).
  int build(const DepthPoint* points, std::size_t count, const ImagePyramid& reference);

  int levels() const { return static_cast<int>(points_.size()); }
  int width(int level) const { return width_ >> level; }
  int height(int level) const { return height_ >> level; }
  const LevelPoints& points(int level) const { return points_[level]; }
  /// Inverse depth of pixel (x, y) of a level after dilation; 0 where unknown. Reads the canvas
  /// of the last build, as that canvas holds it now (0 everywhere before any build).
  float idepthAt(int level, int x, int y) const;
  /// Points rejected by the last build() (outside the image, bad inverse depth or weight).
  int rejectedPoints() const { return rejected_; }
  /// Bytes this pyramid holds: the point lists and its own canvas, if it has one.
  std::size_t bytes() const;

 private:
  void splat(const DepthPoint* points, std::size_t count, DepthMapCanvas& c);
  void downsample(int level, DepthMapCanvas& c) const;
  void dilate(int level, bool diagonal, DepthMapCanvas& c) const;
  void extract(int level, const ImagePyramid& reference, DepthMapCanvas& c);

  int width_;
  int height_;
  std::vector<LevelPoints> points_;
  float max_idepth_ratio_;
  int rejected_ = 0;
  std::unique_ptr<DepthMapCanvas> own_canvas_;
  const DepthMapCanvas* last_canvas_ = nullptr;
};

}  // namespace ldsm
