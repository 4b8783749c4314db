// Place recognition on the real rtabmap_loop84 images (../shared/data): the verified top BoW
// candidate of every image, with the online vocabulary the engine uses when no vocabulary file
// is configured, must be right every time it is given (precision 100 %) for at least half of the
// images that revisit a place (recall >= 50 %).
#include <gtest/gtest.h>

#include <string>

#include "ldsm/drivers/place_ground_truth.h"
#include "loop/place_recognition_eval.h"
#include "test_paths.h"

namespace ldsm::loop {
namespace {

TEST(PlaceRecognition, RtabmapLoop84OnlineVocabularyReachesTheTarget) {
  const std::string dir = test::sharedData("rtabmap_loop84");
  if (dir.empty()) {
    GTEST_SKIP() << "../shared/data absent: rtabmap_loop84 is needed for this test";
  }
  const drivers::PlaceDataset data = drivers::readPlaceDataset(dir);
  ASSERT_EQ(data.images.size(), 84u);
  const PlaceRecognitionResult r =
      evaluatePlaceRecognition(data.images, data.same_place, PlaceRecognitionEvalSettings());
  // The second traversal (images 41..84) revisits the first: 44 queries have a true match.
  EXPECT_EQ(r.queries_with_match, 44);
  EXPECT_GE(r.vocabulary_trainings, 3);  // trained online, retrained as the sequence grew
  EXPECT_EQ(r.false_positives, 0) << "precision " << r.precision;
  EXPECT_DOUBLE_EQ(r.precision, 1.0);
  EXPECT_GE(r.recall, 0.5) << r.true_positives << " of " << r.queries_with_match;
  // No image of the first traversal (no true match) may be detected as a loop.
  for (const PlaceQueryOutcome& o : r.outcomes) {
    if (!o.has_true_match) {
      EXPECT_EQ(o.detection, -1) << "image " << o.query + 1;
    }
  }
}

}  // namespace
}  // namespace ldsm::loop
