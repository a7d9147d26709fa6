#pragma once
// Placing a tracked frame again once the map is adjusted at the end (System::Finish). A frame that is not a keyframe
// is kept as its pose relative to its reference keyframe (Tracker::FrameRecord), and ORB-SLAM carries it rigidly
// with that keyframe; but the adjustment may move the keyframe against the very points the frame was tracked on.
// So each frame keeps its inliers, compactly, and is placed again by them against the adjusted points.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/core/pose.h"
#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/data/map.h"
#include "hoidslam/slam/data/sensor.h"

namespace hoidslam::slam {

// One inlier of a tracked frame as its record keeps it, in 8 bytes (a long run keeps a few hundred for each of its
// frames: 3600 frames of `loop`, some 13 MB): the map point's id (24 bits), the undistorted position in quarter
// pixels (13 bits each, up to 2048), the pyramid level (3 bits) and the disparity u − ur in quarter pixels (11 bits,
// up to 512; 0: the keypoint had no depth). The rounding (0.07 pixel at its standard deviation) is far below the
// pixel a keypoint is weighed with.
class RecordedInlier {
 public:
  // nullopt when a value does not fit: a point made after the first 16.7 million of a run, a position off the image
  // or beyond 2048 pixels, a disparity beyond 512 pixels. The frame keeps its other inliers.
  static std::optional<RecordedInlier> Make(MapPointId point, const Eigen::Vector2d& uv, int level,
                                            std::optional<double> disparity);

  MapPointId point() const { return bits_ >> 40; }
  Eigen::Vector2d uv() const;
  int level() const { return static_cast<int>((bits_ >> 11) & 0x7); }
  bool has_depth() const { return (bits_ & 0x7FF) != 0; }
  double disparity() const;  // pixels, when has_depth()

 private:
  explicit RecordedInlier(std::uint64_t bits) : bits_(bits) {}
  std::uint64_t bits_;  // point 24 | u 13 | v 13 | level 3 | disparity 11
};

// The inliers of `frame` (its map points that the last pose optimisation kept), those RecordedInlier can hold.
std::vector<RecordedInlier> RecordInliers(const Frame& frame);

// A frame placed again needs this many inliers, and half of those still in the map, agreeing on its pose.
inline constexpr int kMinPlacementInliers = 20;

// The pose (T_cw) that `inliers`, seen with `sensor`, give against the points of `map` as they now stand (a point
// fused into another: that one; an erased one: left out), optimised from `T_cw` (where the frame's reference keyframe
// now puts it). nullopt when fewer than kMinPlacementInliers of them, or fewer than half of those in the map, agree.
// The map's lock is the caller's.
std::optional<core::Pose> PlaceByInliers(const Map& map, std::span<const RecordedInlier> inliers, const Sensor& sensor,
                                         const core::Pose& T_cw);

}  // namespace hoidslam::slam
