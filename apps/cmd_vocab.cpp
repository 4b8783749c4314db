// `ldsm vocab`: vocabularies for loop detection.
//   ldsm vocab train --images DIR... --out FILE [--k 10 --levels 5 --features N --every S]
//     detects Shi-Tomasi corners on 5 pyramid levels with their ORB descriptors on every
//     S-th image of each dataset (any format `ldsm run` reads: image folders, TUM/EuRoC/KITTI
//     layouts, zip archives, videos), trains a vocabulary tree and writes it atomically.
//   ldsm vocab info FILE
//     validates a vocabulary file and prints what it holds.
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/vocabulary_file.h"
#include "ldsm/error.h"
#include "ldsm/loop/vocabulary_builder.h"

namespace ldsm::app {
namespace {

struct VocabTrainOptions {
  std::vector<std::string> images;
  std::string out;
  int k = 10;
  int levels = 5;
  int features = 500;
  int every = 1;
  int iterations = 10;
  std::uint64_t seed = 1;
};

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void printSummary(const loop::VocabularySummary& s) {
  std::printf("branching %d, levels %d, %zu words (%zu nodes), idf from %u images\n", s.branching,
              s.levels, s.words, s.nodes, s.training_images);
}

void runTrain(const VocabTrainOptions& o) {
  loop::VocabularyTrainingOptions options;
  options.branching = o.k;
  options.levels = o.levels;
  options.features_per_image = o.features;
  options.max_iterations = o.iterations;
  options.seed = o.seed;
  loop::VocabularyBuilder builder(options);
  const auto t0 = std::chrono::steady_clock::now();
  for (const std::string& dir : o.images) {
    std::unique_ptr<drivers::FrameSource> source = drivers::openDataset(dir);
    drivers::Frame frame;
    std::size_t used = 0;
    std::size_t features = 0;
    for (std::int64_t i = 0; source->next(frame); ++i) {
      if (i % o.every != 0) continue;
      features += static_cast<std::size_t>(builder.addImage(frame.image.view()));
      ++used;
    }
    if (used == 0) throw InputError(dir + ": no images");
    spdlog::info("{}: {} images, {} features", dir, used, features);
    std::printf("%s: %zu images, %zu features\n", dir.c_str(), used, features);
  }
  std::printf("features of %zu images in %.1f s; training...\n", builder.imageCount(),
              secondsSince(t0));
  const auto t1 = std::chrono::steady_clock::now();
  const std::vector<std::uint8_t> bytes = builder.train();
  const loop::VocabularySummary summary =
      loop::inspectVocabulary(bytes.data(), bytes.size(), "trained vocabulary");
  drivers::writeVocabularyFile(o.out, bytes);
  std::printf("trained in %.1f s on %zu descriptors: ", secondsSince(t1),
              builder.descriptorCount());
  printSummary(summary);
  std::printf("wrote %s (%zu bytes)\n", o.out.c_str(), bytes.size());
}

void runInfo(const std::string& path) {
  const auto t0 = std::chrono::steady_clock::now();
  const drivers::VocabularyFile file = drivers::readVocabularyFile(path);
  std::printf("%s: %zu bytes, loaded and verified in %.3f s\n", path.c_str(), file.bytes.size(),
              secondsSince(t0));
  printSummary(file.summary);
}

}  // namespace

void addVocabCommand(CLI::App& app, CommandResult& /*result*/) {
  CLI::App* vocab = app.add_subcommand("vocab", "Bag-of-words vocabularies for loop detection");
  vocab->require_subcommand(1);

  auto train_options = std::make_shared<VocabTrainOptions>();
  CLI::App* train = vocab->add_subcommand(
      "train", "Train a vocabulary on the corners + ORB features of image datasets");
  train
      ->add_option("--images", train_options->images,
                   "image folders, dataset folders, zip archives or videos (one or more)")
      ->required()
      ->expected(1, -1);
  train->add_option("--out", train_options->out, "vocabulary file to write")->required();
  train->add_option("--k", train_options->k, "branching factor (children per node)")
      ->check(CLI::Range(2, 64))
      ->capture_default_str();
  train->add_option("--levels", train_options->levels, "depth of the tree (up to k^levels words)")
      ->check(CLI::Range(1, 10))
      ->capture_default_str();
  train
      ->add_option("--features", train_options->features,
                   "corners per image (Shi-Tomasi, on 5 pyramid levels)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  train->add_option("--every", train_options->every, "use every N-th image of each dataset")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  train->add_option("--iterations", train_options->iterations, "k-majority rounds per node")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  train->add_option("--seed", train_options->seed, "random seed (training is deterministic)")
      ->capture_default_str();
  train->callback([train_options]() { runTrain(*train_options); });

  auto info_path = std::make_shared<std::string>();
  CLI::App* info = vocab->add_subcommand("info", "Check a vocabulary file and print its shape");
  info->add_option("file", *info_path, "vocabulary file")->required();
  info->callback([info_path]() { runInfo(*info_path); });
}

}  // namespace ldsm::app
