#pragma once
// Data association between keypoints and map points: by projection (a predicted position, a search window that
// grows with the pyramid level, the nearest descriptor) and by descriptor alone (when no pose prediction can be
// trusted). Every function reads the map and expects Map::mutex() held by the caller, shared at least.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/features/orb_extractor.h"
#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/data/keyframe.h"

namespace hoidslam::slam {

// Descriptor distance limits (bits of 256): a strict one for matching without a pose prior, a loose one with.
inline constexpr int kDescriptorDistanceLow = 50;
inline constexpr int kDescriptorDistanceHigh = 100;

// Matches the map points of `last` (its inliers) into `current`, projected with current.T_cw; the window is
// `radius` pixels at level 0, scaled with the level. Keeps only matches whose orientation change agrees with
// the dominant ones. Returns the number of new matches (written into current.map_points).
int SearchByProjection(Frame& current, const Frame& last, double radius);

// A map point predicted to be visible in a frame: where and at which pyramid level.
struct ProjectedPoint {
  MapPoint* point = nullptr;
  Eigen::Vector2d uv;
  double ur = 0.0;
  int level = 0;
  double view_cos = 1.0;
};

// Projects `point` into a camera at T_cw: true when it lies in front, inside the image, within the point's
// scale-invariance distance range and seen at less than acos(min_view_cos) from its mean viewing direction.
bool ProjectIntoFrame(const MapPoint& point, const core::Pose& T_cw, const Sensor& sensor, double min_view_cos,
                      ProjectedPoint& projected);

// Matches predicted-visible points to `frame` keypoints still unmatched; window `radius` pixels at level 0
// (widened for oblique views), descriptors at most `max_distance` apart. Returns the number of matches.
int SearchByProjection(Frame& frame, std::span<const ProjectedPoint> points, double radius,
                       int max_distance = kDescriptorDistanceHigh);

// Matches the keyframe's map points to the frame's keypoints by descriptor alone (nearest neighbour, ratio
// test, orientation consistency). matches[i] is the map point of frame keypoint i, or nullptr. Returns the count.
int SearchByDescriptor(const KeyFrame& keyframe, const Frame& frame, std::vector<MapPoint*>& matches,
                       float ratio = 0.7F);

// Matches the keyframe's map points to the frame's keypoints as SearchByDescriptor does, but comparing only
// keypoints under the same node of the vocabulary's tree (the keyframe's direct index, and `frame_features`, the
// frame's, both kBowMatchingLevelsUp): ORB-SLAM's guided matching, a tenth of the comparisons.
int SearchByBoW(const KeyFrame& keyframe, const Frame& frame, const bow::FeatureVector& frame_features,
                std::vector<MapPoint*>& matches, float ratio = 0.7F);

// Hamming distance of a map point's descriptor and keypoint i of `keypoints`.
int DescriptorDistance(const MapPoint& point, const KeypointSet& keypoints, int i);

// The nearest and the second-nearest to one descriptor (Hamming distance) of candidate descriptors offered one at
// a time: the nearest for a match, both distances for a ratio test. Only a candidate within max_distance can be the
// nearest: it is as if one at max_distance + 1 had been offered first, so once there is a nearest, the second
// distance is at most max_distance + 1. With the default, 256 (further than any two descriptors) stands for none.
class NearestTwo {
 public:
  explicit NearestTwo(const std::uint8_t* descriptor, int max_distance = 255)
      : descriptor_(descriptor), best_distance_(max_distance + 1) {}

  // Candidate `index`, whose descriptor is `candidate`.
  void Offer(int index, const std::uint8_t* candidate) {
    const int d = features::DescriptorDistance(descriptor_, candidate);
    if (d < best_distance_) {
      second_distance_ = best_distance_;
      best_distance_ = d;
      best_ = index;
    } else if (d < second_distance_) {
      second_distance_ = d;
    }
  }

  int best() const { return best_; }  // the nearest candidate's index; -1: none within max_distance
  int best_distance() const { return best_distance_; }
  int second_distance() const { return second_distance_; }

 private:
  const std::uint8_t* descriptor_;
  int best_ = -1;
  int best_distance_;
  int second_distance_ = 256;
};

// Keeps the matches whose keypoint orientation change falls in the three most common 12° bins (the others are
// removed, i.e. set to nullptr in `matches`). `angle_change[i]` is only read where matches[i] is set.
void KeepConsistentRotations(std::vector<MapPoint*>& matches, std::span<const float> angle_change);
// The same for matches between keypoints: partner[i] < 0 means none; inconsistent ones are set to -1.
void KeepConsistentRotations(std::vector<int>& partner, std::span<const float> angle_change);

}  // namespace hoidslam::slam
