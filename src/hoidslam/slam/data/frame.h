#pragma once
// The frame being tracked: its keypoints, the map points matched to them and the pose estimated from them.
// Owned by the tracker; holds non-owning pointers into the Map (valid for the Map's lifetime, see map.h).

#include <cstdint>
#include <memory>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/slam/data/keypoints.h"
#include "hoidslam/slam/data/map_point.h"

namespace hoidslam::slam {

class KeyFrame;

struct Frame {
  Frame(std::uint64_t id, double timestamp, std::shared_ptr<const KeypointSet> keypoints)
      : id(id), timestamp(timestamp), keypoints(std::move(keypoints)),
        map_points(static_cast<std::size_t>(this->keypoints->size()), nullptr),
        outlier(static_cast<std::size_t>(this->keypoints->size()), 0) {}

  int size() const { return keypoints->size(); }
  // Keypoint i has a map point that the last pose optimisation kept.
  bool IsInlier(int i) const {
    const auto k = static_cast<std::size_t>(i);
    return map_points[k] != nullptr && outlier[k] == 0;
  }
  Eigen::Vector3d center() const { return T_cw.inverse().translation(); }

  std::uint64_t id;
  double timestamp;
  double depth_delay = 0.0;  // seconds from the colour image to the depth image (core::RgbdFrame::depth_delay)
  std::shared_ptr<const KeypointSet> keypoints;
  std::vector<MapPoint*> map_points;  // per keypoint, nullptr: unmatched
  std::vector<std::uint8_t> outlier;  // per keypoint, from the last pose optimisation
  core::Pose T_cw = core::Pose::Identity();
  KeyFrame* reference_keyframe = nullptr;
};

}  // namespace hoidslam::slam
