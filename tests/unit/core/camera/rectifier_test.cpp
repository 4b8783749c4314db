#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "camera/remap_bilinear.h"
#include "ldsm/camera/camera_model.h"
#include "ldsm/camera/rectifier.h"
#include "ldsm/error.h"
#include "sample_cameras.h"

namespace ldsm {
namespace {

GeometricCalibration calibration(const CameraIntrinsics& in, OutputMode mode, int w, int h) {
  GeometricCalibration c;
  c.input = in;
  c.output.mode = mode;
  c.output.width = w;
  c.output.height = h;
  return c;
}

GeometricCalibration explicitCalibration(const CameraIntrinsics& in, double fx, double fy,
                                         double cx, double cy, bool relative, int w, int h) {
  GeometricCalibration c = calibration(in, OutputMode::Explicit, w, h);
  c.output.fx = fx;
  c.output.fy = fy;
  c.output.cx = cx;
  c.output.cy = cy;
  c.output.relative = relative;
  return c;
}

/// A scene edge: the plane through the camera center a x + b y + c = 0 (normalized coordinates),
/// i.e. the image of a straight 3D line. Intensity is a smooth ramp across it.
struct Edge {
  double a = 0.8, b = -0.3, c = 0.05;
  double value(const Eigen::Vector3d& ray, double sharpness) const {
    const double d = (a * ray.x() + b * ray.y() + c * ray.z()) / std::hypot(a, b) / ray.z();
    return 128.0 + 100.0 * std::tanh(d * sharpness);
  }
};

/// Renders the edge as the distorted input camera sees it.
ImageF renderInput(const CameraModel& cam, const Edge& edge, double sharpness) {
  ImageF img(cam.width(), cam.height());
  for (int v = 0; v < cam.height(); ++v)
    for (int u = 0; u < cam.width(); ++u) {
      Eigen::Vector3d ray;
      EXPECT_TRUE(cam.unproject({u, v}, &ray));
      img(u, v) = static_cast<float>(edge.value(ray, sharpness));
    }
  return img;
}

void expectStraightEdge(const CameraIntrinsics& in, OutputMode mode) {
  const Rectifier rect(calibration(in, mode, 640, 480));
  const PinholeIntrinsics& out = rect.output();
  const Edge edge;
  const double sharpness = out.fx / 3.0;  // ramp about 3 output pixels wide
  const ImageF input = renderInput(rect.inputModel(), edge, sharpness);
  ImageF rectified;
  rect.rectify(input.view(), rectified, -1.0f);
  ASSERT_EQ(rectified.width(), 640);
  ASSERT_EQ(rectified.height(), 480);
  // Per row: where the ramp crosses 128, against where the straight line is in the output.
  int rows = 0;
  double max_err = 0;
  for (int v = 0; v < out.height; ++v) {
    const double y = (v - out.cy) / out.fy;
    const double x = -(edge.b * y + edge.c) / edge.a;  // the line in normalized coordinates
    const double u_true = out.fx * x + out.cx;
    if (u_true < 3 || u_true > out.width - 4) continue;
    for (int u = static_cast<int>(u_true) - 3; u < static_cast<int>(u_true) + 3; ++u) {
      const float l = rectified(u, v), r = rectified(u + 1, v);
      if (l < 0 || r < 0) continue;  // invalid
      if ((l - 128.0f) * (r - 128.0f) <= 0 && l != r) {
        const double u_found = u + (128.0 - l) / (r - l);
        max_err = std::max(max_err, std::abs(u_found - u_true));
        ++rows;
        break;
      }
    }
  }
  EXPECT_GT(rows, 300);
  EXPECT_LT(max_err, 0.05);
}

TEST(Rectifier, CropTurnsADistortedLineIntoAStraightLine) {
  expectStraightEdge(test::radTanIntrinsics(), OutputMode::Crop);
}

TEST(Rectifier, FullTurnsADistortedLineIntoAStraightLine) {
  expectStraightEdge(test::radTanIntrinsics(), OutputMode::Full);
  expectStraightEdge(test::pincushionIntrinsics(), OutputMode::Full);
}

TEST(Rectifier, CropHasNoInvalidPixelAndIsTight) {
  for (const auto& in : {test::radTanIntrinsics(), test::pincushionIntrinsics(),
                         test::fovIntrinsics(), test::equidistantIntrinsics()}) {
    const Rectifier rect(calibration(in, OutputMode::Crop, 500, 400));
    const PinholeIntrinsics& out = rect.output();
    EXPECT_EQ(rect.numValidPixels(), 500 * 400) << cameraModelName(in.model);
    // A field of view 1% wider around the same center sees invalid input.
    const Rectifier wider(explicitCalibration(in, out.fx * 0.99, out.fy * 0.99,
                                              out.cx * 0.99 + 0.01 * 249.5,
                                              out.cy * 0.99 + 0.01 * 199.5, false, 500, 400));
    EXPECT_LT(wider.numValidPixels(), 500 * 400) << cameraModelName(in.model);
  }
}

TEST(Rectifier, FullShowsTheWholeInputImage) {
  for (const auto& in :
       {test::radTanIntrinsics(), test::pincushionIntrinsics(), test::fovIntrinsics()}) {
    const Rectifier rect(calibration(in, OutputMode::Full, 600, 400));
    const PinholeIntrinsics& out = rect.output();
    double min_u = 1e9, max_u = -1e9, min_v = 1e9, max_v = -1e9;
    // Every input border pixel (corners included) lands inside the output image.
    const auto& cam = rect.inputModel();
    for (int i = 0; i < 2 * (in.width + in.height); ++i) {
      Eigen::Vector2d px = i < in.width       ? Eigen::Vector2d(i, 0)
                           : i < 2 * in.width ? Eigen::Vector2d(i - in.width, in.height - 1)
                           : i < 2 * in.width + in.height
                               ? Eigen::Vector2d(0, i - 2 * in.width)
                               : Eigen::Vector2d(in.width - 1, i - 2 * in.width - in.height);
      Eigen::Vector3d ray;
      ASSERT_TRUE(cam.unproject(px, &ray));
      const double u = out.fx * ray.x() / ray.z() + out.cx, v = out.fy * ray.y() / ray.z() + out.cy;
      min_u = std::min(min_u, u);
      max_u = std::max(max_u, u);
      min_v = std::min(min_v, v);
      max_v = std::max(max_v, v);
    }
    EXPECT_NEAR(min_u, 0.0, 1e-6);
    EXPECT_NEAR(min_v, 0.0, 1e-6);
    EXPECT_NEAR(max_u, 599.0, 1e-6);
    EXPECT_NEAR(max_v, 399.0, 1e-6);
    // Distortion leaves parts of the output without input.
    EXPECT_LT(rect.numValidPixels(), 600 * 400);
    EXPECT_GT(rect.numValidPixels(), 600 * 400 / 2);
  }
}

TEST(Rectifier, FullOfAFisheyeBeyondNinetyDegreesIsAnError) {
  EXPECT_THROW(Rectifier(calibration(test::equidistantIntrinsics(), OutputMode::Full, 512, 512)),
               InputError);
}

TEST(Rectifier, NoneWithTheInputSizeIsACopy) {
  const auto in = test::pinholeIntrinsics();
  const Rectifier rect(calibration(in, OutputMode::None, in.width, in.height));
  EXPECT_TRUE(rect.isIdentity());
  EXPECT_EQ(rect.output().fx, in.fx);
  EXPECT_EQ(rect.output().cy, in.cy);
  ImageU8 img(in.width, in.height);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) img(x, y) = static_cast<std::uint8_t>((x * 7 + y * 3) % 256);
  ImageF out;
  rect.rectify(img.view(), out);
  for (int y = 0; y < in.height; y += 13)
    for (int x = 0; x < in.width; x += 11) EXPECT_EQ(out(x, y), img(x, y));
}

TEST(Rectifier, NoneRescalesWithPixelCentersAtIntegers) {
  const auto in = test::pinholeIntrinsics();
  const Rectifier rect(calibration(in, OutputMode::None, in.width / 2, in.height / 2));
  EXPECT_FALSE(rect.isIdentity());
  const PinholeIntrinsics& out = rect.output();
  // A point's output pixel is its input pixel scaled about the pixel corner (-0.5, -0.5).
  const Eigen::Vector3d p(0.3, -0.1, 1.7);
  Eigen::Vector2d px_in;
  ASSERT_TRUE(rect.inputModel().project(p, &px_in));
  EXPECT_NEAR(out.fx * p.x() / p.z() + out.cx, (px_in.x() + 0.5) * 0.5 - 0.5, 1e-9);
  EXPECT_NEAR(out.fy * p.y() / p.z() + out.cy, (px_in.y() + 0.5) * 0.5 - 0.5, 1e-9);
  // Downsampling by two of a linear ramp samples between input pixels.
  ImageF ramp(in.width, in.height);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) ramp(x, y) = static_cast<float>(x + 1000 * y);
  ImageF small;
  rect.rectify(ramp.view(), small);
  EXPECT_NEAR(small(10, 20), 2 * 10 + 0.5 + 1000 * (2 * 20 + 0.5), 0.05);
}

TEST(Rectifier, ExplicitRelativeFollowsDso) {
  const Rectifier rect(
      explicitCalibration(test::radTanIntrinsics(), 0.6, 0.9, 0.5, 0.5, true, 640, 480));
  EXPECT_DOUBLE_EQ(rect.output().fx, 384.0);
  EXPECT_DOUBLE_EQ(rect.output().fy, 432.0);
  EXPECT_DOUBLE_EQ(rect.output().cx, 319.5);
  EXPECT_DOUBLE_EQ(rect.output().cy, 239.5);
  const Rectifier pixels(
      explicitCalibration(test::radTanIntrinsics(), 384, 432, 319.5, 239.5, false, 640, 480));
  EXPECT_DOUBLE_EQ(pixels.output().fx, 384.0);
  EXPECT_DOUBLE_EQ(pixels.output().cy, 239.5);
}

TEST(Rectifier, ExplicitOutputLargerThanTheInputIsAllowed) {
  const Rectifier rect(
      explicitCalibration(test::radTanIntrinsics(), 0.6, 0.9, 0.5, 0.5, true, 1000, 700));
  EXPECT_EQ(rect.output().width, 1000);
  EXPECT_GT(rect.numValidPixels(), 0);
  EXPECT_LT(rect.numValidPixels(), 1000 * 700);
}

TEST(Rectifier, RemapInterpolatesBilinearly) {
  // Pinhole input, explicit output shifted by a quarter pixel: a bilinear ramp is exact.
  const auto in = test::pinholeIntrinsics();
  const Rectifier rect(explicitCalibration(in, in.fx, in.fy, in.cx - 0.25, in.cy + 0.75, false,
                                           in.width, in.height));
  ImageF ramp(in.width, in.height);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) ramp(x, y) = static_cast<float>(3 * x - 2 * y);
  ImageF out;
  rect.rectify(ramp.view(), out, -1000.0f);
  EXPECT_NEAR(out(100, 50), 3 * 100.25 - 2 * 49.25, 1e-3);
  EXPECT_EQ(out(100, 0), -1000.0f);  // samples above the first input row: invalid
  EXPECT_FALSE(rect.isValid(100, 0));
  EXPECT_NEAR(rect.inputPixel(100, 50).x(), 100.25, 1e-4);
}

/// Rectifies `img` with the full table rebuilt from rect.inputPixel() and the per-pixel reference.
ImageF rectifyWithTheFullTable(const Rectifier& rect, const ImageU8& img) {
  const int w = rect.output().width, h = rect.output().height;
  std::vector<float> mx(static_cast<std::size_t>(w)), my(static_cast<std::size_t>(w));
  ImageF out(w, h);
  const simd::RemapInput<std::uint8_t> in{img.data(), img.width(), img.width(), img.height()};
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      mx[u] = rect.inputPixel(u, v).x();
      my[u] = rect.inputPixel(u, v).y();
    }
    simd::reference::remapRow(in, mx.data(), my.data(), w, -5.f, out.row(v));
  }
  return out;
}

ImageU8 randomBytes(int w, int h) {
  ImageU8 img(w, h);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> b(0, 255);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img(x, y) = static_cast<std::uint8_t>(b(rng));
  return img;
}

// KITTI's calibration: an undistorted pinhole cropped to a smaller output. Its table is one row of
// input columns and one column of input rows (8 bytes per output pixel otherwise), and the
// rectified image is bit for bit the one of the full table.
TEST(Rectifier, AnUndistortedPinholeKeepsASeparableTable) {
  CameraIntrinsics kitti;
  kitti.model = CameraModelType::Pinhole;
  kitti.width = 1241;
  kitti.height = 376;
  kitti.fx = kitti.fy = 718.856;
  kitti.cx = 607.1928;
  kitti.cy = 185.2157;
  const Rectifier rect(calibration(kitti, OutputMode::Crop, 1232, 368));
  ASSERT_TRUE(rect.isSeparable());
  // The columns' input x, clamped cell and weight, and the rows' input y.
  EXPECT_EQ(rect.tableBytes(), (3u * 1232u + 368u) * sizeof(float));
  EXPECT_EQ(rect.numValidPixels(), 1232 * 368);
  const ImageU8 img = randomBytes(1241, 376);
  ImageF out;
  rect.rectify(img.view(), out, -5.f);
  const ImageF expected = rectifyWithTheFullTable(rect, img);
  for (int y = 0; y < 368; ++y)
    for (int x = 0; x < 1232; ++x) ASSERT_EQ(out(x, y), expected(x, y)) << x << "," << y;
}

// Rows and columns that see no input stay invalid in the separable table (the output shifted by
// a quarter pixel and three quarters of a row: its first row samples above the input).
TEST(Rectifier, ASeparableTableKeepsItsInvalidRowsAndColumns) {
  const auto in = test::pinholeIntrinsics();
  const Rectifier rect(explicitCalibration(in, in.fx, in.fy, in.cx + 0.25, in.cy + 0.75, false,
                                           in.width, in.height));
  ASSERT_TRUE(rect.isSeparable());
  EXPECT_FALSE(rect.isValid(100, 0));
  EXPECT_FALSE(rect.isValid(0, 50));
  EXPECT_TRUE(rect.isValid(1, 50));
  EXPECT_EQ(rect.numValidPixels(), (in.width - 1) * (in.height - 1));
  ImageU8 img = randomBytes(in.width, in.height);
  ImageF out;
  rect.rectify(img.view(), out, -5.f);
  const ImageF expected = rectifyWithTheFullTable(rect, img);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) ASSERT_EQ(out(x, y), expected(x, y)) << x << "," << y;
  EXPECT_EQ(out(100, 0), -5.f);
  EXPECT_EQ(out(0, 50), -5.f);
}

TEST(Rectifier, ADistortedCameraKeepsTheFullTable) {
  const Rectifier rect(calibration(test::radTanIntrinsics(), OutputMode::Crop, 640, 480));
  EXPECT_FALSE(rect.isSeparable());
  EXPECT_EQ(rect.tableBytes(), 2u * 640u * 480u * sizeof(float));
}

TEST(Rectifier, RectifyDoesNotReallocateASizedOutput) {
  const Rectifier rect(calibration(test::radTanIntrinsics(), OutputMode::Crop, 640, 480));
  ImageU8 img(752, 480, 77);
  ImageF out(640, 480);
  const float* before = out.data();
  rect.rectify(img.view(), out);
  EXPECT_EQ(out.data(), before);
  EXPECT_FLOAT_EQ(out(320, 240), 77.0f);
  EXPECT_FLOAT_EQ(out(0, 0), 77.0f);
}

// rectifyRow() is what a pyramid is built from, row by row: every row must be that row of
// rectify()'s whole image, bit for bit, for each kind of table and both input types.
TEST(Rectifier, ARowIsThatRowOfTheWholeImage) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> grey(0, 255);
  const GeometricCalibration cameras[] = {
      calibration(test::radTanIntrinsics(), OutputMode::Crop, 640, 480),   // full table
      calibration(test::pinholeIntrinsics(), OutputMode::Crop, 600, 440),  // separable
      calibration(test::pinholeIntrinsics(), OutputMode::None, 640, 480),  // identity
      calibration(test::fovIntrinsics(), OutputMode::Full, 500, 400),      // invalid pixels
  };
  for (const GeometricCalibration& c : cameras) {
    const Rectifier rect(c);
    ImageU8 in8(c.input.width, c.input.height);
    ImageF inf(c.input.width, c.input.height);
    for (int y = 0; y < in8.height(); ++y)
      for (int x = 0; x < in8.width(); ++x) {
        in8(x, y) = static_cast<std::uint8_t>(grey(rng));
        inf(x, y) = static_cast<float>(grey(rng)) * 0.37f;
      }
    ImageF whole8, wholef;
    rect.rectify(in8.view(), whole8, -3.f);
    rect.rectify(inf.view(), wholef, -3.f);
    std::vector<float> row(static_cast<std::size_t>(rect.output().width));
    for (int v = 0; v < rect.output().height; ++v) {
      rect.rectifyRow(in8.view(), v, row.data(), -3.f);
      ASSERT_EQ(std::memcmp(row.data(), whole8.row(v), row.size() * sizeof(float)), 0) << v;
      rect.rectifyRow(inf.view(), v, row.data(), -3.f);
      ASSERT_EQ(std::memcmp(row.data(), wholef.row(v), row.size() * sizeof(float)), 0) << v;
    }
    EXPECT_THROW(rect.rectifyRow(in8.view(), rect.output().height, row.data()), InputError);
    EXPECT_THROW(rect.rectifyRow(in8.view(), -1, row.data()), InputError);
    const ImageU8 small(c.input.width - 1, c.input.height);
    EXPECT_THROW(rect.rectifyRow(small.view(), 0, row.data()), InputError);
  }
}

void expectError(const GeometricCalibration& c, const std::string& text) {
  try {
    Rectifier r(c);
    ADD_FAILURE() << "accepted an invalid rectification (" << text << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(Rectifier, ValidationErrors) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto radtan = test::radTanIntrinsics();
  expectError(calibration(radtan, OutputMode::Crop, 0, 480), "output size");
  expectError(calibration(radtan, OutputMode::Full, 640, -1), "output size");
  expectError(calibration(radtan, OutputMode::Crop, 800, 480), "larger than the input");
  expectError(calibration(radtan, OutputMode::Full, 640, 500), "larger than the input");
  expectError(calibration(radtan, OutputMode::None, 752, 480), "none");
  expectError(explicitCalibration(radtan, nan, 0.9, 0.5, 0.5, true, 640, 480), "fx");
  expectError(explicitCalibration(radtan, 0.6, 0.9, 0.5, nan, true, 640, 480), "cy");
  expectError(explicitCalibration(radtan, 0.6, -0.9, 0.5, 0.5, true, 640, 480), "fy");
  expectError(explicitCalibration(radtan, 300, 300, 1e6, 240, false, 640, 480), "no pixel");
  auto bad_input = radtan;
  bad_input.fx = nan;
  expectError(calibration(bad_input, OutputMode::Crop, 640, 480), "fx");
  // Wrong input image size at run time.
  const Rectifier rect(calibration(radtan, OutputMode::Crop, 640, 480));
  ImageU8 wrong(640, 480, 0);
  ImageF out;
  EXPECT_THROW(rect.rectify(wrong.view(), out), InputError);
}

}  // namespace
}  // namespace ldsm
