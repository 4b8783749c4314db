#include "ldsm/loop/vocabulary_builder.h"

#include <optional>
#include <string>

#include "ldsm/error.h"
#include "loop/still_image_features.h"
#include "loop/vocabulary.h"

namespace ldsm::loop {
namespace {

/// Smallest image side: a corner needs its 31x31 ORB patch plus the corner border.
constexpr int kMinImageSide = 40;

VocabularyParams toParams(const VocabularyTrainingOptions& o) {
  VocabularyParams p;
  p.branching = o.branching;
  p.levels = o.levels;
  p.max_iterations = o.max_iterations;
  p.seed = o.seed;
  return p;
}

}  // namespace

VocabularySummary inspectVocabulary(const std::uint8_t* data, std::size_t size,
                                    const std::string& where) {
  const Vocabulary v = Vocabulary::deserialize(data, size, where);
  VocabularySummary s;
  s.branching = v.branching();
  s.levels = v.levels();
  s.nodes = v.nodeCount();
  s.words = v.wordCount();
  s.training_images = v.trainingImages();
  return s;
}

struct VocabularyBuilder::Impl {
  VocabularyTrainingOptions options;
  std::optional<StillImageFeatures> features;
  StillFeatures scratch;
  std::vector<std::vector<OrbDescriptor>> images;
  std::size_t descriptors = 0;
};

VocabularyBuilder::VocabularyBuilder(const VocabularyTrainingOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  if (options.branching < 2 || options.branching > Vocabulary::kMaxBranching) {
    throw ConfigError("vocabulary: branching must be in [2, " +
                      std::to_string(Vocabulary::kMaxBranching) + "] (got " +
                      std::to_string(options.branching) + ")");
  }
  if (options.levels < 1 || options.levels > Vocabulary::kMaxLevels) {
    throw ConfigError("vocabulary: levels must be in [1, " +
                      std::to_string(Vocabulary::kMaxLevels) + "] (got " +
                      std::to_string(options.levels) + ")");
  }
  if (options.max_iterations < 0 || options.max_iterations > 100) {
    throw ConfigError("vocabulary: max_iterations must be in [0, 100] (got " +
                      std::to_string(options.max_iterations) + ")");
  }
  if (options.features_per_image < 1 || options.features_per_image > 100000) {
    throw ConfigError("vocabulary: features per image must be in [1, 100000] (got " +
                      std::to_string(options.features_per_image) + ")");
  }
}

VocabularyBuilder::~VocabularyBuilder() = default;

int VocabularyBuilder::addImage(ImageView<const std::uint8_t> image) {
  Impl& m = *impl_;
  if (image.data == nullptr || image.width < kMinImageSide || image.height < kMinImageSide) {
    throw InputError("vocabulary: image of " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " pixels is too small (at least " +
                     std::to_string(kMinImageSide) + "x" + std::to_string(kMinImageSide) + ")");
  }
  if (!m.features || m.features->width() != image.width || m.features->height() != image.height) {
    StillImageFeatureSettings settings;
    settings.max_corners = m.options.features_per_image;
    m.features.emplace(image.width, image.height, settings);
  }
  const int n = m.features->compute(image, m.scratch);
  m.images.push_back(m.scratch.descriptors);
  m.descriptors += static_cast<std::size_t>(n);
  return n;
}

std::size_t VocabularyBuilder::imageCount() const {
  return impl_->images.size();
}
std::size_t VocabularyBuilder::descriptorCount() const {
  return impl_->descriptors;
}

std::vector<std::uint8_t> VocabularyBuilder::train() const {
  if (impl_->descriptors == 0) {
    throw InputError("vocabulary: no features found in " + std::to_string(impl_->images.size()) +
                     " images, nothing to train on");
  }
  std::optional<Vocabulary> v = Vocabulary::train(impl_->images, toParams(impl_->options));
  return v->serialize();
}

}  // namespace ldsm::loop
