// Point selection for a new keyframe, after DSO's "Point Selection" (Engel et al., PAMI 2017):
// pixels with a gradient well above their region's median, spread evenly over the image by an
// adaptive grid, plus a share of Shi-Tomasi corners that later carry ORB descriptors.
//
//  * The regional threshold is the median of |grad I| in 32x32 blocks plus min_gradient, smoothed
//    over 3x3 blocks (GradientThresholdMap).
//  * The image is tiled into cells of d x d pixels. Each cell contributes at most its best level-0
//    pixel above threshold; a 2d x 2d block where no cell found one tries level 1 (threshold x
//    0.75), a 4d x 4d block with nothing at all tries level 2 (x 0.75^2). Coarse picks are mapped
//    to their strongest level-0 child pixel. Among the candidates of a cell, the score favours
//    the gradient component along a direction that changes from cell to cell (a fixed hash), so
//    that the selected points do not all share the dominant edge direction.
//  * d is adapted (a few passes, d <- d sqrt(n / target)) until the count is close to the target;
//    an excess is thinned out uniformly in grid order.
//  * Corners are chosen first; no other point is taken within 2 pixels of a corner.
// Everything is deterministic and, after construction, free of heap allocation.
#pragma once

#include <array>
#include <vector>

#include "features/corner_detector.h"
#include "features/gradient_threshold_map.h"
#include "image/image_pyramid.h"
#include "ldsm/config.h"
#include "ldsm/image.h"

namespace ldsm {

struct SelectedPixel {
  float u, v;      ///< level-0 pixel position (integer for gradient points, sub-pixel for corners)
  int level;       ///< pyramid level the point was found on (0, 1 or 2)
  bool is_corner;  ///< Shi-Tomasi corner (gets an ORB descriptor)
  float score;     ///< |grad I| at `level` for gradient points, Shi-Tomasi score for corners
};

class PixelSelector {
 public:
  /// Gradient points keep this distance (pixels) from the image border.
  static constexpr int kBorder = 4;
  /// Corners keep this distance from the border: ORB's patch radius.
  static constexpr int kCornerBorder = 16;
  /// Minimum distance (pixels) between two corners.
  static constexpr float kCornerMinDistance = 8.f;
  /// No gradient point within this Chebyshev radius of a corner's (rounded) pixel. Any pixel
  /// outside it is more than 2 pixels (Euclidean) from the sub-pixel corner.
  static constexpr int kCornerExclusionRadius = 2;
  /// Threshold factor per coarser level.
  static constexpr float kCoarseThresholdFactor = 0.75f;
  /// Most grid passes per select().
  static constexpr int kMaxPasses = 4;
  /// A pass within this relative distance of the target ends the adaptation.
  static constexpr float kCountTolerance = 0.05f;

  /// Preallocates for width x height keyframes. Throws ConfigError when a config value is out of
  /// range and InputError when the size is not positive.
  PixelSelector(int width, int height, const PointSelectionConfig& config);

  /// What detectCorners() is asked for: up to max_corners corners with score >= min_score.
  struct CornerLimits {
    int max_corners = 0;
    float min_score = 0.f;
  };

  /// Selects about points_per_keyframe * density_factor pixels of the pyramid's level 0 (of which
  /// corner_fraction are corners, listed first) into `out` (cleared; capacity reused). Returns the
  /// count. No pixel within clipped_margin of one of the pyramid's clipped pixels is selected.
  /// Throws InputError when the pyramid's size differs from the selector's or density_factor is not
  /// a positive finite number.
  /// With `more_out`, also the corners detectCorners(pyramid, more.max_corners, more.min_score,
  /// *more_out) gives, with the corner scores computed once for both.
  int select(const ImagePyramid& pyramid, float density_factor, std::vector<SelectedPixel>& out,
             const CornerLimits& more, std::vector<Corner>* more_out);
  int select(const ImagePyramid& pyramid, float density_factor, std::vector<SelectedPixel>& out) {
    return select(pyramid, density_factor, out, CornerLimits{}, nullptr);
  }

  /// More corners than the odometry wants, for place recognition: up to `max_corners` Shi-Tomasi
  /// corners of the pyramid's level 0 with score >= min_score (same spacing and border as the
  /// selection's corners), strongest first, into `out`. Reuses the selector's detector buffers;
  /// does not change the last select()'s results.
  int detectCorners(const ImagePyramid& pyramid, int max_corners, float min_score,
                    std::vector<Corner>& out);

  /// Cell size d (level-0 pixels) of the pass that was used by the last select().
  float lastCellSize() const { return last_cell_size_; }
  /// Number of corners in the last select().
  int lastCornerCount() const { return static_cast<int>(corners_.size()); }
  const GradientThresholdMap& thresholds() const { return thresholds_; }

 private:
  struct LevelGrid {
    ImageView<const GradientPixel> grad;
    float threshold_factor_sq;
  };

  /// Marks every pixel within config.clipped_margin (Chebyshev) of a clipped pixel.
  void markNearClipped(ImageView<const std::uint8_t> clipped);
  /// Drops the corners near clipped pixels.
  void dropCornersNearClipped();
  void blockAroundCorners();
  /// Sets kBelowThreshold in blocked_ where a level-0 pixel of the grid region does not exceed
  /// its gradient threshold: every grid pass then tests one byte instead of the threshold map.
  void markBelowThreshold(ImageView<const GradientPixel> grad0);
  int gridPass(float cell, std::vector<SelectedPixel>& picks) const;
  bool pickLevel0(int x0, int x1, int y0, int y1, unsigned cell_hash,
                  std::vector<SelectedPixel>& picks) const;
  bool pickCoarse(int level, int x0, int x1, int y0, int y1, unsigned cell_hash,
                  std::vector<SelectedPixel>& picks) const;

  int width_;
  int height_;
  PointSelectionConfig config_;
  GradientThresholdMap thresholds_;
  CornerDetector corner_detector_;
  std::vector<Corner> corners_;
  /// Per level-0 pixel: kNearCorner where no gradient point may be taken, kBelowThreshold where
  /// the gradient is too weak for a level-0 pick (coarse levels test only kNearCorner).
  Image<std::uint8_t> blocked_;
  std::vector<float> magnitude_sq_;  ///< scratch of markBelowThreshold: one row's |grad I|^2
  static constexpr std::uint8_t kNearCorner = 1;
  static constexpr std::uint8_t kBelowThreshold = 2;
  /// 1 near a clipped pixel: a grid cell whose best pixel lies there gives no point, since its
  /// gradient comes from the clipping (the next best one in the cell mostly too).
  Image<std::uint8_t> near_clipped_;
  /// The horizontal pass of markNearClipped(): a ring of 2 clipped_margin + 1 rows.
  std::vector<std::uint8_t> near_clipped_rows_;
  std::vector<int> last_clipped_;  ///< per row: -1 when it has no clipped pixel
  std::array<LevelGrid, 3> levels_{};
  int num_levels_ = 0;
  std::array<float, 16> dir_x_{};  ///< the fixed set of score directions
  std::array<float, 16> dir_y_{};
  std::vector<SelectedPixel> pass_picks_;
  std::vector<SelectedPixel> best_picks_;
  float last_cell_size_ = 0.f;
};

}  // namespace ldsm
