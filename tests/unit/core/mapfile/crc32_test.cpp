#include "mapfile/crc32.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ldsm::mapfile {
namespace {

std::uint32_t crcOf(const std::string& s, std::uint32_t previous = 0) {
  return crc32(reinterpret_cast<const std::uint8_t*>(s.data()), s.size(), previous);
}

TEST(Crc32, KnownValues) {
  EXPECT_EQ(crcOf(""), 0u);
  EXPECT_EQ(crcOf("a"), 0xE8B7BE43u);
  EXPECT_EQ(crcOf("123456789"), 0xCBF43926u);  // the CRC-32 check value
  EXPECT_EQ(crcOf("The quick brown fox jumps over the lazy dog"), 0x414FA339u);
}

TEST(Crc32, ContinuesOverPiecesAndAgreesWithTheBytewiseDefinition) {
  std::vector<std::uint8_t> data(1000);
  for (std::size_t i = 0; i < data.size(); ++i)
    data[i] = static_cast<std::uint8_t>(i * 7 + (i >> 3));
  // Bit by bit, the textbook way.
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::uint8_t b : data) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
  }
  const std::uint32_t whole = crc32(data.data(), data.size());
  EXPECT_EQ(whole, ~c);
  for (std::size_t cut : {0, 1, 7, 8, 9, 500, 999, 1000})
    EXPECT_EQ(crc32(data.data() + cut, data.size() - cut, crc32(data.data(), cut)), whole) << cut;
}

}  // namespace
}  // namespace ldsm::mapfile
