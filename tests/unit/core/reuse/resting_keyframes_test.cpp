// Which map keyframes the reuse search leaves alone: one taken out of the window may come back at
// once, but taken out twice within the rest period it rests for as long; a candidate the trial
// turned down rests at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "reuse/resting_keyframes.h"

namespace ldsm {
namespace {

bool rests(RestingKeyframes& r, int id, int newest_id) {
  const std::vector<int> ids = r.resting(newest_id);
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

TEST(RestingKeyframes, TakenOutOnceItMayComeBackAtOnce) {
  RestingKeyframes r(5);
  EXPECT_FALSE(r.takenOut(7, 20));
  EXPECT_FALSE(rests(r, 7, 20));
  EXPECT_FALSE(rests(r, 7, 21));
}

TEST(RestingKeyframes, TakenOutTwiceSoonItRestsForThePeriod) {
  RestingKeyframes r(5);
  EXPECT_FALSE(r.takenOut(7, 20));
  EXPECT_TRUE(r.takenOut(7, 21));
  for (int newest = 21; newest <= 26; ++newest) EXPECT_TRUE(rests(r, 7, newest)) << newest;
  EXPECT_FALSE(rests(r, 7, 27));
  // Afterwards it starts afresh: the next take-out is free again.
  EXPECT_FALSE(r.takenOut(7, 30));
  EXPECT_FALSE(rests(r, 7, 30));
}

TEST(RestingKeyframes, TakeOutsFurtherApartThanThePeriodNeverRest) {
  RestingKeyframes r(5);
  for (int newest = 10; newest < 100; newest += 6) {
    EXPECT_FALSE(r.takenOut(3, newest)) << newest;
    EXPECT_FALSE(rests(r, 3, newest)) << newest;
  }
  // Exactly at the period's end it still counts as soon.
  EXPECT_FALSE(r.takenOut(4, 200));
  EXPECT_TRUE(r.takenOut(4, 205));
}

TEST(RestingKeyframes, EachKeyframeIsCountedOnItsOwn) {
  RestingKeyframes r(5);
  EXPECT_FALSE(r.takenOut(1, 10));
  EXPECT_FALSE(r.takenOut(2, 10));
  EXPECT_FALSE(r.takenOut(3, 11));
  EXPECT_TRUE(r.takenOut(2, 12));
  const std::vector<int> ids = r.resting(12);
  EXPECT_EQ(ids, std::vector<int>{2});
}

TEST(RestingKeyframes, TurnedDownByTheTrialItRestsAtOnce) {
  RestingKeyframes r(5);
  r.rest(9, 40, 3);
  EXPECT_TRUE(rests(r, 9, 40));
  EXPECT_TRUE(rests(r, 9, 43));
  EXPECT_FALSE(rests(r, 9, 44));
  r.rest(9, 50, 0);  // a period of 0: no rest
  EXPECT_FALSE(rests(r, 9, 50));
}

TEST(RestingKeyframes, NoPeriodNoRest) {
  RestingKeyframes r(0);
  for (int newest = 0; newest < 10; ++newest) EXPECT_FALSE(r.takenOut(5, newest));
  EXPECT_TRUE(r.resting(10).empty());
}

}  // namespace
}  // namespace ldsm
