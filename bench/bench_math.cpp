// Per-pixel and per-frame costs of the core math: point transforms, Lie exp/log, pyramid build and
// bilinear lookups.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "image/image_pyramid.h"
#include "image/interpolation.h"
#include "ldsm/image.h"
#include "math/se3.h"
#include "math/sim3.h"

namespace {

using ldsm::SE3d;
using ldsm::SE3f;
using ldsm::Sim3d;

std::vector<Eigen::Vector3f> randomPoints(int n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-2.f, 2.f);
  std::vector<Eigen::Vector3f> pts(static_cast<std::size_t>(n));
  for (auto& p : pts) p = Eigen::Vector3f(u(rng), u(rng), 3.f + u(rng));
  return pts;
}

Eigen::Matrix<double, 6, 1> someTwist() {
  Eigen::Matrix<double, 6, 1> x;
  x << 0.1, -0.2, 0.3, 0.4, -0.5, 0.6;
  return x;
}

void BM_SE3fTransformPoints(benchmark::State& state) {
  const auto pts = randomPoints(2048);
  const SE3f T = SE3d::exp(someTwist()).cast<float>();
  // Tracking precomputes R and t once per frame; this is the per-point cost.
  const Eigen::Matrix3f R = T.rotationMatrix();
  const Eigen::Vector3f t = T.translation();
  for (auto _ : state) {
    float sum = 0.f;
    for (const auto& p : pts) sum += (R * p + t).z();
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pts.size()));
}
BENCHMARK(BM_SE3fTransformPoints);

void BM_SE3dExpLog(benchmark::State& state) {
  Eigen::Matrix<double, 6, 1> x = someTwist();
  for (auto _ : state) {
    x = SE3d::exp(x).log();
    benchmark::DoNotOptimize(x);
  }
}
BENCHMARK(BM_SE3dExpLog);

void BM_Sim3dExpLog(benchmark::State& state) {
  Eigen::Matrix<double, 7, 1> x;
  x << 0.1, -0.2, 0.3, 0.04, -0.05, 0.06, 0.1;  // small angle: the series branch
  for (auto _ : state) {
    x = Sim3d::exp(x).log();
    benchmark::DoNotOptimize(x);
  }
}
BENCHMARK(BM_Sim3dExpLog);

void BM_SE3dRightJacobianInverse(benchmark::State& state) {
  const Eigen::Matrix<double, 6, 1> x = someTwist();
  for (auto _ : state) benchmark::DoNotOptimize(SE3d::rightJacobianInverse(x));
}
BENCHMARK(BM_SE3dRightJacobianInverse);

void BM_PyramidBuild(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0));
  const int h = static_cast<int>(state.range(1));
  ldsm::ImageF img(w, h);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.f, 255.f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img(x, y) = u(rng);
  ldsm::ImagePyramid pyramid(w, h, 5);
  for (auto _ : state) {
    pyramid.build(img.view());
    benchmark::DoNotOptimize(pyramid.gradients(0).data);
  }
  state.SetItemsProcessed(state.iterations() * w * h);
}
BENCHMARK(BM_PyramidBuild)->Args({640, 480})->Args({752, 480})->Args({1280, 720});

void BM_BilinearGradientLookup(benchmark::State& state) {
  const int w = 640;
  const int h = 480;
  ldsm::ImageF img(w, h);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 255.f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img(x, y) = u(rng);
  ldsm::ImagePyramid pyramid(w, h, 1);
  pyramid.build(img.view());
  std::vector<Eigen::Vector2f> pos(4096);
  std::uniform_real_distribution<float> ux(1.f, w - 2.f);
  std::uniform_real_distribution<float> uy(1.f, h - 2.f);
  for (auto& p : pos) p = Eigen::Vector2f(ux(rng), uy(rng));
  const auto level = pyramid.gradients(0);
  for (auto _ : state) {
    float sum = 0.f;
    for (const auto& p : pos) {
      if (!ldsm::isInsideForBilinear(level, p.x(), p.y())) continue;
      const ldsm::GradientPixel g = ldsm::interpolateBilinear(level, p.x(), p.y());
      sum += g.intensity + g.dx + g.dy;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pos.size()));
}
BENCHMARK(BM_BilinearGradientLookup);

}  // namespace

BENCHMARK_MAIN();
