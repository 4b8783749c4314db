// The 8-pixel residual pattern around each point (offsets in pixels at the point's level),
// spread so that it covers a 5x5 neighbourhood with 8 samples, as in the DSO paper (Fig. 4).
#pragma once

namespace ldsm {

constexpr int kPatternSize = 8;
constexpr int kPatternOffsets[kPatternSize][2] = {{0, -2}, {-1, -1}, {1, -1}, {-2, 0},
                                                  {0, 0},  {2, 0},   {-1, 1}, {0, 2}};
constexpr int kPatternPadding = 2;  ///< max |offset|

}  // namespace ldsm
