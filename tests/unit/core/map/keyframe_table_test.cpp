// The map store's keyframe table: records by id, copies that share blocks and never see a later
// change, and a count that follows the keyframes set.
#include <gtest/gtest.h>

#include <vector>

#include "map/keyframe_table.h"

namespace ldsm {
namespace {

KeyframeRecord record(int id, double x) {
  KeyframeRecord r;
  r.id = id;
  r.frame_index = 10 * id;
  r.timestamp = 0.5 * id;
  r.T_w_c = SE3d(SO3d(), Eigen::Vector3d(x, 0, 0));
  return r;
}

TEST(KeyframeTable, RecordsByIdWithGapsAndACount) {
  KeyframeTable t;
  EXPECT_EQ(t.size(), 0u);
  EXPECT_FALSE(t.has(0));
  EXPECT_FALSE(t.has(-1));
  t.set(record(3, 1.0));
  t.set(record(300, 2.0));  // beyond the first block
  EXPECT_EQ(t.size(), 301u);
  EXPECT_EQ(t.count(), 2u);
  EXPECT_FALSE(t.has(0));
  EXPECT_EQ(t[0].id, -1);
  EXPECT_TRUE(t.has(3));
  EXPECT_TRUE(t.has(300));
  EXPECT_FALSE(t.has(301));
  EXPECT_EQ(t[300].frame_index, 3000);
  t.set(record(-1, 9.0));  // no keyframe: not stored, nothing lost
  EXPECT_EQ(t.size(), 301u);
  EXPECT_EQ(t.count(), 2u);
  t.set(record(3, 5.0));  // an update is no new keyframe
  EXPECT_EQ(t.count(), 2u);
  EXPECT_DOUBLE_EQ(t[3].T_w_c.translation().x(), 5.0);
  std::vector<int> ids;
  t.forEach([&](const KeyframeRecord& r) { ids.push_back(r.id); });
  EXPECT_EQ(ids, std::vector<int>({3, 300}));
}

TEST(KeyframeTable, ACopyNeverSeesALaterChange) {
  KeyframeTable t;
  for (int id = 0; id < 3 * static_cast<int>(KeyframeTable::kBlockSize); ++id)
    t.set(record(id, id));
  const KeyframeTable published = t;  // what a snapshot holds
  t.edit(5).T_w_c = SE3d(SO3d(), Eigen::Vector3d(-1, 0, 0));
  t.edit(200).scale = 2.0;
  t.set(record(1000, 7.0));
  EXPECT_DOUBLE_EQ(published[5].T_w_c.translation().x(), 5.0);
  EXPECT_DOUBLE_EQ(published[200].scale, 1.0);
  EXPECT_EQ(published.size(), 3 * KeyframeTable::kBlockSize);
  EXPECT_EQ(published.count(), 3 * KeyframeTable::kBlockSize);
  EXPECT_DOUBLE_EQ(t[5].T_w_c.translation().x(), -1.0);
  EXPECT_DOUBLE_EQ(t[200].scale, 2.0);
  EXPECT_EQ(t.count(), 3 * KeyframeTable::kBlockSize + 1);
  // A block no copy shares any more is changed in place, and the copy taken after it sees it.
  const KeyframeTable later = t;
  t.edit(6).scale = 3.0;
  EXPECT_DOUBLE_EQ(later[6].scale, 1.0);
  EXPECT_DOUBLE_EQ(t[6].scale, 3.0);
}

}  // namespace
}  // namespace ldsm
