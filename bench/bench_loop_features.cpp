// Loop-closure features and bag of words: the per-keyframe cost (ORB at the odometry's corners +
// BoW transform, budget <= 10 ms at 640x480), vocabulary loading (a 1M-word file must load well
// under a second), online vocabulary training (the background task's budget), database queries
// and re-quantisation after a retraining.
//
// The keyframe is a 640x480 crop of vamr_desk_loop (../shared/data) when present, else a
// synthetic texture; its 300 Shi-Tomasi corners are found as the pixel selector finds them.
#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "features/corner_detector.h"
#include "features/orb_extractor.h"
#include "image/image_pyramid.h"
#include "ldsm/drivers/dataset_source.h"
#include "loop/binary_kmajority.h"
#include "loop/bow_index.h"
#include "loop/keyframe_database.h"
#include "loop/online_vocabulary.h"
#include "loop/vocabulary.h"

namespace {

using namespace ldsm;
using namespace ldsm::loop;

constexpr int kW = 640;
constexpr int kH = 480;

/// Frames of vamr_desk_loop cropped to 640x480 (float, 0..255), or synthetic textures.
const std::vector<ImageF>& frames() {
  static const std::vector<ImageF> images = [] {
    std::vector<ImageF> out;
    const std::string dir = std::string(LDSM_BENCH_DATA) + "/vamr_desk_loop";
    if (std::filesystem::exists(dir)) {
      auto source = drivers::openDataset(dir);
      drivers::Frame frame;
      for (int i = 0; source->next(frame); ++i) {
        if (i % 5 != 0 || frame.image.width() < kW || frame.image.height() < kH) continue;
        ImageF f(kW, kH);
        const int x0 = (frame.image.width() - kW) / 2;
        for (int y = 0; y < kH; ++y) {
          for (int x = 0; x < kW; ++x) f(x, y) = frame.image(x0 + x, y);
        }
        out.push_back(std::move(f));
      }
    }
    if (out.empty()) {
      for (int k = 0; k < 50; ++k) {
        ImageF f(kW, kH);
        for (int y = 0; y < kH; ++y) {
          for (int x = 0; x < kW; ++x) {
            SplitMix64 cell(static_cast<std::uint64_t>(k * 1000003 + (y / 7) * 997 + x / 7));
            f(x, y) = static_cast<float>(cell.below(256));
          }
        }
        out.push_back(std::move(f));
      }
    }
    return out;
  }();
  return images;
}

/// A blocky synthetic texture: corners everywhere, so the keyframe gets its full 300.
const ImageF& syntheticFrame() {
  static const ImageF f = [] {
    ImageF img(kW, kH);
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        SplitMix64 cell(static_cast<std::uint64_t>((y / 9) * 997 + x / 9));
        img(x, y) = static_cast<float>(cell.below(256));
      }
    }
    return img;
  }();
  return f;
}

/// The 300 strongest corners of a frame, as the pixel selector picks them (score >= 49).
std::vector<Eigen::Vector2f> cornersOf(const ImageF& image) {
  ImagePyramid pyramid(kW, kH, 1, false);
  pyramid.build(image.view());
  CornerDetector detector(kW, kH);
  CornerParams params;
  params.max_corners = 300;
  std::vector<Corner> corners;
  detector.detect(pyramid.gradients(0), params, corners);
  std::vector<Eigen::Vector2f> out;
  for (const Corner& c : corners) out.emplace_back(c.u, c.v);
  return out;
}

/// Descriptors of every frame (the keyframes of a session).
const std::vector<std::vector<OrbDescriptor>>& sessionDescriptors() {
  static const std::vector<std::vector<OrbDescriptor>> all = [] {
    std::vector<std::vector<OrbDescriptor>> out;
    OrbExtractor orb(kW, kH);
    std::vector<std::uint32_t> kept;
    for (const ImageF& f : frames()) {
      out.emplace_back();
      orb.compute(f.view(), cornersOf(f), out.back(), kept);
    }
    return out;
  }();
  return all;
}

/// Online-size vocabulary: what the engine trains from a session (k = 8, L = 4).
const Vocabulary& onlineVocabulary() {
  static const Vocabulary v = [] {
    VocabularyParams p;
    p.branching = 8;
    p.levels = 4;
    return *Vocabulary::train(sessionDescriptors(), p);
  }();
  return v;
}

/// A full k = 10, L = 6 tree (~1M words) trained on 2M random descriptors: the size of a large
/// offline vocabulary, for the load and transform costs (which depend on the size, not the data).
const std::vector<std::uint8_t>& millionWordBytes() {
  static const std::vector<std::uint8_t> bytes = [] {
    SplitMix64 rng(7);
    std::vector<std::vector<OrbDescriptor>> images(200);
    for (int i = 0; i < 2'000'000; ++i) {
      images[static_cast<std::size_t>(i) % images.size()].push_back(
          {rng.next(), rng.next(), rng.next(), rng.next()});
    }
    VocabularyParams p;
    p.branching = 10;
    p.levels = 6;
    p.max_iterations = 0;
    return Vocabulary::train(images, p)->serialize();
  }();
  return bytes;
}

const Vocabulary& millionWordVocabulary() {
  static const Vocabulary v = Vocabulary::deserialize(
      millionWordBytes().data(), millionWordBytes().size(), "1M-word vocabulary");
  return v;
}

void BM_OrbAtCorners(benchmark::State& state) {
  const ImageF& f = frames().front();
  const auto corners = cornersOf(f);
  OrbExtractor orb(kW, kH);
  std::vector<OrbDescriptor> d;
  std::vector<std::uint32_t> kept;
  for (auto _ : state) {
    orb.compute(f.view(), corners, d, kept);
    benchmark::DoNotOptimize(d.data());
  }
  state.counters["corners"] = static_cast<double>(corners.size());
  state.counters["described"] = static_cast<double>(d.size());
}
BENCHMARK(BM_OrbAtCorners)->Unit(benchmark::kMillisecond);

/// The per-keyframe budget: ORB at the corners + BoW vector + FeatureVector.
void BM_OrbPlusBow(benchmark::State& state, const Vocabulary& (*vocabulary)(), bool synthetic) {
  const ImageF& f = synthetic ? syntheticFrame() : frames().front();
  const auto corners = cornersOf(f);
  const Vocabulary& v = vocabulary();
  OrbExtractor orb(kW, kH);
  std::vector<OrbDescriptor> d;
  std::vector<std::uint32_t> kept;
  BowVector bow;
  FeatureVector fv;
  for (auto _ : state) {
    orb.compute(f.view(), corners, d, kept);
    v.transform(d, bow, fv, 2);
    benchmark::DoNotOptimize(bow.data());
  }
  state.counters["words"] = static_cast<double>(v.wordCount());
  state.counters["corners"] = static_cast<double>(corners.size());
  state.counters["bow_entries"] = static_cast<double>(bow.size());
}
BENCHMARK_CAPTURE(BM_OrbPlusBow, desk_online_k8_L4, onlineVocabulary, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OrbPlusBow, desk_offline_1M_words, millionWordVocabulary, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OrbPlusBow, texture300_offline_1M_words, millionWordVocabulary, true)
    ->Unit(benchmark::kMillisecond);

void BM_VocabularyLoad1M(benchmark::State& state) {
  const auto& bytes = millionWordBytes();
  for (auto _ : state) {
    Vocabulary v = Vocabulary::deserialize(bytes.data(), bytes.size(), "bench");
    benchmark::DoNotOptimize(v.wordCount());
  }
  state.counters["words"] = static_cast<double>(millionWordVocabulary().wordCount());
  state.counters["MB"] = static_cast<double>(bytes.size()) / 1e6;
}
BENCHMARK(BM_VocabularyLoad1M)->Unit(benchmark::kMillisecond)->Iterations(5);

/// One online (re)training at the default budget (60k descriptors max) on the session.
void BM_OnlineVocabularyTraining(benchmark::State& state) {
  OnlineTrainingJob job;
  for (const auto& kf : sessionDescriptors()) {
    job.keyframes.push_back(std::make_shared<const std::vector<OrbDescriptor>>(kf));
  }
  std::size_t words = 0, descriptors = 0;
  for (const auto& kf : sessionDescriptors()) descriptors += kf.size();
  for (auto _ : state) {
    auto v = trainOnlineVocabulary(job);
    words = v->wordCount();
  }
  state.counters["keyframes"] = static_cast<double>(job.keyframes.size());
  state.counters["descriptors"] = static_cast<double>(descriptors);
  state.counters["words"] = static_cast<double>(words);
}
BENCHMARK(BM_OnlineVocabularyTraining)->Unit(benchmark::kMillisecond);

/// Training at the full budget: 60k descriptors (the session's repeated with fresh noise).
void BM_OnlineVocabularyTrainingFullBudget(benchmark::State& state) {
  OnlineTrainingJob job;
  SplitMix64 rng(3);
  std::size_t total = 0;
  while (total < job.settings.max_training_descriptors) {
    for (const auto& kf : sessionDescriptors()) {
      auto copy = std::make_shared<std::vector<OrbDescriptor>>(kf);
      for (auto& d : *copy) d[rng.below(4)] ^= 1ull << rng.below(64);
      total += copy->size();
      job.keyframes.push_back(std::move(copy));
    }
  }
  std::size_t words = 0;
  for (auto _ : state) words = trainOnlineVocabulary(job)->wordCount();
  state.counters["descriptors"] = static_cast<double>(total);
  state.counters["words"] = static_cast<double>(words);
}
BENCHMARK(BM_OnlineVocabularyTrainingFullBudget)->Unit(benchmark::kMillisecond)->Iterations(3);

/// Query of a database of 1000 keyframes (the session's, repeated).
void BM_DatabaseQuery1000(benchmark::State& state) {
  const Vocabulary& v = onlineVocabulary();
  KeyframeDatabase db;
  std::vector<BowVector> bows;
  for (const auto& kf : sessionDescriptors()) {
    bows.emplace_back();
    v.transform(kf, bows.back());
  }
  for (int i = 0; i < 1000; ++i) db.add(i, bows[static_cast<std::size_t>(i) % bows.size()]);
  std::size_t found = 0;
  for (auto _ : state) {
    const auto r = db.query(
        bows.front(), [](int id) { return id < 10; }, 5);
    found = r.size();
    benchmark::DoNotOptimize(found);
  }
}
BENCHMARK(BM_DatabaseQuery1000)->Unit(benchmark::kMicrosecond);

/// Installing a retrained vocabulary: re-quantising 1000 keyframes of 300 descriptors.
void BM_RequantiseAfterRetraining1000(benchmark::State& state) {
  BowIndex index;
  const auto& all = sessionDescriptors();
  for (int i = 0; i < 1000; ++i) index.add(i, all[static_cast<std::size_t>(i) % all.size()]);
  auto v = std::make_shared<const Vocabulary>(onlineVocabulary());
  for (auto _ : state) index.install(v, 1000);
  state.counters["descriptors"] = static_cast<double>(index.descriptorCount());
}
BENCHMARK(BM_RequantiseAfterRetraining1000)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
