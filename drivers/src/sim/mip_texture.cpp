// Mip chain construction and a double-precision reference sampler.
#include "ldsm/drivers/sim/mip_texture.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

bool isPowerOfTwo(int n) {
  return n > 0 && (n & (n - 1)) == 0;
}

// Index i of a row/column of n texels, wrapped or clamped.
int fixIndex(int i, int n, bool wrap) {
  if (wrap) return i & (n - 1);
  return std::clamp(i, 0, n - 1);
}

int reducedSize(int n, bool wrap) {
  if (wrap) return std::max(1, n / 2);
  return n > 2 ? n / 2 + 1 : n;
}

// One reduction step: output texel k takes [1/4 1/2 1/4] of input texels 2k-1, 2k, 2k+1 along
// each axis that shrinks (an axis that keeps its size is copied).
ImageF reduce(const ImageF& in, bool wrap) {
  const int w = in.width(), h = in.height();
  const int ow = reducedSize(w, wrap), oh = reducedSize(h, wrap);
  ImageF tmp(ow, h);
  for (int y = 0; y < h; ++y) {
    const float* src = in.row(y);
    float* dst = tmp.row(y);
    for (int k = 0; k < ow; ++k) {
      if (ow == w) {
        dst[k] = src[k];
        continue;
      }
      const float a = src[fixIndex(2 * k - 1, w, wrap)];
      const float b = src[fixIndex(2 * k, w, wrap)];
      const float c = src[fixIndex(2 * k + 1, w, wrap)];
      dst[k] = (0.25f * a + 0.5f * b) + 0.25f * c;
    }
  }
  ImageF out(ow, oh);
  for (int k = 0; k < oh; ++k) {
    float* dst = out.row(k);
    if (oh == h) {
      std::copy(tmp.row(k), tmp.row(k) + ow, dst);
      continue;
    }
    const float* a = tmp.row(fixIndex(2 * k - 1, h, wrap));
    const float* b = tmp.row(fixIndex(2 * k, h, wrap));
    const float* c = tmp.row(fixIndex(2 * k + 1, h, wrap));
    for (int x = 0; x < ow; ++x) dst[x] = (0.25f * a[x] + 0.5f * b[x]) + 0.25f * c[x];
  }
  return out;
}

// The level with its padding column and row.
MipLevel makeLevel(const ImageF& img, bool wrap, double scale_u, double scale_v) {
  MipLevel level;
  level.width = img.width();
  level.height = img.height();
  level.scale_u = scale_u;
  level.scale_v = scale_v;
  level.texels.resize(level.width + 1, level.height + 1);
  for (int y = 0; y <= level.height; ++y) {
    const float* src = img.row(y < level.height ? y : (wrap ? 0 : level.height - 1));
    float* dst = level.texels.row(y);
    std::copy(src, src + level.width, dst);
    dst[level.width] = src[wrap ? 0 : level.width - 1];
  }
  return level;
}

}  // namespace

MipTexture buildMipTexture(const ImageF& base, bool wrap, double texel_size_m) {
  const int w = base.width(), h = base.height();
  if (wrap && (!isPowerOfTwo(w) || !isPowerOfTwo(h)))
    throw InputError("sim texture: a repeating texture needs power-of-two sizes, got " +
                     std::to_string(w) + "x" + std::to_string(h));
  if (!wrap && (w < 2 || h < 2))
    throw InputError("sim texture: a clamped texture needs at least 2x2 texels, got " +
                     std::to_string(w) + "x" + std::to_string(h));
  if (!(texel_size_m > 0.0)) throw InputError("sim texture: texel size must be positive");
  MipTexture t;
  t.wrap = wrap;
  t.texel_size_m = texel_size_m;
  ImageF current = base;
  double su = 1.0, sv = 1.0;
  for (;;) {
    t.levels.push_back(makeLevel(current, wrap, su, sv));
    const int cw = current.width(), ch = current.height();
    const bool done = wrap ? (cw == 1 && ch == 1) : (cw <= 2 && ch <= 2);
    if (done) break;
    if (reducedSize(cw, wrap) != cw) su *= 0.5;
    if (reducedSize(ch, wrap) != ch) sv *= 0.5;
    current = reduce(current, wrap);
  }
  return t;
}

double sampleLevelBilinear(const MipTexture& texture, int level, double s, double t) {
  const MipLevel& L = texture.levels.at(static_cast<std::size_t>(level));
  s *= L.scale_u;
  t *= L.scale_v;
  const int w = L.width, h = L.height;
  if (!texture.wrap) {
    s = std::clamp(s, 0.0, static_cast<double>(w - 1));
    t = std::clamp(t, 0.0, static_cast<double>(h - 1));
  }
  const double fs = std::floor(s), ft = std::floor(t);
  const int i = static_cast<int>(fs), j = static_cast<int>(ft);
  const double a = s - fs, b = t - ft;
  const int i0 = fixIndex(i, w, texture.wrap), i1 = fixIndex(i + 1, w, texture.wrap);
  const int j0 = fixIndex(j, h, texture.wrap), j1 = fixIndex(j + 1, h, texture.wrap);
  const double v00 = L.at(i0, j0), v10 = L.at(i1, j0), v01 = L.at(i0, j1), v11 = L.at(i1, j1);
  return (1.0 - b) * ((1.0 - a) * v00 + a * v10) + b * ((1.0 - a) * v01 + a * v11);
}

}  // namespace ldsm::drivers::sim
