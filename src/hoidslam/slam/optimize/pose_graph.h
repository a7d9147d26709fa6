#pragma once
// Pose-graph optimisation of keyframe poses alone (ORB-SLAM's essential graph, in SE(3): depth fixes the scale):
// each edge holds the relative pose two keyframes should have, and the poses are moved so that every edge holds as
// nearly as it can. After a loop is closed, this spreads the correction found at the loop over the keyframes
// between its two ends. On plain data, so it can be tested on its own and run without the map's lock held.

#include <cstdint>
#include <vector>

#include "hoidslam/core/pose.h"

namespace hoidslam::slam {

struct PoseGraphProblem {
  std::vector<core::Pose> T_cw;          // one per keyframe, world to camera
  std::vector<std::uint8_t> pose_fixed;  // one per keyframe: 1 = held constant (at least one must be)
  struct Edge {
    int from = 0;  // indices into T_cw
    int to = 0;
    core::Pose T_from_to;  // the relative pose T_from,w · T_to,w⁻¹ the edge asks for (camera `to` into camera `from`)
  };
  std::vector<Edge> edges;
};

struct PoseGraphOptions {
  int iterations = 20;  // Levenberg-Marquardt, as ORB-SLAM
};

// Refines the poses not fixed in place. Every edge weighs the same: its rotation error in radians and its
// translation error in metres. Returns the iterations run. Deterministic (one thread). Throws
// std::invalid_argument for indices out of range, a pose_fixed of the wrong size, or no pose fixed.
int OptimizePoseGraph(PoseGraphProblem& problem, const PoseGraphOptions& options = {});

}  // namespace hoidslam::slam
