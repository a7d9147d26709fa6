#pragma once
// A 3D point of the map.
//
// Ownership and locking (docs/slam.md): the Map owns every MapPoint and frees none before it is destroyed itself;
// a point that is culled or fused into another is only marked bad (and, when fused, points to its replacement),
// so the non-owning pointers that frames and keyframes hold stay valid. Every member is read with
// Map::mutex() held, shared or exclusive, and changed with it held exclusively — except the tracking statistics
// (visible / found / outlier streak), which tracking updates under a shared lock and are therefore atomic.

#include <atomic>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "hoidslam/slam/data/sensor.h"

namespace hoidslam::slam {

class KeyFrame;
using MapPointId = std::uint64_t;
using KeyFrameId = std::uint64_t;
// Which of the Atlas's maps a keyframe belongs to (Map: several maps, one active).
using MapId = std::uint32_t;

class MapPoint {
 public:
  struct Observation {
    KeyFrame* keyframe = nullptr;
    int index = 0;  // keypoint index in the keyframe
  };

  MapPoint(MapPointId id, const Eigen::Vector3d& position_w, KeyFrameId first_keyframe_id, const cv::Mat& descriptor,
           cv::Vec3b color);
  MapPoint(const MapPoint&) = delete;
  MapPoint& operator=(const MapPoint&) = delete;

  MapPointId id() const { return id_; }
  KeyFrameId first_keyframe_id() const { return first_keyframe_id_; }
  const Eigen::Vector3d& position() const { return position_; }
  void SetPosition(const Eigen::Vector3d& position_w) { position_ = position_w; }
  const Eigen::Vector3d& normal() const { return normal_; }  // mean viewing direction, unit length
  const cv::Mat& descriptor() const { return descriptor_; }  // the observation descriptor closest to all others
  cv::Vec3b color() const { return color_; }                 // BGR, where it was first seen

  // Observations sorted by keyframe id.
  const std::vector<Observation>& observations() const { return observations_; }
  // ORB-SLAM's count: an observation with depth counts twice (it constrains the point like a stereo pair).
  int num_observations() const { return num_observations_; }
  int IndexIn(const KeyFrame* keyframe) const;  // -1 when not observed by it
  KeyFrame* reference_keyframe() const { return reference_keyframe_; }

  bool bad() const { return bad_; }
  MapPoint* replaced_by() const { return replaced_by_; }
  // Follows replacements to the point that stands for this one now (this one when never replaced).
  MapPoint* Current();

  // Scale-invariance: the distance range over which the ORB pyramid can see the point, and the level at which it
  // appears at `distance`.
  float min_distance() const { return 0.8F * min_distance_; }
  float max_distance() const { return 1.2F * max_distance_; }
  int PredictLevel(double distance, const features::ScalePyramid& pyramid) const;

  // Tracking statistics: frames in which the point was predicted visible, and in which it was matched.
  void IncreaseVisible(int n = 1) { visible_.fetch_add(n, std::memory_order_relaxed); }
  void IncreaseFound(int n = 1) { found_.fetch_add(n, std::memory_order_relaxed); }
  float FoundRatio() const;
  // The geometric safety net's count: how many times in a row the point was matched by a frame yet misfit its
  // pose. Returns the count after this frame.
  int RecordOutlier(bool outlier) {
    if (!outlier) {
      outlier_streak_.store(0, std::memory_order_relaxed);
      return 0;
    }
    return outlier_streak_.fetch_add(1, std::memory_order_relaxed) + 1;
  }

 private:
  friend class Map;  // the graph operations (observations, bad flag, replacement) go through the Map

  void AddObservation(KeyFrame* keyframe, int index);
  void EraseObservation(const KeyFrame* keyframe);
  // Normal, distance range and representative descriptor from the current observations.
  void UpdateFromObservations();

  MapPointId id_;
  KeyFrameId first_keyframe_id_;
  Eigen::Vector3d position_;
  Eigen::Vector3d normal_ = Eigen::Vector3d::Zero();
  float min_distance_ = 0.0F;
  float max_distance_ = 0.0F;
  cv::Mat descriptor_;
  cv::Vec3b color_;
  std::vector<Observation> observations_;
  int num_observations_ = 0;
  KeyFrame* reference_keyframe_ = nullptr;
  bool bad_ = false;
  MapPoint* replaced_by_ = nullptr;
  std::atomic<int> visible_{1};
  std::atomic<int> found_{1};
  std::atomic<int> outlier_streak_{0};
};

}  // namespace hoidslam::slam
