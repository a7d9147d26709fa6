// TUM trajectories: the bytes are a trajectory file (`timestamp tx ty tz qx qy qz qw` lines).

#include "fuzz/targets.h"
#include "hoidslam/io/trajectory_file.h"

namespace hoidslam::fuzz {

void FuzzTrajectory(Bytes input) {
  const std::filesystem::path path = ScratchDir() / "trajectory.txt";
  WriteBytes(path, input);
  if (const auto trajectory = ParseOrReject([&] { return io::ReadTumTrajectory(path); }, path.string())) {
    CheckTrajectory(*trajectory);
  }
}

}  // namespace hoidslam::fuzz
