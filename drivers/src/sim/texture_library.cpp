// Procedural albedo patterns with corners, edges and smooth areas: plaster, brick, floor tiles,
// wood planks, ceiling panels, a noisy checker, blobs and concrete. Each is baked once per scene
// at 2x2 samples per texel (box-filtered edges), then mip-mapped.
#include "texture_library.h"

#include <cmath>
#include <utility>

#include "procedural.h"

namespace ldsm::drivers::sim {
namespace {

constexpr int N = kLibraryTextureSize;
constexpr double kN = static_cast<double>(N);

// Integer cell index of coordinate x in cells of `cell` texels.
int cellOf(double x, double cell) {
  return static_cast<int>(std::floor(x / cell));
}

std::uint32_t u32(int v) {
  return static_cast<std::uint32_t>(v);
}

// Bakes f(x, y) (texel coordinates, repeating every N) at 2x2 samples per texel.
// `smooth` is evaluated once per texel at its centre and passed to f as its third argument.
template <typename Smooth, typename Pattern>
ImageF bake(const Smooth& smooth, const Pattern& f) {
  ImageF img(N, N);
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; ++x) {
      const double cx = static_cast<double>(x), cy = static_cast<double>(y);
      const double s = smooth(cx, cy);
      double sum = 0.0;
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i)
          sum += f(wrapCoord(cx + (static_cast<double>(i) - 0.5) * 0.5, kN),
                   wrapCoord(cy + (static_cast<double>(j) - 0.5) * 0.5, kN), s);
      const double v = 0.25 * sum;
      img(x, y) = static_cast<float>(v < 0.02 ? 0.02 : (v > 0.98 ? 0.98 : v));
    }
  }
  return img;
}

ImageF plaster(std::uint32_t seed) {
  FractalNoise fbm(N, 4, 4, 6, 0.55, hash32(seed, 1));
  PeriodicNoise stains(6, 6, hash32(seed, 2));
  return bake([&](double x, double y) { return fbm.at(x, y); },
              [&](double x, double y, double s) {
                const double stain = smoothstep(0.62, 0.68, stains.at(x * 6.0 / kN, y * 6.0 / kN));
                return 0.66 + 0.45 * (s - 0.5) - 0.16 * stain;
              });
}

ImageF brick(std::uint32_t seed) {
  FractalNoise fbm(N, 16, 16, 4, 0.5, hash32(seed, 3));
  constexpr double kW = 64.0, kH = 16.0, kMortar = 2.0;
  return bake([&](double x, double y) { return fbm.at(x, y); },
              [&](double x, double y, double s) {
                const int row = cellOf(y, kH);
                const double xs = wrapCoord(x + ((row & 1) ? kW / 2 : 0.0), kN);
                const int col = cellOf(xs, kW);
                const bool mortar = wrapCoord(xs, kW) < kMortar || wrapCoord(y, kH) < kMortar;
                if (mortar) return 0.78 + 0.1 * (s - 0.5);
                const double albedo = 0.28 + 0.38 * hashUnit(u32(row), u32(col), seed);
                return albedo + 0.25 * (s - 0.5);
              });
}

ImageF floorTiles(std::uint32_t seed) {
  FractalNoise fbm(N, 8, 8, 5, 0.6, hash32(seed, 4));
  PeriodicNoise speckle(256, 256, hash32(seed, 5));
  constexpr double kTile = 64.0, kGrout = 3.0;
  return bake([&](double x,
                  double y) { return fbm.at(x, y) + 0.35 * (speckle.at(x * 0.5, y * 0.5) - 0.5); },
              [&](double x, double y, double s) {
                if (wrapCoord(x, kTile) < kGrout || wrapCoord(y, kTile) < kGrout)
                  return 0.18 + 0.05 * s;
                const double albedo =
                    0.32 + 0.42 * hashUnit(u32(cellOf(x, kTile)), u32(cellOf(y, kTile)), seed);
                return albedo + 0.22 * (s - 0.5);
              });
}

ImageF wood(std::uint32_t seed) {
  // Grain: noise stretched along x (planks run along x).
  FractalNoise grain(N, 4, 64, 3, 0.5, hash32(seed, 6));
  FractalNoise blotch(N, 4, 4, 3, 0.5, hash32(seed, 7));
  constexpr double kPlank = 32.0, kSeam = 1.5;
  return bake([&](double x, double y) { return 0.7 * grain.at(x, y) + 0.3 * blotch.at(x, y); },
              [&](double x, double y, double s) {
                const int plank = cellOf(y, kPlank);
                // Planks of 128 or 256 texels, shifted per row.
                const double len = hashUnit(u32(plank), 11, seed) < 0.5 ? 128.0 : 256.0;
                const double shift = std::floor(hashUnit(u32(plank), 12, seed) * 8.0) * 64.0;
                const double xs = wrapCoord(x + shift, kN);
                if (wrapCoord(y, kPlank) < kSeam || wrapCoord(xs, len) < kSeam) return 0.12;
                const double tone = 0.35 + 0.25 * hashUnit(u32(plank), u32(cellOf(xs, len)), seed);
                return tone + 0.45 * (s - 0.5);
              });
}

ImageF ceilingPanels(std::uint32_t seed) {
  FractalNoise fbm(N, 8, 8, 3, 0.5, hash32(seed, 8));
  constexpr double kPanel = 128.0, kLine = 3.0, kDot = 8.0;
  return bake([&](double x, double y) { return fbm.at(x, y); },
              [&](double x, double y, double s) {
                if (wrapCoord(x, kPanel) < kLine || wrapCoord(y, kPanel) < kLine) return 0.32;
                const double dx = wrapCoord(x, kDot) - kDot / 2, dy = wrapCoord(y, kDot) - kDot / 2;
                const double panel =
                    0.74 + 0.08 * hashUnit(u32(cellOf(x, kPanel)), u32(cellOf(y, kPanel)), seed);
                const double dot = (dx * dx + dy * dy < 1.6 * 1.6) ? 0.18 : 0.0;
                return panel - dot + 0.08 * (s - 0.5);
              });
}

ImageF checker(std::uint32_t seed) {
  FractalNoise fbm(N, 8, 8, 4, 0.55, hash32(seed, 9));
  constexpr double kSquare = 32.0;
  return bake([&](double x, double y) { return fbm.at(x, y); },
              [&](double x, double y, double s) {
                const int cx = cellOf(x, kSquare), cy = cellOf(y, kSquare);
                const bool dark = ((cx + cy) & 1) != 0;
                const double jitter = 0.12 * (hashUnit(u32(cx), u32(cy), seed) - 0.5);
                return (dark ? 0.24 : 0.68) + jitter + 0.3 * (s - 0.5);
              });
}

ImageF blobs(std::uint32_t seed) {
  FractalNoise fbm(N, 4, 4, 5, 0.55, hash32(seed, 10));
  ImageF img(N, N);
  for (int y = 0; y < N; ++y)
    for (int x = 0; x < N; ++x) img(x, y) = static_cast<float>(0.5 + 0.3 * (fbm.at(x, y) - 0.5));
  // Disks drawn over their bounding boxes (wrapping), later ones covering earlier ones; coverage
  // from 4x4 samples per texel.
  for (std::uint32_t i = 0; i < 90; ++i) {
    const double r = 6.0 + 34.0 * hashUnit(i, 1, seed) * hashUnit(i, 2, seed);
    const double cx = kN * hashUnit(i, 3, seed), cy = kN * hashUnit(i, 4, seed);
    const double albedo = 0.12 + 0.8 * hashUnit(i, 5, seed);
    const int x0 = static_cast<int>(std::floor(cx - r)) - 1, x1 = static_cast<int>(cx + r) + 1;
    const int y0 = static_cast<int>(std::floor(cy - r)) - 1, y1 = static_cast<int>(cy + r) + 1;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        int inside = 0;
        for (int j = 0; j < 4; ++j) {
          for (int k = 0; k < 4; ++k) {
            const double dx = x + (k - 1.5) * 0.25 - cx, dy = y + (j - 1.5) * 0.25 - cy;
            if (dx * dx + dy * dy < r * r) ++inside;
          }
        }
        if (inside == 0) continue;
        const double cov = inside / 16.0;
        float& t = img(x & (N - 1), y & (N - 1));
        t = static_cast<float>((1.0 - cov) * t + cov * albedo);
      }
    }
  }
  return img;
}

ImageF concrete(std::uint32_t seed) {
  FractalNoise fbm(N, 4, 4, 7, 0.62, hash32(seed, 11));
  constexpr double kHoles = 128.0, kBoard = 256.0;
  return bake([&](double x, double y) { return fbm.at(x, y); },
              [&](double x, double y, double s) {
                const double hx = wrapCoord(x + kHoles / 2, kHoles) - kHoles / 2;
                const double hy = wrapCoord(y + kHoles / 2, kHoles) - kHoles / 2;
                if (hx * hx + hy * hy < 16.0) return 0.15;
                if (wrapCoord(y + 5.0, kBoard) < 1.5) return 0.3;
                return 0.52 + 0.6 * (s - 0.5);
              });
}

}  // namespace

std::vector<MipTexture> makeTextureLibrary(std::uint32_t seed) {
  std::vector<MipTexture> lib;
  lib.reserve(kTextureCount);
  ImageF (*const makers[kTextureCount])(std::uint32_t) = {
      plaster, brick, floorTiles, wood, ceilingPanels, checker, blobs, concrete};
  for (int i = 0; i < kTextureCount; ++i)
    lib.push_back(buildMipTexture(makers[i](hash32(seed, u32(100 + i))), true, kLibraryTexelSize));
  return lib;
}

}  // namespace ldsm::drivers::sim
