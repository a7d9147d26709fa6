#pragma once
// Trajectories in TUM format: one pose per line, `timestamp tx ty tz qx qy qz qw`, camera-to-world.

#include <filesystem>

#include "hoidslam/core/pose.h"

namespace hoidslam::io {

// Reads a TUM trajectory as TUM's own tools do: '#' comment lines and blank lines are skipped, fields may be
// separated by spaces, tabs or commas, and a repeated timestamp keeps its last pose. The result is sorted by
// time. Throws InputError "<file>:<line>: ..." for a line that is not 8 numbers or has a zero quaternion.
core::Trajectory ReadTumTrajectory(const std::filesystem::path& path);

// Writes atomically (complete or absent), with microsecond timestamps and sub-micrometre positions.
void WriteTumTrajectory(const std::filesystem::path& path, const core::Trajectory& trajectory);

}  // namespace hoidslam::io
