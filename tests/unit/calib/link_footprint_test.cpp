// The memory baseline: the ldsm tool must not load OpenCV imgcodecs or videoio (they bring GDAL,
// HDF5, FFmpeg, GStreamer... tens of MB of resident memory), and reading images must not load
// the video plugin.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/dataset_source.h"
#include "test_paths.h"

namespace ldsm {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

#ifdef LDSM_EXE
TEST(LinkFootprint, LdsmToolLoadsNeitherImgcodecsNorVideoio) {
  std::string out;
#ifdef LDSM_TEST_EMULATED
  // Cross build run under qemu-user: the host's ldd cannot read the target's tool, so the target's
  // dynamic loader lists the libraries itself (as ldd makes it do), told so through qemu.
  const std::string list_libraries =
      std::string("QEMU_SET_ENV=LD_TRACE_LOADED_OBJECTS=1 ") + LDSM_EXE;
#else
  if (test::runCommand("ldd --version", &out) != 0) GTEST_SKIP() << "no ldd";
  const std::string list_libraries = std::string("ldd ") + LDSM_EXE;
#endif
  ASSERT_EQ(test::runCommand(list_libraries, &out), 0) << out;
  EXPECT_THAT(out, HasSubstr("libopencv_core"));  // the listing is real
  EXPECT_THAT(out, Not(HasSubstr("opencv_imgcodecs")));
  EXPECT_THAT(out, Not(HasSubstr("opencv_videoio")));
  EXPECT_THAT(out, Not(HasSubstr("libgdal")));
  EXPECT_THAT(out, Not(HasSubstr("libavcodec")));
}
#endif

std::string mappedFiles() {
  std::ifstream maps("/proc/self/maps");
  std::stringstream s;
  s << maps.rdbuf();
  return s.str();
}

TEST(LinkFootprint, ReadingImagesDoesNotLoadTheVideoPlugin) {
  const std::string dir = test::scratchDir("imageio/footprint");
  ImageU8 frame(8, 6, 50);
  for (int k = 0; k < 3; ++k) calib::writePng(dir + "/" + std::to_string(k) + ".png", frame.view());
  auto source = drivers::openDataset(dir);
  drivers::Frame f;
  int n = 0;
  while (source->next(f)) ++n;
  EXPECT_EQ(n, 3);
  const std::string maps = mappedFiles();
  ASSERT_THAT(maps, HasSubstr("libpng"));
  EXPECT_THAT(maps, Not(HasSubstr("libldsm_video_plugin")));
  EXPECT_THAT(maps, Not(HasSubstr("opencv_videoio")));
}

}  // namespace
}  // namespace ldsm
