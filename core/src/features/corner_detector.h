// Shi-Tomasi corners: the smaller eigenvalue of the gradient structure tensor averaged over a 5x5
// window, local maxima only, spread out by a minimum distance and kept away from the image border
// (so that an ORB descriptor patch fits around every corner).
#pragma once

#include <cstdint>
#include <vector>

#include "image/gradient_pixel.h"
#include "ldsm/image.h"

namespace ldsm {

struct Corner {
  float u, v;   ///< level-0 position, refined to sub-pixel by a parabola through the scores
  float score;  ///< min eigenvalue of the mean structure tensor, (grey levels / pixel)^2
};

struct CornerParams {
  int max_corners = 300;
  float min_score = 49.f;    ///< weaker local maxima are ignored
  float min_distance = 8.f;  ///< pixels between two kept corners (greedy, strongest first)
  int border = 16;           ///< corners lie at border <= x <= width - 1 - border (same for y)
};

class CornerDetector {
 public:
  /// Half the side of the structure-tensor window (5x5).
  static constexpr int kWindowRadius = 2;

  /// Preallocates every buffer for width x height images. Throws InputError when the size is not
  /// positive.
  CornerDetector(int width, int height);

  /// Detects up to params.max_corners corners in the level-0 gradients (size as at construction,
  /// else InputError), strongest first, into `out` (cleared; its capacity is reused). Returns the
  /// number found. Deterministic: ties are broken by position.
  int detect(ImageView<const GradientPixel> gradients, const CornerParams& params,
             std::vector<Corner>& out);

  /// Corners again from the score image of the last detect(), with other limits (count, score,
  /// spacing): the same as detect() on the same gradients, without computing the scores again.
  /// params.border must be that detect()'s border (the scores, and the zeros around them, depend
  /// on it); else, or without an earlier detect() that computed scores, InputError.
  int reselect(const CornerParams& params, std::vector<Corner>& out);

  /// The Shi-Tomasi score image of the last detect() (0 where not computed).
  ImageView<const float> scores() const { return score_.view(); }

 private:
  struct Candidate {
    float score;
    std::int32_t x, y;
  };

  void computeScores(ImageView<const GradientPixel> gradients, int border);
  void collectLocalMaxima(const CornerParams& params);
  void suppressByDistance(const CornerParams& params, std::vector<Corner>& out);

  int width_;
  int height_;
  /// Horizontal 5-sums of the per-pixel tensor for the last kRingRows rows, per row the xx, xy
  /// and yy planes of width_ floats (row y in slot y % kRingRows).
  static constexpr int kRingRows = 2 * kWindowRadius + 2;
  /// Horizontal sums of row y into its ring slot.
  void rowSums(ImageView<const GradientPixel> g, int y, int x_lo, int x_hi);
  float* ringRow(int y, int plane) {
    return ring_.data() + (static_cast<std::size_t>(y % kRingRows) * 3 + plane) * width_;
  }
  std::vector<float> ring_;
  std::vector<float> column_acc_;  ///< vertical sums: xx, xy and yy planes of width_ floats
  Image<float> score_;
  std::vector<Candidate> candidates_;
  int scores_border_ = -1;  ///< border of the scores in score_, -1 when none were computed
};

}  // namespace ldsm
