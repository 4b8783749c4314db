// The tracking reference's budget: map keyframes' points all stay, the window's own are thinned
// evenly to fill the rest; nothing changes without map points or within the budget.
#include "backend/reference_budget.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

namespace ldsm {
namespace {

/// `n` points, those at the indices where `is_map(i)` holds from map keyframes; each point's u
/// is its index, so that the kept ones can be traced back.
template <typename IsMap>
std::vector<DepthPoint> points(int n, IsMap is_map) {
  std::vector<DepthPoint> out;
  for (int i = 0; i < n; ++i) out.push_back({float(i), 0.f, 1.f, 1.f, is_map(i)});
  return out;
}

std::vector<int> indices(const std::vector<DepthPoint>& pts, bool from_map) {
  std::vector<int> out;
  for (const DepthPoint& p : pts)
    if (p.from_map == from_map) out.push_back(static_cast<int>(p.u));
  return out;
}

TEST(ReferenceBudget, KeepsEveryMapPointAndSpreadsTheOwnPointsEvenly) {
  // 700 own points, 300 map points interleaved; room for 301 own ones (an odd share).
  const std::vector<DepthPoint> all = points(1000, [](int i) { return i % 10 < 3; });
  const std::vector<int> own = indices(all, false), map = indices(all, true);
  for (const int budget : {601, 650, 999, 301}) {
    std::vector<DepthPoint> pts = all;
    thinToReferenceBudget(pts, budget);
    ASSERT_EQ(static_cast<int>(pts.size()), budget) << budget;
    EXPECT_EQ(indices(pts, true), map) << "every map point, in order";
    const std::vector<int> kept = indices(pts, false);
    const std::size_t room = static_cast<std::size_t>(budget) - map.size();
    ASSERT_EQ(kept.size(), room);
    // Evenly: between kept own points (and after the last), never more than ceil(own / room) - 1
    // own points in a row left out.
    const std::size_t max_gap = (own.size() + room - 1) / room - 1;
    std::size_t at = 0;
    for (const int k : kept) {
      std::size_t next = at;
      while (own[next] != k) ++next;
      EXPECT_LE(next - at, max_gap) << "budget " << budget << ", before own point " << k;
      at = next + 1;
    }
    EXPECT_LE(own.size() - at, max_gap) << "budget " << budget << ": the last own points";
  }
}

TEST(ReferenceBudget, LeavesPointsWithoutMapPointsOrWithinTheBudgetAlone) {
  const std::vector<DepthPoint> own_only = points(500, [](int) { return false; });
  std::vector<DepthPoint> pts = own_only;
  thinToReferenceBudget(pts, 10);
  EXPECT_EQ(pts.size(), own_only.size()) << "a window without map points is never thinned";
  const std::vector<DepthPoint> mixed = points(500, [](int i) { return i % 2 == 0; });
  pts = mixed;
  thinToReferenceBudget(pts, 500);
  EXPECT_EQ(pts.size(), mixed.size());
  pts = mixed;
  thinToReferenceBudget(pts, 0);
  EXPECT_EQ(pts.size(), mixed.size()) << "budget 0: no limit";
}

TEST(ReferenceBudget, MoreMapPointsThanTheBudgetKeepsThoseAlone) {
  const std::vector<DepthPoint> all = points(400, [](int i) { return i < 300; });
  std::vector<DepthPoint> pts = all;
  thinToReferenceBudget(pts, 200);
  ASSERT_EQ(pts.size(), 300u);
  for (const DepthPoint& p : pts) EXPECT_TRUE(p.from_map);
  const std::vector<DepthPoint> map_only = points(400, [](int) { return true; });
  pts = map_only;
  thinToReferenceBudget(pts, 200);
  EXPECT_EQ(pts.size(), 400u);
}

TEST(ReferenceBudget, RatioTimesActivePointsWithZeroForNoLimit) {
  EXPECT_EQ(referencePointBudget(0.0, 2000), 0);
  EXPECT_EQ(referencePointBudget(1.0, 2000), 2000);
  EXPECT_EQ(referencePointBudget(1.25, 2000), 2500);
  // A tiny ratio is the tightest budget, never "no limit".
  EXPECT_EQ(referencePointBudget(1e-5, 2000), 1);
}

}  // namespace
}  // namespace ldsm
