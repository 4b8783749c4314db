// Place recognition on an image sequence with a ground-truth "same place" matrix, as loop
// detection runs in the engine: every image becomes a keyframe (Shi-Tomasi corners + ORB), is
// added to a BowIndex (online vocabulary, retrained as the sequence grows, or a pre-trained one)
// and queries the images before it, except the most recent ones (the engine's active window).
// The top-scoring candidate(s) are verified geometrically (descriptor matches + fundamental-
// matrix RANSAC, no depth on stills) and the first verified one is the detection.
//
// Precision = correct detections / detections; recall = correct detections / queries that have a
// true match among the searchable images.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ldsm/image.h"
#include "loop/bow_index.h"
#include "loop/descriptor_matcher.h"
#include "loop/epipolar_check.h"
#include "loop/still_image_features.h"
#include "loop/vocabulary.h"

namespace ldsm::loop {

/// Settings of evaluatePlaceRecognition().
struct PlaceRecognitionEvalSettings {
  int skip_recent = 10;       ///< images i-1 .. i-skip_recent are never candidates of image i
  int verify_candidates = 1;  ///< top-scoring candidates verified, best first
  float min_score = 0.f;      ///< BoW score below which candidates are ignored
  StillImageFeatureSettings features;
  BowIndexSettings index;
  DescriptorMatchSettings matching;
  EpipolarCheckSettings verification;
};

/// What happened to one query image.
struct PlaceQueryOutcome {
  int query = -1;
  int top_candidate = -1;  ///< best BoW candidate (-1: none)
  float top_score = 0.f;
  int detection = -1;  ///< verified candidate (-1: none)
  int matches = 0;     ///< descriptor matches with the detection (or the best rejected one)
  int inliers = 0;     ///< of the detection (or of the best rejected candidate)
  bool has_true_match = false;
  bool correct = false;  ///< detection is a true match
};

struct PlaceRecognitionResult {
  int queries = 0;
  int queries_with_match = 0;
  int detections = 0;
  int true_positives = 0;
  int false_positives = 0;
  double precision = 1.0;  ///< 1 when nothing was detected
  double recall = 0.0;
  int vocabulary_trainings = 0;
  std::size_t final_words = 0;
  double mean_features = 0.0;  ///< features (corners with a descriptor) per image
  double features_ms = 0.0;    ///< total time in corner detection + ORB
  double index_ms = 0.0;       ///< total time adding, (re)training and querying
  double verify_ms = 0.0;      ///< total time in matching + RANSAC
  std::vector<PlaceQueryOutcome> outcomes;
};

/// Runs the evaluation. `same_place[i][j]` (n x n, either triangle or both) says whether images
/// i and j show the same place; images must all have the same size. `pretrained` replaces the
/// online vocabulary when given. Throws InputError on size mismatches.
PlaceRecognitionResult evaluatePlaceRecognition(
    const std::vector<ImageU8>& images, const std::vector<std::vector<std::uint8_t>>& same_place,
    const PlaceRecognitionEvalSettings& settings,
    std::shared_ptr<const Vocabulary> pretrained = nullptr);

}  // namespace ldsm::loop
