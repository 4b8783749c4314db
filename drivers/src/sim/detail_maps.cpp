// Landmarks and lighting of each quad. Landmarks are rectangles ("decals") in quad coordinates
// whose inside multiplies the albedo pattern by a factor drawn from one of several designs, so
// that every wall segment looks different and places can be recognised again.
#include "detail_maps.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ldsm/drivers/sim/det_math.h"
#include "procedural.h"

namespace ldsm::drivers::sim {
namespace {

enum class DecalType { Poster, Door, Band, Lamp, Mat, Label };

struct Decal {
  double u0, v0, u1, v1;  // rectangle in quad metres
  DecalType type;
  int design;
  std::uint32_t seed;

  bool contains(double u, double v) const { return u >= u0 && u < u1 && v >= v0 && v < v1; }
  bool overlaps(const Decal& o, double gap) const {
    return u0 < o.u1 + gap && o.u0 < u1 + gap && v0 < o.v1 + gap && o.v0 < v1 + gap;
  }
};

class Rng {
 public:
  explicit Rng(std::uint32_t seed) : seed_(seed) {}
  double uniform() { return hashUnit(seed_, counter_++, 0x51u); }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  int integer(int n) { return std::min(n - 1, static_cast<int>(uniform() * n)); }
  std::uint32_t next() { return hash32(seed_, counter_++); }

 private:
  std::uint32_t seed_;
  std::uint32_t counter_ = 0;
};

// Factor of a poster design at (a, b) in [0, 1]^2 of its printable area (w x h metres).
double posterDesign(int design, std::uint32_t seed, double a, double b, double w, double h) {
  Rng rng(seed);
  const double f1 = rng.uniform(0.25, 0.7), f2 = rng.uniform(1.0, 1.6);
  switch (design) {
    case 0: {  // vertical stripes of varying width
      const int n = 3 + rng.integer(5);
      const double x = a * n;
      const int k = static_cast<int>(x);
      return (k & 1) ? f1 : f2 * (0.85 + 0.15 * hashUnit(seed, static_cast<std::uint32_t>(k), 3));
    }
    case 1: {  // grid of random tones
      const int nx = 2 + rng.integer(3), ny = 2 + rng.integer(3);
      const int i = std::min(nx - 1, static_cast<int>(a * nx)),
                j = std::min(ny - 1, static_cast<int>(b * ny));
      return 0.25 +
             1.35 * hashUnit(seed, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
    }
    case 2: {  // disk and ring
      const double dx = (a - 0.5) * w, dy = (b - 0.5) * h, r = 0.42 * std::min(w, h);
      const double d2 = dx * dx + dy * dy;
      if (d2 < 0.25 * r * r) return f2;
      if (d2 < r * r) return f1;
      return 1.3;
    }
    case 3: {  // diagonal split with a square
      if (a > 0.55 && a < 0.85 && b > 0.15 && b < 0.4) return 0.2;
      return a + b < 1.0 ? f1 : f2;
    }
    case 4: {  // "text": dark bars of random length on a light ground
      const int lines = 5 + rng.integer(5);
      const double y = b * lines;
      const int line = static_cast<int>(y);
      if (y - line > 0.55) return 1.45;
      const double len = 0.35 + 0.6 * hashUnit(seed, static_cast<std::uint32_t>(line), 9);
      return a < len ? 0.3 : 1.45;
    }
    default: {  // random blocks
      double v = 1.4;
      for (std::uint32_t k = 0; k < 6; ++k) {
        const double x0 = hashUnit(seed, k, 20), y0 = hashUnit(seed, k, 21);
        const double x1 = x0 + 0.15 + 0.4 * hashUnit(seed, k, 22);
        const double y1 = y0 + 0.1 + 0.4 * hashUnit(seed, k, 23);
        if (a >= x0 && a < x1 && b >= y0 && b < y1) v = 0.2 + 1.3 * hashUnit(seed, k, 24);
      }
      return v;
    }
  }
}

double decalFactor(const Decal& d, double u, double v) {
  const double w = d.u1 - d.u0, h = d.v1 - d.v0;
  const double du = u - d.u0, dv = v - d.v0;
  const double edge = std::min(std::min(du, w - du), std::min(dv, h - dv));
  switch (d.type) {
    case DecalType::Poster: {
      if (edge < 0.02) return 0.3;   // frame
      if (edge < 0.05) return 1.45;  // white margin
      const double iw = w - 0.1, ih = h - 0.1;
      return posterDesign(d.design, d.seed, (du - 0.05) / iw, (dv - 0.05) / ih, iw, ih);
    }
    case DecalType::Label: {
      if (edge < 0.015) return 0.35;
      return posterDesign(4, d.seed, (du - 0.015) / (w - 0.03), (dv - 0.015) / (h - 0.03), w, h);
    }
    case DecalType::Door: {
      if (edge < 0.05) return 0.3;  // frame
      // Handle, kick plate and (for some designs) a window.
      if (du > w - 0.2 && du < w - 0.08 && dv > 0.98 && dv < 1.03) return 0.12;
      if (dv < 0.25 && edge > 0.09) return 0.8;
      if (d.design == 1 && dv > 1.35 && dv < h - 0.2 && du > 0.25 && du < w - 0.25) return 0.22;
      return 0.6;
    }
    case DecalType::Band:
      return d.design == 0 ? 0.4 : 0.55;
    case DecalType::Lamp:
      return edge < 0.04 ? 0.5 : 2.4;
    case DecalType::Mat:
      if (edge < 0.05) return 0.3;
      return d.design == 0 ? 0.5 : 1.4;
  }
  return 1.0;
}

// Tries to place a w x h rectangle with its lower-left corner in [ulo, uhi] x [vlo, vhi] without
// overlapping the decals already placed.
bool place(std::vector<Decal>& decals, Rng& rng, Decal d, double ulo, double uhi, double vlo,
           double vhi) {
  const double w = d.u1, h = d.v1;  // the caller passes the size in u1, v1
  if (uhi < ulo || vhi < vlo) return false;
  for (int attempt = 0; attempt < 8; ++attempt) {
    Decal c = d;
    c.u0 = rng.uniform(ulo, uhi);
    c.v0 = rng.uniform(vlo, vhi);
    c.u1 = c.u0 + w;
    c.v1 = c.v0 + h;
    bool free = true;
    for (const Decal& o : decals)
      if (o.type != DecalType::Band && c.overlaps(o, 0.15)) free = false;
    if (free) {
      decals.push_back(c);
      return true;
    }
  }
  return false;
}

std::vector<Decal> makeDecals(const SimScene& scene, int qi, std::uint32_t seed) {
  const SimQuad& q = scene.quads[static_cast<std::size_t>(qi)];
  Rng rng(hash32(seed, static_cast<std::uint32_t>(qi), 0xdeca1u));
  std::vector<Decal> decals;
  const double su = q.size_u, sv = q.size_v;
  switch (q.kind) {
    case SurfaceKind::Wall: {
      // Walls are vertical with axis_v up; heights are relative to the wall's bottom edge.
      const double z0 = q.origin.z;
      const double floor_v = -z0;  // v of height 0
      decals.push_back({0, floor_v - 1.0, su, floor_v + 0.1, DecalType::Band, 0, 0});
      if (rng.uniform() < 0.3) {
        const double hz = rng.uniform(0.9, 1.1);
        decals.push_back({0, floor_v + hz, su, floor_v + hz + 0.04, DecalType::Band, 1, 0});
      }
      if (su > 1.6 && rng.uniform() < 0.4) {
        Decal door{0, 0, 0.9, 2.05, DecalType::Door, rng.integer(2), rng.next()};
        place(decals, rng, door, 0.2, su - 1.1, floor_v, floor_v);
      }
      const int posters = su > 2.5 ? 1 + rng.integer(2) : (su > 1.0 ? rng.integer(2) : 0);
      for (int k = 0; k < posters; ++k) {
        Decal p{0,
                0,
                rng.uniform(0.4, 1.1),
                rng.uniform(0.4, 0.9),
                DecalType::Poster,
                rng.integer(6),
                rng.next()};
        place(decals, rng, p, 0.1, su - p.u1 - 0.1, floor_v + 1.0, floor_v + 1.5);
      }
      break;
    }
    case SurfaceKind::Box: {
      if (su > 0.35 && sv > 0.3 && rng.uniform() < 0.6) {
        Decal l{0, 0,         std::min(0.3, su - 0.1), std::min(0.2, sv - 0.1), DecalType::Label,
                0, rng.next()};
        place(decals, rng, l, 0.05, su - l.u1 - 0.05, 0.05, sv - l.v1 - 0.05);
      }
      break;
    }
    case SurfaceKind::Floor: {
      if (rng.uniform() < 0.5) {
        Decal m{0,
                0,
                rng.uniform(0.6, 1.2),
                rng.uniform(0.4, 0.8),
                DecalType::Mat,
                rng.integer(2),
                rng.next()};
        place(decals, rng, m, 0.2, su - m.u1 - 0.2, 0.2, sv - m.v1 - 0.2);
      }
      break;
    }
    case SurfaceKind::Ceiling: {
      // A lamp panel above every light that lies over this quad.
      for (const SimLight& l : scene.lights) {
        const Vec3 d = l.position - q.origin;
        const double u = dot(d, q.axis_u), v = dot(d, q.axis_v);
        if (u > 0 && u < su && v > 0 && v < sv)
          decals.push_back({u - 0.6, v - 0.15, u + 0.6, v + 0.15, DecalType::Lamp, 0, 0});
      }
      break;
    }
  }
  return decals;
}

double landmarkFactor(const std::vector<Decal>& decals, double u, double v) {
  double f = 1.0;
  for (const Decal& d : decals)
    if (d.contains(u, v))
      f = d.type == DecalType::Band ? f * decalFactor(d, u, v) : decalFactor(d, u, v);
  return f;
}

double lightingAt(const SimScene& scene, const Vec3& p, const Vec3& n) {
  constexpr double kAmbient = 0.35, kSoft2 = 0.3 * 0.3, kRange2 = 14.0 * 14.0;
  double sum = kAmbient;
  for (const SimLight& l : scene.lights) {
    const Vec3 d = l.position - p;
    const double d2 = dot(d, d);
    if (d2 > kRange2) continue;
    const double r2 = d2 + kSoft2;
    sum += l.intensity * std::fabs(dot(n, d)) / (r2 * std::sqrt(r2));
  }
  return sum * 1.6 / (1.0 + 0.6 * sum);  // soft compression of hot spots
}

}  // namespace

MipTexture bakeDetailMap(const SimScene& scene, int quad, std::uint32_t seed) {
  const SimQuad& q = scene.quads[static_cast<std::size_t>(quad)];
  const int nu = std::max(2, static_cast<int>(std::ceil(q.size_u / kDetailTexelSize)) + 1);
  const int nv = std::max(2, static_cast<int>(std::ceil(q.size_v / kDetailTexelSize)) + 1);
  const std::vector<Decal> decals = makeDecals(scene, quad, seed);
  const Vec3 n = q.normal();

  // Lighting is smooth: evaluate every 4th texel and interpolate bilinearly.
  constexpr int kStep = 4;
  const int lu = (nu - 1) / kStep + 2, lv = (nv - 1) / kStep + 2;
  std::vector<double> light(static_cast<std::size_t>(lu) * lv);
  for (int j = 0; j < lv; ++j)
    for (int i = 0; i < lu; ++i)
      light[static_cast<std::size_t>(j) * lu + i] =
          lightingAt(scene, q.point(i * kStep * kDetailTexelSize, j * kStep * kDetailTexelSize), n);

  ImageF img(nu, nv);
  for (int j = 0; j < nv; ++j) {
    const int lj = j / kStep;
    const double fj = static_cast<double>(j - lj * kStep) / kStep;
    for (int i = 0; i < nu; ++i) {
      const int li = i / kStep;
      const double fi = static_cast<double>(i - li * kStep) / kStep;
      const std::size_t k = static_cast<std::size_t>(lj) * lu + li;
      const double l =
          lerp(lerp(light[k], light[k + 1], fi), lerp(light[k + lu], light[k + lu + 1], fi), fj);
      double f = 1.0;
      if (!decals.empty()) {
        double sum = 0.0;  // 2x2 samples: box-filtered decal edges
        for (int b = 0; b < 2; ++b)
          for (int a = 0; a < 2; ++a)
            sum += landmarkFactor(decals, (i + (a - 0.5) * 0.5) * kDetailTexelSize,
                                  (j + (b - 0.5) * 0.5) * kDetailTexelSize);
        f = 0.25 * sum;
      }
      img(i, j) = static_cast<float>(f * l);
    }
  }
  return buildMipTexture(std::move(img), false, kDetailTexelSize);
}

}  // namespace ldsm::drivers::sim
