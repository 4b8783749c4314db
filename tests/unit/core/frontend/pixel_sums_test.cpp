// PixelSums: cells by pixel index, absent pixels read as zero, growth keeps the cells, clear()
// forgets them.
#include "frontend/pixel_sums.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <unordered_map>

namespace ldsm {
namespace {

TEST(PixelSums, CellsByPixelAcrossGrowthAndClear) {
  PixelSums table(4);
  EXPECT_EQ(table.find(7), nullptr);
  EXPECT_EQ(table.weight(7), 0.f);
  EXPECT_EQ(table.sum(7), 0.f);
  std::unordered_map<int, PixelSums::Cell> expected;
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> pixel(0, 450000);
  for (int i = 0; i < 20000; ++i) {
    const int p = pixel(rng);
    PixelSums::Cell& c = table.insert(p);
    c.sum += 1.5f;
    c.weight += 1.f;
    c.from_map = static_cast<unsigned char>(p % 2);
    PixelSums::Cell& e = expected[p];
    e.sum += 1.5f;
    e.weight += 1.f;
    e.from_map = static_cast<unsigned char>(p % 2);
  }
  EXPECT_EQ(table.size(), expected.size());
  for (const auto& [p, e] : expected) {
    const PixelSums::Cell* c = table.find(p);
    ASSERT_NE(c, nullptr) << p;
    EXPECT_EQ(c->sum, e.sum);
    EXPECT_EQ(c->weight, e.weight);
    EXPECT_EQ(c->from_map, e.from_map);
  }
  for (int p = 450001; p < 451000; ++p) EXPECT_EQ(table.find(p), nullptr);
  const std::size_t bytes = table.bytes();
  EXPECT_LE(bytes, 64u * 1024 * (sizeof(int) + sizeof(PixelSums::Cell) + 4));  // at most half empty
  table.clear();
  EXPECT_EQ(table.size(), 0u);
  EXPECT_EQ(table.bytes(), bytes);  // the memory stays for the next build
  for (const auto& [p, e] : expected) ASSERT_EQ(table.find(p), nullptr) << p;
  EXPECT_EQ(table.insert(12).weight, 0.f);  // a new cell is zero
  EXPECT_EQ(table.get(13).sum, 0.f);
}

// A table bounded by its level's pixels becomes a plane of one slot per pixel instead of growing
// past it, and reads and clears as before.
TEST(PixelSums, ADenseLevelBecomesAPlaneOfItsPixels) {
  constexpr int kPixels = 5000;
  PixelSums table(16, kPixels);
  std::mt19937 rng(2);
  std::uniform_int_distribution<int> pixel(0, kPixels - 1);
  std::unordered_map<int, float> expected;
  for (int i = 0; i < 20000; ++i) {
    const int p = pixel(rng);
    table.insert(p).sum += 1.f;
    expected[p] += 1.f;
  }
  EXPECT_EQ(table.size(), expected.size());
  EXPECT_GT(table.size(), 4000u);
  // One slot per pixel at most (a hash table this full would take 8192 slots).
  EXPECT_LE(table.bytes(),
            kPixels * (sizeof(int) + sizeof(PixelSums::Cell)) + kPixels * sizeof(std::uint32_t));
  for (int p = 0; p < kPixels; ++p) {
    const auto it = expected.find(p);
    if (it == expected.end()) {
      EXPECT_EQ(table.find(p), nullptr) << p;
    } else {
      const PixelSums::Cell* c = table.find(p);
      ASSERT_NE(c, nullptr) << p;
      EXPECT_EQ(table.sum(p), it->second);
    }
  }
  table.clear();
  EXPECT_EQ(table.size(), 0u);
  for (int p = 0; p < kPixels; ++p) ASSERT_EQ(table.find(p), nullptr) << p;
  table.insert(4999).weight = 2.f;
  EXPECT_EQ(table.weight(4999), 2.f);
  EXPECT_EQ(table.weight(4998), 0.f);
}

}  // namespace
}  // namespace ldsm
