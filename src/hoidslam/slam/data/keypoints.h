#pragma once
// The keypoints of one RGB-D frame that tracking may use — those the exclusion filter kept — with what tracking
// and mapping compute from them: undistorted positions, depth and the virtual right coordinate, descriptors, the
// colour under each keypoint (for the map's point cloud), and a grid for searching by position. Immutable once
// built, so a frame and the keyframe made from it share one copy.

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/slam/data/measurement.h"
#include "hoidslam/slam/data/sensor.h"

namespace hoidslam::slam {

class KeypointSet {
 public:
  // `keypoints` and `descriptors` (one row each) as extracted, already filtered; `depth` (CV_32FC1, metres, 0 =
  // invalid) and `bgr` (CV_8UC3) the frame's images, sampled at the (distorted) keypoint positions.
  KeypointSet(std::shared_ptr<const Sensor> sensor, std::vector<cv::KeyPoint> keypoints, cv::Mat descriptors,
              const cv::Mat& depth, const cv::Mat& bgr);
  // The same from each keypoint's depth (metres; 0, negative or not finite = invalid) and colour as sampled
  // before (a saved map's keyframes); `depth` and `colors` have one entry per keypoint.
  KeypointSet(std::shared_ptr<const Sensor> sensor, std::vector<cv::KeyPoint> keypoints, cv::Mat descriptors,
              std::vector<float> depth, std::vector<cv::Vec3b> colors);

  const Sensor& sensor() const { return *sensor_; }
  const std::shared_ptr<const Sensor>& shared_sensor() const { return sensor_; }
  int size() const { return static_cast<int>(keypoints_.size()); }

  const cv::KeyPoint& keypoint(int i) const { return keypoints_[static_cast<std::size_t>(i)]; }  // as extracted
  const std::vector<cv::KeyPoint>& keypoints() const { return keypoints_; }
  const Eigen::Vector2d& undistorted(int i) const { return undistorted_[static_cast<std::size_t>(i)]; }
  int level(int i) const { return keypoint(i).octave; }
  float depth(int i) const { return depth_[static_cast<std::size_t>(i)]; }  // metres, 0 when invalid
  bool has_depth(int i) const { return depth(i) > 0.0F; }
  double right(int i) const { return right_[static_cast<std::size_t>(i)]; }  // u - bf / depth, when has_depth
  const std::uint8_t* descriptor(int i) const { return descriptors_.ptr(i); }
  const cv::Mat& descriptors() const { return descriptors_; }
  cv::Vec3b color(int i) const { return colors_[static_cast<std::size_t>(i)]; }
  int num_with_depth() const { return num_with_depth_; }

  // The measurement an optimiser uses for keypoint i.
  KeypointMeasurement Measurement(int i) const;
  // Keypoint i in camera coordinates (needs has_depth(i)).
  Eigen::Vector3d Unproject(int i) const;

  // Indices of keypoints within `radius` pixels (square window) of undistorted (u, v) whose level is in
  // [min_level, max_level] (max_level < 0: no upper bound), in index order.
  std::vector<int> FeaturesInArea(double u, double v, double radius, int min_level = 0, int max_level = -1) const;
  // The same into `found` (cleared first): matching asks this for every projected point, and a buffer kept by the
  // caller saves an allocation each time.
  void FeaturesInArea(double u, double v, double radius, int min_level, int max_level, std::vector<int>& found) const;

 private:
  std::shared_ptr<const Sensor> sensor_;
  std::vector<cv::KeyPoint> keypoints_;
  std::vector<Eigen::Vector2d> undistorted_;
  std::vector<float> depth_;
  std::vector<double> right_;
  cv::Mat descriptors_;
  std::vector<cv::Vec3b> colors_;
  int num_with_depth_ = 0;
  // The grid in compressed form: keypoints of cell c are cell_indices_[cell_start_[c] .. cell_start_[c + 1]).
  std::vector<int> cell_start_;
  std::vector<int> cell_indices_;
};

}  // namespace hoidslam::slam
