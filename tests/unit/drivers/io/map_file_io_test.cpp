// Map files on disk: reading names the path, writing is atomic.
#include "ldsm/drivers/map_file_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "ldsm/error.h"
#include "mapfile/map_codec.h"
#include "synthetic_map.h"
#include "test_paths.h"

namespace ldsm {
namespace {

namespace fs = std::filesystem;

std::string errorOf(const std::string& path) {
  try {
    drivers::readMapFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return {};
}

TEST(MapFileIo, WriteThenReadGivesTheSameBytesAndMap) {
  const std::string dir = test::scratchDir("map_file_io");
  const std::vector<std::uint8_t> bytes = encodeMap(test::syntheticMap({}));
  const std::string path = dir + "/office.ldsmmap";
  drivers::writeMapFile(path, bytes);
  EXPECT_EQ(drivers::readMapFile(path), bytes);
  // Overwriting replaces the file whole, leaving no temporary file behind.
  test::SyntheticMapSize size;
  size.keyframes = 3;
  const std::vector<std::uint8_t> smaller = encodeMap(test::syntheticMap(size));
  drivers::writeMapFile(path, smaller);
  const std::vector<std::uint8_t> read = drivers::readMapFile(path);
  EXPECT_EQ(read, smaller);
  EXPECT_NO_THROW(decodeMap(read.data(), read.size(), path));
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "office.ldsmmap");
  }
  EXPECT_EQ(files, 1u);
}

TEST(MapFileIo, AMissingOrUnreadableFileNamesThePath) {
  const std::string dir = test::scratchDir("map_file_io_missing");
  EXPECT_EQ(errorOf(dir + "/none.ldsmmap"), dir + "/none.ldsmmap: cannot open (no such file)");
  EXPECT_NE(errorOf(dir).find(dir + ": cannot open: it is a folder"), std::string::npos);
  if (::geteuid() != 0) {  // root reads anything
    const std::string locked = dir + "/locked.ldsmmap";
    drivers::writeMapFile(locked, {1, 2, 3});
    ::chmod(locked.c_str(), 0);
    EXPECT_NE(errorOf(locked).find(locked + ": cannot open"), std::string::npos);
  }
}

TEST(MapFileIo, AFailedWriteNamesThePathAndLeavesTheOldFile) {
  const std::string dir = test::scratchDir("map_file_io_fail");
  try {
    drivers::writeMapFile(dir + "/no/such/folder/m.ldsmmap", {1, 2, 3});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/no/such/folder/m.ldsmmap: cannot write"),
              std::string::npos)
        << e.what();
  }
  // The target is a folder: the rename fails, the temporary file is removed.
  fs::create_directories(dir + "/taken");
  fs::create_directories(dir + "/taken/inside");
  EXPECT_THROW(drivers::writeMapFile(dir + "/taken", {1, 2, 3}), Error);
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++entries;
    EXPECT_EQ(e.path().filename(), "taken");
  }
  EXPECT_EQ(entries, 1u);
}

}  // namespace
}  // namespace ldsm
