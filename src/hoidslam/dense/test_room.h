#pragma once
// A box room for the occupancy tests and benchmark (test-only, header-only): depth images of it seen from inside,
// each pixel's ray cast against the walls, floor and ceiling and the solid boxes in the room.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"

namespace hoidslam::dense::test_room {

struct Box {
  Eigen::Vector3d min, max;
};

// Floor frame: the room spans [0, size.x] × [0, size.y] × [0, size.z], z up, the floor at 0.
struct Room {
  Eigen::Vector3d size{4.0, 3.0, 2.5};
  std::vector<Box> solids;
};

// A crate on the floor, its top inside the default height band [0.1, 1.8] m.
inline const Box kCrate{{0.5, 0.5, 0.0}, {1.0, 1.0, 0.6}};
// A shelf on the wall y = 3, above the band: a robot passes under it.
inline const Box kShelf{{1.0, 2.6, 1.9}, {3.0, 3.0, 2.0}};

inline Room TestRoom() { return Room{.solids = {kCrate, kShelf}}; }

// The distance along o + t d at which the ray enters `box`, infinity when it misses it (slab method).
inline double EntryDistance(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double enter = 0.0;
  double leave = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double t1 = (box.min[axis] - o[axis]) / d[axis];
    const double t2 = (box.max[axis] - o[axis]) / d[axis];
    enter = std::max(enter, std::min(t1, t2));
    leave = std::min(leave, std::max(t1, t2));
  }
  return enter <= leave ? enter : std::numeric_limits<double>::infinity();
}

// The depth image (CV_32FC1, metres) of `room` from a camera at T_fc (camera to floor frame) inside it.
inline cv::Mat RenderDepth(const Room& room, const core::CameraIntrinsics& camera, const core::Pose& T_fc) {
  cv::Mat depth(camera.height, camera.width, CV_32FC1);
  const Eigen::Vector3d o = T_fc.translation();
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      // A direction of camera depth 1: the distance along it is the depth.
      const Eigen::Vector3d d = T_fc.linear() * camera.Unproject(u, v, 1.0);
      double t = std::numeric_limits<double>::infinity();
      for (int axis = 0; axis < 3; ++axis) {  // the wall, floor or ceiling the ray leaves the room through
        if (d[axis] != 0.0) t = std::min(t, ((d[axis] > 0.0 ? room.size[axis] : 0.0) - o[axis]) / d[axis]);
      }
      for (const Box& solid : room.solids) t = std::min(t, EntryDistance(solid, o, d));
      depth.at<float>(v, u) = static_cast<float>(t);
    }
  }
  return depth;
}

// Camera poses (camera to floor frame) at the room's middle, 1 m above the floor: 8 headings, each level and tilted
// 40° down and up, which together see all of the walls, the floor and the ceiling.
inline std::vector<core::Pose> RoomViews(const Room& room) {
  // Camera axes (x right, y down, z forward) in the floor frame, looking along +x.
  Eigen::Matrix3d level;
  level.col(0) = -Eigen::Vector3d::UnitY();
  level.col(1) = -Eigen::Vector3d::UnitZ();
  level.col(2) = Eigen::Vector3d::UnitX();
  std::vector<core::Pose> views;
  for (int heading = 0; heading < 8; ++heading) {
    for (const double tilt_degrees : {-40.0, 0.0, 40.0}) {
      core::Pose T_fc = core::Pose::Identity();
      T_fc.linear() = Eigen::AngleAxisd(heading * std::numbers::pi / 4.0, Eigen::Vector3d::UnitZ()) * level *
                      Eigen::AngleAxisd(tilt_degrees * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX());
      T_fc.translation() = Eigen::Vector3d(room.size.x() / 2.0, room.size.y() / 2.0, 1.0);
      views.push_back(T_fc);
    }
  }
  return views;
}

}  // namespace hoidslam::dense::test_room
