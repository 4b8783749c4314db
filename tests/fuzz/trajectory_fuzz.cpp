// Trajectory files as `ldsm eval` reads them: TUM, KITTI poses, EuRoC ground-truth CSV, detected
// or named (the first byte picks), and timestamp lists.
#include "fuzz_input.h"
#include "ldsm/drivers/trajectory_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using ldsm::drivers::TrajectoryFormat;
  const std::string path = ldsm::fuzz::asFile(data + 1, size - 1, "trajectory.txt");
  ldsm::fuzz::parseOrReject([&] {
    switch (data[0] % 5) {
      case 0:
        ldsm::drivers::readTrajectory(path, TrajectoryFormat::Auto);
        break;
      case 1:
        ldsm::drivers::readTrajectory(path, TrajectoryFormat::Tum);
        break;
      case 2:
        ldsm::drivers::readTrajectory(path, TrajectoryFormat::Kitti);
        break;
      case 3:
        ldsm::drivers::readTrajectory(path, TrajectoryFormat::EurocCsv);
        break;
      default:
        ldsm::drivers::readTimestampList(path);
        break;
    }
  });
  return 0;
}
