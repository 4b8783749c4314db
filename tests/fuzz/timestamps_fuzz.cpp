// Frame lists: TUM-Mono times.txt, EuRoC data.csv, TUM RGB-D rgb.txt, KITTI times.txt. The first
// byte picks the reader, the rest is the file.
#include "dataset/timestamp_files.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path = ldsm::fuzz::asFile(data + 1, size - 1, "times.txt");
  ldsm::fuzz::parseOrReject([&] {
    switch (data[0] % 4) {
      case 0:
        ldsm::drivers::detail::readTumMonoTimes(path);
        break;
      case 1:
        ldsm::drivers::detail::readEurocImageCsv(path);
        break;
      case 2:
        ldsm::drivers::detail::readTumRgbdList(path);
        break;
      default:
        ldsm::drivers::detail::readKittiTimes(path);
        break;
    }
  });
  return 0;
}
