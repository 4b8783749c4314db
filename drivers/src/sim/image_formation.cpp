#include "ldsm/drivers/sim/image_formation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

// Standard deviation of the sum of four independent uniform integers in [0, 255]:
// sqrt(4 * (256^2 - 1) / 12).
constexpr double kByteSumSigma = 147.80138520322697;

}  // namespace

double responseCurve(SimResponse response, double e) {
  e = std::clamp(e, 0.0, 1.0);
  switch (response) {
    case SimResponse::Linear:
      return e;
    case SimResponse::Gamma:
      return detPow(e, 1.0 / 2.2);
    case SimResponse::SCurve: {
      const double g = detPow(e, 0.6);
      return 0.5 * g + 0.5 * (g * g * (3.0 - 2.0 * g));
    }
  }
  return e;
}

ImageFormation::ImageFormation(const SimOptions& options, const PinholeIntrinsics& camera)
    : table_(kTableSize + 1), sigma_(options.noise_sigma) {
  validate(options);
  for (int i = 0; i <= kTableSize; ++i)
    table_[static_cast<std::size_t>(i)] = static_cast<float>(
        255.0 * responseCurve(options.response, static_cast<double>(i) / kTableSize));
  // Invert the piecewise-linear table at the 256 grey values.
  std::size_t seg = 0;
  for (int v = 0; v < 256; ++v) {
    const double target = v;
    while (seg + 1 < kTableSize && table_[seg + 1] < target) ++seg;
    const double a = table_[seg], b = table_[seg + 1];
    const double f = b > a ? std::clamp((target - a) / (b - a), 0.0, 1.0) : 0.0;
    inverse_response_[static_cast<std::size_t>(v)] =
        static_cast<float>(255.0 * ((static_cast<double>(seg) + f) / kTableSize));
  }
  inverse_response_[0] = 0.0f;
  inverse_response_[255] = 255.0f;

  // Radial vignette: V = 1 - s (r^2 + r^4) / 2, r = distance to the principal point relative to
  // the farthest corner.
  vignette_.resize(camera.width, camera.height);
  double r2max = 0.0;
  for (int cy = 0; cy < 2; ++cy)
    for (int cx = 0; cx < 2; ++cx) {
      const double dx = cx * (camera.width - 1) - camera.cx,
                   dy = cy * (camera.height - 1) - camera.cy;
      r2max = std::max(r2max, dx * dx + dy * dy);
    }
  const double s = options.vignette;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const double dx = x - camera.cx, dy = y - camera.cy;
      const double r2 = (dx * dx + dy * dy) / r2max;
      vignette_(x, y) = static_cast<float>(1.0 - s * 0.5 * (r2 + r2 * r2));
    }
}

double ImageFormation::responseGrey(double e) const {
  // Exactly as apply() does it: the table position in float, clamped, then interpolated.
  constexpr float kLast = static_cast<float>(kTableSize) - (1.0f / 1024.0f);
  const float p = static_cast<float>(e) * static_cast<float>(kTableSize);
  const float p0 = p > 0.0f ? p : 0.0f;
  const float p1 = p0 < kLast ? p0 : kLast;
  const int i = static_cast<int>(p1);
  const float f = p1 - static_cast<float>(i);
  const float* table = table_.data();
  return table[i] + f * (table[i + 1] - table[i]);
}

void ImageFormation::apply(const ImageF& irradiance, double exposure_ms, std::uint32_t noise_key,
                           ImageU8& out) const {
  if (irradiance.width() != vignette_.width() || irradiance.height() != vignette_.height())
    throw InputError("sim image formation: irradiance is " + std::to_string(irradiance.width()) +
                     "x" + std::to_string(irradiance.height()) + ", expected " +
                     std::to_string(vignette_.width()) + "x" + std::to_string(vignette_.height()));
  const int W = irradiance.width(), H = irradiance.height();
  out.resize(W, H);
  const float k = static_cast<float>(exposure_ms / kSaturationExposureMs);
  const float noise_scale = static_cast<float>(sigma_ / kByteSumSigma);
  const bool noisy = sigma_ > 0.0;
  const float* table = table_.data();
  constexpr float kLast = static_cast<float>(kTableSize) - (1.0f / 1024.0f);
  std::vector<float> pos(static_cast<std::size_t>(W)), noise(static_cast<std::size_t>(W), 0.0f);
  for (int y = 0; y < H; ++y) {
    const float* b = irradiance.row(y);
    const float* v = vignette_.row(y);
    std::uint8_t* o = out.row(y);
    // Table position of the exposure (e clamped to [0, 1]) and the noise: vectorisable.
    for (int x = 0; x < W; ++x) {
      const float p = ((b[x] * v[x]) * k) * static_cast<float>(kTableSize);
      const float p0 = p > 0.0f ? p : 0.0f;  // also maps NaN to 0
      pos[static_cast<std::size_t>(x)] = p0 < kLast ? p0 : kLast;
    }
    if (noisy) {
      const std::uint32_t base = static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(W);
      for (int x = 0; x < W; ++x) {
        const std::uint32_t h = hash32(base + static_cast<std::uint32_t>(x), noise_key);
        const std::uint32_t sum =
            (h & 0xffu) + ((h >> 8) & 0xffu) + ((h >> 16) & 0xffu) + (h >> 24);
        noise[static_cast<std::size_t>(x)] =
            static_cast<float>(static_cast<int>(sum) - 510) * noise_scale;
      }
    }
    // Table lookups (gathers, scalar), then noise, clamping and rounding (vectorisable).
    float* grey = pos.data();
    for (int x = 0; x < W; ++x) {
      const float p = grey[x];
      const int i = static_cast<int>(p);
      const float f = p - static_cast<float>(i);
      grey[x] = table[i] + f * (table[i + 1] - table[i]);
    }
    const float* n = noise.data();
    for (int x = 0; x < W; ++x) {
      // Round half up, then clamp as integers (same result as clamping first; |g| stays small).
      int q = static_cast<int>((grey[x] + n[x]) + 0.5f);
      q = q < 0 ? 0 : q;
      q = q > 255 ? 255 : q;
      o[x] = static_cast<std::uint8_t>(q);
    }
  }
}

double simExposureMs(const SimOptions& options, double t) {
  if (!options.exposure_changes) return options.exposure_ms;
  const double c1 = t / 13.0 - std::floor(t / 13.0);
  const double c2 = t / 5.9 - std::floor(t / 5.9);
  const double stops = 0.6 * detSin(2.0 * kPi * c1) + 0.4 * detSin(2.0 * kPi * c2 + 1.3);
  return options.exposure_ms * detExp(stops * 0.6931471805599453);
}

}  // namespace ldsm::drivers::sim
