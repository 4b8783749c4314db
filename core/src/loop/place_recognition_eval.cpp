#include "loop/place_recognition_eval.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "ldsm/error.h"

namespace ldsm::loop {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

PlaceRecognitionResult evaluatePlaceRecognition(
    const std::vector<ImageU8>& images, const std::vector<std::vector<std::uint8_t>>& same_place,
    const PlaceRecognitionEvalSettings& settings, std::shared_ptr<const Vocabulary> pretrained) {
  const std::size_t n = images.size();
  if (same_place.size() != n) {
    throw InputError("place recognition: ground truth has " + std::to_string(same_place.size()) +
                     " rows for " + std::to_string(n) + " images");
  }
  for (const auto& row : same_place) {
    if (row.size() != n) {
      throw InputError("place recognition: ground truth row of " + std::to_string(row.size()) +
                       " entries for " + std::to_string(n) + " images");
    }
  }
  PlaceRecognitionResult result;
  if (n == 0) return result;
  auto same = [&](std::size_t i, std::size_t j) {
    return same_place[i][j] != 0 || same_place[j][i] != 0;
  };

  StillImageFeatures extractor(images[0].width(), images[0].height(), settings.features);
  BowIndex index(settings.index, std::move(pretrained));
  std::vector<KeyframeFeatures> keyframes(n);
  StillFeatures features;
  for (std::size_t i = 0; i < n; ++i) {
    if (images[i].width() != extractor.width() || images[i].height() != extractor.height()) {
      throw InputError("place recognition: image " + std::to_string(i) + " is " +
                       std::to_string(images[i].width()) + "x" +
                       std::to_string(images[i].height()) + ", the first is " +
                       std::to_string(extractor.width()) + "x" +
                       std::to_string(extractor.height()));
    }
    auto t0 = Clock::now();
    extractor.compute(images[i].view(), features);
    result.features_ms += msSince(t0);
    result.mean_features +=
        static_cast<double>(features.descriptors.size()) / static_cast<double>(n);
    KeyframeFeatures& kf = keyframes[i];
    kf.keyframe_id = static_cast<int>(i);
    kf.pixels = features.pixels;
    kf.descriptors = features.descriptors;
    kf.idepth.assign(kf.pixels.size(), 0.f);

    t0 = Clock::now();
    index.add(kf.keyframe_id, kf.descriptors);
    if (index.retrainIfDue()) ++result.vocabulary_trainings;
    const int newest_candidate = static_cast<int>(i) - settings.skip_recent - 1;
    const std::vector<PlaceCandidate> candidates =
        newest_candidate < 0 ? std::vector<PlaceCandidate>()
                             : index.query(
                                   kf.keyframe_id, [&](int id) { return id > newest_candidate; },
                                   settings.verify_candidates, settings.min_score);
    result.index_ms += msSince(t0);

    PlaceQueryOutcome o;
    o.query = static_cast<int>(i);
    for (int j = 0; j <= newest_candidate; ++j) {
      if (same(i, static_cast<std::size_t>(j))) o.has_true_match = true;
    }
    if (!candidates.empty()) {
      o.top_candidate = candidates.front().keyframe_id;
      o.top_score = candidates.front().score;
    }
    t0 = Clock::now();
    for (const PlaceCandidate& c : candidates) {
      KeyframeFeatures& other = keyframes[static_cast<std::size_t>(c.keyframe_id)];
      const FeatureVector* fq = index.featureVector(kf.keyframe_id);
      const FeatureVector* fc = index.featureVector(other.keyframe_id);
      kf.feature_vector = fq != nullptr ? *fq : FeatureVector();
      other.feature_vector = fc != nullptr ? *fc : FeatureVector();
      const std::vector<DescriptorMatch> matches = matchDescriptors(kf, other, settings.matching);
      const EpipolarCheckResult check =
          checkEpipolar(kf.pixels, other.pixels, matches, settings.verification);
      if (check.accepted) {
        o.detection = c.keyframe_id;
        o.inliers = check.inliers;
        o.matches = check.matches;
        break;
      }
      if (check.inliers > o.inliers || (check.inliers == o.inliers && check.matches > o.matches)) {
        o.inliers = check.inliers;
        o.matches = check.matches;
      }
    }
    result.verify_ms += msSince(t0);

    if (newest_candidate >= 0) ++result.queries;
    if (o.has_true_match) ++result.queries_with_match;
    if (o.detection >= 0) {
      ++result.detections;
      o.correct = same(i, static_cast<std::size_t>(o.detection));
      if (o.correct) {
        ++result.true_positives;
      } else {
        ++result.false_positives;
      }
    }
    result.outcomes.push_back(o);
  }
  result.precision =
      result.detections > 0 ? static_cast<double>(result.true_positives) / result.detections : 1.0;
  result.recall = result.queries_with_match > 0
                      ? static_cast<double>(result.true_positives) / result.queries_with_match
                      : 0.0;
  result.final_words = index.vocabulary() != nullptr ? index.vocabulary()->wordCount() : 0;
  return result;
}

}  // namespace ldsm::loop
