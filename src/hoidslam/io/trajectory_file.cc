#include "hoidslam/io/trajectory_file.h"

#include <array>
#include <map>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/text_lines.h"

namespace hoidslam::io {

using core::InputError;

core::Trajectory ReadTumTrajectory(const std::filesystem::path& path) {
  // A map keyed by timestamp: a repeated timestamp keeps its last pose, as TUM's read_file_list does.
  std::map<double, core::Pose> poses;
  ForEachDataLine(path, [&](std::size_t line_number, const std::vector<std::string_view>& fields) {
    if (fields.size() != 8) {
      throw InputError::AtLine(path, line_number,
                               fmt::format("expected 8 values 'timestamp tx ty tz qx qy qz qw', found {}", fields.size()));
    }
    std::array<double, 8> v{};
    for (std::size_t i = 0; i < 8; ++i) v[i] = ParseDouble(fields[i], path, line_number);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (q.norm() < 1e-9) throw InputError::AtLine(path, line_number, "quaternion is zero");
    poses[v[0]] = core::PoseFromTranslationQuaternion({v[1], v[2], v[3]}, q);
  });
  core::Trajectory trajectory;
  trajectory.reserve(poses.size());
  for (const auto& [timestamp, pose] : poses) trajectory.push_back({timestamp, pose});
  return trajectory;
}

void WriteTumTrajectory(const std::filesystem::path& path, const core::Trajectory& trajectory) {
  AtomicFile file(path);
  file.stream() << "# timestamp tx ty tz qx qy qz qw\n";
  for (const core::StampedPose& stamped : trajectory) {
    const Eigen::Vector3d t = stamped.T_wc.translation();
    const Eigen::Quaterniond q(stamped.T_wc.rotation());
    file.stream() << fmt::format("{:.6f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}\n", stamped.timestamp,
                                 t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  }
  file.Commit();
}

}  // namespace hoidslam::io
