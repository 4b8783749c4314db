#include "ldsm/drivers/sim/calibration_target.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

// Standard deviation of the sum of four independent uniform integers in [0, 255].
constexpr double kByteSumSigma = 147.80138520322697;

void validate(const CalibrationTarget& t, const TargetRenderOptions& o) {
  if (t.cols < 2 || t.rows < 2 || !(t.square_m > 0) || !(t.margin_m >= 0))
    throw ConfigError("calibration target: needs at least 2 x 2 squares of positive size");
  if (!t.texture.empty() && (t.texture.width() < 2 || t.texture.height() < 2))
    throw ConfigError("calibration target: texture must be at least 2 x 2 pixels");
  if (o.samples_per_axis < 1 || o.samples_per_axis > 8)
    throw ConfigError("calibration target: samples_per_axis must be in 1..8");
  if (!(o.blur_sigma_px >= 0 && o.blur_sigma_px <= 20) || !(o.noise_sigma >= 0))
    throw ConfigError("calibration target: blur must be in [0, 20] px, noise non-negative");
}

/// Irradiance of the board point (x, y) (metres, board frame).
class BoardShader {
 public:
  explicit BoardShader(const CalibrationTarget& t)
      : t_(t),
        width_m_(t.cols * t.square_m + 2 * t.margin_m),
        height_m_(t.rows * t.square_m + 2 * t.margin_m) {}

  double operator()(double x, double y) const {
    const double u = x + t_.margin_m, v = y + t_.margin_m;
    if (!(u >= 0 && v >= 0 && u < width_m_ && v < height_m_)) return t_.background;
    if (!t_.texture.empty()) return texture(u, v);
    if (x < 0 || y < 0) return t_.white;
    const int ix = static_cast<int>(x / t_.square_m), iy = static_cast<int>(y / t_.square_m);
    if (ix >= t_.cols || iy >= t_.rows) return t_.white;
    return (ix + iy) % 2 == 0 ? t_.black : t_.white;
  }

 private:
  /// Bilinear texture lookup at (u, v) metres from the texture's corner.
  double texture(double u, double v) const {
    const ImageU8& tex = t_.texture;
    const double tx = std::clamp(u / width_m_ * tex.width() - 0.5, 0.0, tex.width() - 1.0);
    const double ty = std::clamp(v / height_m_ * tex.height() - 0.5, 0.0, tex.height() - 1.0);
    const int x0 = std::min(static_cast<int>(tx), tex.width() - 2);
    const int y0 = std::min(static_cast<int>(ty), tex.height() - 2);
    const double fx = tx - x0, fy = ty - y0;
    const double a = tex(x0, y0) + fx * (tex(x0 + 1, y0) - tex(x0, y0));
    const double b = tex(x0, y0 + 1) + fx * (tex(x0 + 1, y0 + 1) - tex(x0, y0 + 1));
    const double g = (a + fy * (b - a)) / 255.0;
    return t_.black + g * (t_.white - t_.black);
  }

  const CalibrationTarget& t_;
  double width_m_, height_m_;
};

/// Where the ray through pixel `px` meets the board's printed side (false: it does not).
bool boardPoint(const CameraModel& camera, const Eigen::Isometry3d& T, const Eigen::Vector2d& px,
                Eigen::Vector2d& out) {
  Eigen::Vector3d ray;
  if (!camera.unproject(px, &ray)) return false;
  const Eigen::Vector3d d = T.linear() * ray;
  const Eigen::Vector3d& o = T.translation();
  if (!(o.z() < 0 && d.z() > 1e-12)) return false;
  const double lambda = -o.z() / d.z();
  out = (o + lambda * d).head<2>();
  return true;
}

/// Separable Gaussian blur with clamped borders.
void blur(ImageF& img, double sigma) {
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> k(static_cast<std::size_t>(2 * radius + 1));
  double sum = 0;
  for (int i = -radius; i <= radius; ++i) {
    k[static_cast<std::size_t>(i + radius)] = detExp(-0.5 * i * i / (sigma * sigma));
    sum += k[static_cast<std::size_t>(i + radius)];
  }
  for (double& v : k) v /= sum;
  const int W = img.width(), H = img.height();
  ImageF tmp(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double s = 0;
      for (int i = -radius; i <= radius; ++i)
        s += k[static_cast<std::size_t>(i + radius)] * img(std::clamp(x + i, 0, W - 1), y);
      tmp(x, y) = static_cast<float>(s);
    }
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double s = 0;
      for (int i = -radius; i <= radius; ++i)
        s += k[static_cast<std::size_t>(i + radius)] * tmp(x, std::clamp(y + i, 0, H - 1));
      img(x, y) = static_cast<float>(s);
    }
}

}  // namespace

void renderTargetIrradiance(const CalibrationTarget& target, const CameraModel& camera,
                            const Pose& camera_to_board, const TargetRenderOptions& options,
                            ImageF& out) {
  validate(target, options);
  const int W = camera.width(), H = camera.height();
  const Eigen::Isometry3d T = camera_to_board.isometry();
  const BoardShader shade(target);

  // Board coordinates at the pixel corners; samples inside a pixel interpolate them bilinearly
  // (the mapping is smooth at the scale of a pixel), pixels with an invalid corner unproject
  // every sample.
  const int cw = W + 1;
  std::vector<Eigen::Vector2d> corner(static_cast<std::size_t>(cw) * (H + 1));
  std::vector<std::uint8_t> ok(corner.size());
  for (int v = 0; v <= H; ++v)
    for (int u = 0; u <= W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * cw + u;
      ok[i] = boardPoint(camera, T, Eigen::Vector2d(u - 0.5, v - 0.5), corner[i]);
    }

  const int n = options.samples_per_axis;
  out.resize(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t i00 = static_cast<std::size_t>(y) * cw + x, i10 = i00 + 1, i01 = i00 + cw,
                        i11 = i01 + 1;
      const bool fast = ok[i00] && ok[i10] && ok[i01] && ok[i11];
      double sum = 0;
      for (int sy = 0; sy < n; ++sy)
        for (int sx = 0; sx < n; ++sx) {
          const double fx = (sx + 0.5) / n, fy = (sy + 0.5) / n;
          Eigen::Vector2d b;
          if (fast) {
            b = (1 - fy) * ((1 - fx) * corner[i00] + fx * corner[i10]) +
                fy * ((1 - fx) * corner[i01] + fx * corner[i11]);
          } else if (!boardPoint(camera, T, Eigen::Vector2d(x - 0.5 + fx, y - 0.5 + fy), b)) {
            sum += target.background;
            continue;
          }
          sum += shade(b.x(), b.y());
        }
      out(x, y) = static_cast<float>(sum / (n * n));
    }
  if (options.blur_sigma_px > 0) blur(out, options.blur_sigma_px);
}

void renderTargetView(const CalibrationTarget& target, const CameraModel& camera,
                      const Pose& camera_to_board, const TargetRenderOptions& options,
                      ImageU8& out) {
  ImageF irradiance;
  renderTargetIrradiance(target, camera, camera_to_board, options, irradiance);
  const int W = irradiance.width(), H = irradiance.height();
  out.resize(W, H);
  const double noise_scale = options.noise_sigma / kByteSumSigma;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::uint32_t h = hash32(static_cast<std::uint32_t>(y * W + x), options.noise_key);
      const int bytes =
          static_cast<int>((h & 0xffu) + ((h >> 8) & 0xffu) + ((h >> 16) & 0xffu) + (h >> 24));
      const double v = 255.0 * irradiance(x, y) + (bytes - 510) * noise_scale;
      out(x, y) = static_cast<std::uint8_t>(std::clamp(std::floor(v + 0.5), 0.0, 255.0));
    }
}

std::vector<std::optional<Eigen::Vector2d>> projectTargetCorners(const CalibrationTarget& target,
                                                                 const CameraModel& camera,
                                                                 const Pose& camera_to_board) {
  const Eigen::Isometry3d board_to_camera = camera_to_board.isometry().inverse();
  std::vector<std::optional<Eigen::Vector2d>> out;
  for (int iy = 0; iy + 1 < target.rows; ++iy)
    for (int ix = 0; ix + 1 < target.cols; ++ix) {
      const Eigen::Vector3d p = board_to_camera * Eigen::Vector3d((ix + 1) * target.square_m,
                                                                  (iy + 1) * target.square_m, 0);
      Eigen::Vector2d px;
      if (camera.project(p, &px))
        out.emplace_back(px);
      else
        out.emplace_back(std::nullopt);
    }
  return out;
}

std::vector<Pose> calibrationPoses(const CalibrationTarget& target, const CameraModel& camera,
                                   int count, double distance, double margin) {
  const Eigen::Vector3d centre(0.5 * target.cols * target.square_m,
                               0.5 * target.rows * target.square_m, 0.0);
  const double size = std::max(target.cols, target.rows) * target.square_m;
  std::vector<Pose> poses;
  for (int i = 0; poses.size() < static_cast<std::size_t>(count) && i < 20 * count; ++i) {
    const double az = 2.39996322972865332 * i;  // golden angle: directions spread evenly
    const double tilt = 0.25 + 0.45 * (0.618033988749895 * i - std::floor(0.618033988749895 * i));
    const double f = 0.381966011250105 * i + 0.2;
    const double dist = distance * (0.85 + 0.3 * (f - std::floor(f)));
    double s_az, c_az, s_tilt, c_tilt;
    detSinCos(az, s_az, c_az);
    detSinCos(tilt, s_tilt, c_tilt);
    const Eigen::Vector3d pos =
        centre + dist * Eigen::Vector3d(s_tilt * c_az, s_tilt * s_az, -c_tilt);
    // Aim beside the centre so that the board also lands near the image edges and corners.
    const Eigen::Vector3d aim =
        centre + size * Eigen::Vector3d(0.55 * detCos(1.7 * i + 0.5), 0.4 * detSin(2.3 * i), 0.0);
    const Pose pose = lookAtBoard(pos, aim, 0.35 * detSin(1.3 * i));
    bool inside = true;
    for (const auto& c : projectTargetCorners(target, camera, pose))
      inside = inside && c && camera.inImage(*c, margin);
    if (inside) poses.push_back(pose);
  }
  return poses;
}

Pose lookAtBoard(const Eigen::Vector3d& position, const Eigen::Vector3d& look_at, double roll_rad) {
  const Eigen::Vector3d z = (look_at - position).normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z);
  if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = z;
  R = R * Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Pose pose;
  pose.rotation = Eigen::Quaterniond(R).normalized();
  pose.translation = position;
  return pose;
}

}  // namespace ldsm::drivers::sim
