#include "pipeline/calibration_history.h"

#include <gtest/gtest.h>

namespace ldsm {
namespace {

CalibrationSample sampleAt(int windows) {
  CalibrationSample s;
  s.windows = windows;
  s.frame_index = 10 * windows;
  return s;
}

TEST(CalibrationHistory, RecordsEveryWindowUntilFull) {
  CalibrationHistory h(8);
  for (int w = 1; w <= 8; ++w) h.add(sampleAt(w));
  ASSERT_EQ(h.samples()->size(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_EQ((*h.samples())[static_cast<size_t>(i)].windows, i + 1);
  EXPECT_EQ(h.stride(), 1);
}

// However long the run, at most `capacity` samples, evenly spaced from the first window on, and
// the newest one no more than a stride behind.
TEST(CalibrationHistory, StaysBoundedAndEvenOverALongRun) {
  CalibrationHistory h(8);
  for (int w = 1; w <= 1000; ++w) {
    h.add(sampleAt(w));
    const auto s = h.samples();
    ASSERT_LE(s->size(), 8u);
    ASSERT_EQ(s->front().windows, 1);
    for (size_t i = 1; i < s->size(); ++i)
      ASSERT_EQ((*s)[i].windows - (*s)[i - 1].windows, h.stride()) << "window " << w;
    ASSERT_GT(s->back().windows, w - h.stride());
  }
  EXPECT_EQ(h.stride(), 128);
}

TEST(CalibrationHistory, IgnoresWindowsThatDoNotAdvance) {
  CalibrationHistory h(8);
  h.add(sampleAt(1));
  const auto before = h.samples();
  h.add(sampleAt(1));
  h.add(sampleAt(0));
  EXPECT_EQ(h.samples(), before);  // nothing new published
  EXPECT_EQ(h.samples()->size(), 1u);
}

}  // namespace
}  // namespace ldsm
