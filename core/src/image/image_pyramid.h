// An image pyramid with per-level gradients, preallocated once for a fixed image size so that
// building it for each new frame touches no heap memory.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "image/compact_plane.h"
#include "image/gradient_pixel.h"
#include "ldsm/image.h"

namespace ldsm {

/// Levels 0..levels-1 of a float image: level 0 is the input, level l+1 the 2x2 average of level l
/// (size floor(w/2) x floor(h/2); an odd last row or column is dropped). Each level holds the
/// packed (intensity, dx, dy) plane with central-difference gradients that are zero on the
/// one-pixel image border, and optionally dx^2 + dy^2. There is no separate intensity plane (it
/// would repeat the packed plane's first channel): interpolateIntensity() and copyIntensity() read
/// the intensities.
///
/// Level coordinates: pixel centre x at level l+1 is the centre of pixels 2x and 2x+1 at level l,
/// i.e. x_(l+1) = (x_l + 0.5) / 2 - 0.5.
///
/// Level 0 also carries a clipping mask: the pixels where the camera's raw value was saturated
/// (see markClipped()). build() clears it.
/// An image handed over row by row, so that a pyramid can be built without the whole image in
/// memory: row(y) is asked for in order y = 0, 1, ..., and the row it returns (level-0 width
/// floats) must stay valid until row(y + 3) is asked for (a ring of three rows suffices).
class ImageRows {
 public:
  virtual ~ImageRows() = default;
  virtual const float* row(int y) = 0;
};

class ImagePyramid {
 public:
  /// Largest supported number of levels.
  static constexpr int kMaxLevels = 16;

  /// Allocates all levels for width x height input images. Throws InputError when the size is not
  /// positive and ConfigError when levels is outside [1, maxLevels(width, height)].
  ImagePyramid(int width, int height, int levels, bool with_grad_mag_sq = true);

  /// The number of levels a width x height image supports (every level at least 1x1, at most
  /// kMaxLevels); 0 when the size is not positive.
  static int maxLevels(int width, int height);

  /// Fills every level from `image` (any stride). Allocates nothing (unless compacted: the planes
  /// are allocated again first). Throws InputError when the image size differs from the one
  /// given at construction or the view is empty.
  void build(ImageView<const float> image);
  /// The same from the image's rows (of the size given at construction), every float as
  /// build(ImageView) makes it from the whole image.
  void build(ImageRows& rows);
  /// build(rows) and markClippedFromIntensity(clipped_level) in one pass over the rows: the mask
  /// from each row while it is at hand (the same mask). A level of +infinity (or NaN) marks
  /// nothing (as build(rows), which leaves the mask all 0).
  void build(ImageRows& rows, float clipped_level);

  int levels() const { return static_cast<int>(sizes_.size()); }
  int width(int level) const { return sizes_[level].first; }
  int height(int level) const { return sizes_[level].second; }
  bool hasGradMagSq() const { return !grad_mag_sq_.empty(); }

  /// Packed (intensity, dx, dy) plane of a level. Throws std::logic_error after compact()
  /// (level0() reads level 0 then).
  ImageView<const GradientPixel> gradients(int level) const {
    requireFull("gradients", level);
    return gradients_[level].view();
  }
  /// Level 0 as the target of residuals: the packed float plane, or after compact() its
  /// intensities alone (or the 16-bit plane).
  Level0View level0() const {
    if (intensity0_taken_)
      throw std::logic_error("image pyramid: level 0 was handed on (takeIntensity0)");
    Level0View v;
    v.width = width(0);
    v.height = height(0);
    if (!compact0_.empty())
      v.compact = compact0_.view();
    else if (compacted_)
      v.intensity.pixels = intensity0_.view();
    else
      v.full = gradients_[0].view();
    return v;
  }
  /// Copies a level's intensities (the packed plane's first channel) into `out`; level 0 also
  /// after compact() (then rounded to the 16-bit plane's step when it went there).
  void copyIntensity(int level, ImageF& out) const;
  /// Level 0's intensities into `out` as copyIntensity(0, out) gives them, moved instead of
  /// copied when the compacted pyramid holds them alone (a keyframe leaving the window hands its
  /// image on to be described); level 0 can then no longer be read until the next build().
  void takeIntensity0(ImageF& out);
  /// Marks the level-0 pixels where `raw` (the camera's raw values, in the pyramid's geometry) is
  /// >= `level` as clipped. Allocates nothing. Throws InputError when the size differs.
  void markClipped(ImageView<const float> raw, float level);
  /// The same from the raw values' rows (of the level-0 size).
  void markClipped(ImageRows& raw, float level);
  /// markClipped() where the raw values are the intensities build() was given (no photometric
  /// correction): from level 0's own intensities. The reference of build(rows, level), which the
  /// frames take (tests).
  void markClippedFromIntensity(float level);
  /// Level-0 clipping mask: 1 where the raw value was saturated, else 0. Throws std::logic_error
  /// once compacted.
  ImageView<const std::uint8_t> clipped() const {
    requireFull("clipping mask", 0);
    return clipped_.view();
  }

  /// dx^2 + dy^2 of a level; an empty view when built without it.
  ImageView<const float> gradMagSq(int level) const {
    if (hasGradMagSq()) requireFull("|gradient|^2", level);
    return hasGradMagSq() ? grad_mag_sq_[level].view() : ImageView<const float>();
  }

  /// Frees every plane but the level-0 intensities: all a keyframe needs once it is no longer
  /// the newest (it is then only the target image of the window's residuals, and copyIntensity()
  /// gives the image it is described by when it leaves). level0() then reads the intensities
  /// alone, and makes each pixel's gradients again with the arithmetic they were stored with
  /// (IntensityPlaneView: the same values bit for bit): with 5 levels and without |gradient|^2,
  /// 4 of 17 bytes per level-0 pixel are kept. With `level0_16bit`, the intensities go into
  /// 16-bit fixed point instead (CompactPlane: steps of 1/128 grey level for values up to 255;
  /// 2 bytes per pixel; the gradients are those of the rounded values); a level 0 with a
  /// non-finite value then keeps its float intensities. expand() allocates the planes again
  /// (contents undefined until the next build()).
  void compact(bool level0_16bit = false);
  void expand();
  bool compacted() const { return compacted_; }
  /// Bytes the planes hold now.
  std::size_t bytes() const;

 private:
  void computeGradMagSq(int level);
  void allocatePlanes();
  void requireFull(const char* plane, int level) const {
    if (compacted_)
      throw std::logic_error(std::string("image pyramid: the ") + plane + " of level " +
                             std::to_string(level) + " was freed (compacted keyframe)");
  }

  std::vector<std::pair<int, int>> sizes_;  ///< width, height per level
  bool with_grad_mag_sq_ = true;
  bool compacted_ = false;
  bool intensity0_taken_ = false;  ///< takeIntensity0() moved level 0 out

  /// Three rows of a coarser level's intensities while it is built.
  std::vector<float> rows_;
  std::vector<Image<GradientPixel>> gradients_;
  std::vector<ImageF> grad_mag_sq_;
  Image<std::uint8_t> clipped_;
  /// Level 0 once compacted with 16-bit images (empty before, or when it held a non-finite value).
  CompactPlane compact0_;
  /// Level 0's intensities once compacted without 16-bit images (empty before).
  ImageF intensity0_;
};

}  // namespace ldsm
