#pragma once
// What the synthetic renderer draws: a snapshot of the world at one instant, built from textured boxes.
//
// The scene model (scenario, people, actions) produces one SceneSnapshot per frame; the renderer turns a
// snapshot and a camera pose into colour, depth and an instance-id image. Everything is in metres, world
// frame z up; poses follow the project convention (T_wb maps box coordinates to world).

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/pose.h"

namespace hoidslam::synth {

// Instance id 0 is reserved for "nothing drawn" in instance-id images.
inline constexpr int kNoInstance = 0;

// A solid box: the unit of all synthetic geometry (walls, desks, monitors, limbs, cups...).
struct Box {
  core::Pose T_wb = core::Pose::Identity();        // box centre and orientation in the world
  Eigen::Vector3d half_size = {0.5, 0.5, 0.5};     // half extents along the box's own x, y, z, metres
  int texture = 0;                                 // index into the renderer's texture set
  double texture_scale = 1.0;                      // metres covered by one repeat of the texture
  cv::Vec3f tint = {1.0F, 1.0F, 1.0F};             // per-channel (B, G, R) multiplier on the texture
};

// Corner `i` (0..7) of a box of `half_size` in the box's own frame: bit a of `i` set puts it on the + side of axis a.
inline Eigen::Vector3d BoxCorner(const Eigen::Vector3d& half_size, int i) {
  return {(i & 1) ? half_size.x() : -half_size.x(), (i & 2) ? half_size.y() : -half_size.y(),
          (i & 4) ? half_size.z() : -half_size.z()};
}

// A thing the benchmark knows by name: the room, a desk, a person, a cup.
struct SceneInstance {
  int id = kNoInstance;       // > 0, unique in the scene and stable over the whole sequence
  std::string label;          // COCO label ("person", "cup", "tv", ...) or "" for structure (walls, desks)
  bool moving = false;        // true at this instant when it moves (a walking person, a carried cup)
  std::vector<Box> parts;
};

struct SceneSnapshot {
  double timestamp = 0.0;     // seconds
  std::vector<SceneInstance> instances;
};

}  // namespace hoidslam::synth
