#include "hoidslam/slam/data/map_point.h"

#include <algorithm>
#include <cmath>

#include "hoidslam/features/orb_extractor.h"
#include "hoidslam/slam/data/keyframe.h"

namespace hoidslam::slam {

MapPoint::MapPoint(MapPointId id, const Eigen::Vector3d& position_w, KeyFrameId first_keyframe_id,
                   const cv::Mat& descriptor, cv::Vec3b color)
    : id_(id), first_keyframe_id_(first_keyframe_id), position_(position_w), descriptor_(descriptor.clone()),
      color_(color) {}

int MapPoint::IndexIn(const KeyFrame* keyframe) const {
  for (const Observation& o : observations_) {
    if (o.keyframe == keyframe) return o.index;
  }
  return -1;
}

MapPoint* MapPoint::Current() {
  MapPoint* point = this;
  while (point->replaced_by_ != nullptr) point = point->replaced_by_;
  return point;
}

int MapPoint::PredictLevel(double distance, const features::ScalePyramid& pyramid) const {
  if (pyramid.levels() <= 1 || distance <= 0.0) return 0;
  const double ratio = max_distance_ / distance;
  const int level = static_cast<int>(std::ceil(std::log(ratio) / std::log(static_cast<double>(pyramid.scale[1]))));
  return std::clamp(level, 0, pyramid.levels() - 1);
}

float MapPoint::FoundRatio() const {
  return static_cast<float>(found_.load(std::memory_order_relaxed)) /
         static_cast<float>(std::max(1, visible_.load(std::memory_order_relaxed)));
}

void MapPoint::AddObservation(KeyFrame* keyframe, int index) {
  if (IndexIn(keyframe) >= 0) return;
  const auto at = std::lower_bound(observations_.begin(), observations_.end(), keyframe->id(),
                                   [](const Observation& o, KeyFrameId id) { return o.keyframe->id() < id; });
  observations_.insert(at, {keyframe, index});
  num_observations_ += keyframe->keypoints().has_depth(index) ? 2 : 1;
  if (reference_keyframe_ == nullptr) reference_keyframe_ = keyframe;
}

void MapPoint::EraseObservation(const KeyFrame* keyframe) {
  const auto it = std::find_if(observations_.begin(), observations_.end(),
                               [keyframe](const Observation& o) { return o.keyframe == keyframe; });
  if (it == observations_.end()) return;
  num_observations_ -= keyframe->keypoints().has_depth(it->index) ? 2 : 1;
  observations_.erase(it);
  if (reference_keyframe_ == keyframe) reference_keyframe_ = observations_.empty() ? nullptr : observations_.front().keyframe;
}

void MapPoint::UpdateFromObservations() {
  if (observations_.empty() || reference_keyframe_ == nullptr) return;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const Observation& o : observations_) normal += (position_ - o.keyframe->center()).normalized();
  normal_ = normal.normalized();

  const KeypointSet& ref = reference_keyframe_->keypoints();
  const int ref_index = IndexIn(reference_keyframe_);
  const auto& pyramid = ref.sensor().pyramid;
  const float distance = static_cast<float>((position_ - reference_keyframe_->center()).norm());
  max_distance_ = distance * pyramid.scale[static_cast<std::size_t>(ref.level(ref_index))];
  min_distance_ = max_distance_ / pyramid.scale.back();

  // The representative descriptor: the observation with the least median distance to the others.
  const std::size_t n = observations_.size();
  if (n == 1) {
    descriptor_ = cv::Mat(1, 32, CV_8UC1, const_cast<std::uint8_t*>(ref.descriptor(ref_index))).clone();
    return;
  }
  std::vector<const std::uint8_t*> descriptors;
  descriptors.reserve(n);
  for (const Observation& o : observations_) descriptors.push_back(o.keyframe->keypoints().descriptor(o.index));
  std::vector<int> distances(n * n, 0);
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      distances[a * n + b] = distances[b * n + a] = features::DescriptorDistance(descriptors[a], descriptors[b]);
    }
  }
  int best_median = 257;
  std::size_t best = 0;
  std::vector<int> row(n);
  for (std::size_t a = 0; a < n; ++a) {
    std::copy_n(distances.begin() + static_cast<std::ptrdiff_t>(a * n), n, row.begin());
    std::nth_element(row.begin(), row.begin() + static_cast<std::ptrdiff_t>((n - 1) / 2), row.end());
    const int median = row[(n - 1) / 2];
    if (median < best_median) {
      best_median = median;
      best = a;
    }
  }
  std::copy_n(descriptors[best], 32, descriptor_.ptr());
}

}  // namespace hoidslam::slam
