#pragma once
// Where the floor is, for the 2D occupancy grid: SLAM's world frame is the first camera's (z forward, y down),
// tilted as the camera was held.

#include "hoidslam/core/pose.h"
#include "hoidslam/dense/tsdf_volume.h"

namespace hoidslam::dense {

struct FloorFrame {
  // World → floor frame: z up along the floor's normal, the floor at z = 0, the origin under the first camera and x
  // along its view.
  core::Pose T_fw = core::Pose::Identity();
  bool found = false;  // false: no floor in view; "up" is then the first camera's and z = 0 the lowest surface
};

// The lowest horizontal surface with enough support (upward normals within 30° of the first camera's up, at least 5 %
// of those points within ±3 cm of one height), its plane fitted to them. `first_T_wc`: the first keyframe's pose.
FloorFrame EstimateFloor(const OrientedPoints& surface, const core::Pose& first_T_wc);

}  // namespace hoidslam::dense
