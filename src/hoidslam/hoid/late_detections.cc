#include "hoidslam/hoid/late_detections.h"

#include <algorithm>
#include <optional>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/hoid/foreground.h"

namespace hoidslam::hoid {

void LateDetectionOptions::Check() const {
  if (!(grow_per_frame >= 0.0 && grow_per_frame <= 1.0)) {
    throw core::InputError::ForParameter("grow_per_frame", fmt::format("must be in [0, 1], got {}", grow_per_frame));
  }
  if (!(max_grow >= 0.0 && max_grow <= 2.0)) {
    throw core::InputError::ForParameter("max_grow", fmt::format("must be in [0, 2], got {}", max_grow));
  }
  if (!(search_margin >= 0.0 && search_margin <= 2.0)) {
    throw core::InputError::ForParameter("search_margin", fmt::format("must be in [0, 2], got {}", search_margin));
  }
  if (!(max_motion > 0.0)) throw core::InputError::ForParameter("max_motion", fmt::format("must be > 0, got {}", max_motion));
  if (!(max_motion_per_frame >= 0.0)) {
    throw core::InputError::ForParameter("max_motion_per_frame",
                                         fmt::format("must be >= 0, got {}", max_motion_per_frame));
  }
  if (max_frames < 1) throw core::InputError::ForParameter("max_frames", "must be at least 1");
}

namespace {

// A box's motion is the median of at most this many of its keypoints' motions, spread evenly over those inside it:
// plenty for a median, and a frame's carry stays well under a millisecond with a dozen boxes.
constexpr std::size_t kMaxLateKeypoints = 40;

const LateDetectionOptions& Checked(const LateDetectionOptions& options) {
  options.Check();
  return options;
}

}  // namespace

LateDetections::LateDetections(cv::Size image_size, const LateDetectionOptions& options)
    : image_size_(image_size), options_(Checked(options)) {}

void LateDetections::Remember(std::size_t index, std::span<const cv::KeyPoint> keypoints,
                              const cv::Mat& descriptors) {
  RememberedFrame frame;
  frame.index = index;
  frame.keypoints.assign(keypoints.begin(), keypoints.end());
  frame.points.reserve(keypoints.size());
  for (const cv::KeyPoint& keypoint : keypoints) frame.points.push_back(keypoint.pt);
  descriptors.copyTo(frame.descriptors);
  frames_.push_back(std::move(frame));
  while (frames_.size() > options_.max_frames) frames_.pop_front();
}

const LateDetections::RememberedFrame* LateDetections::Find(std::size_t index) const {
  const auto it = std::find_if(frames_.begin(), frames_.end(), [&](const RememberedFrame& f) { return f.index == index; });
  return it == frames_.end() ? nullptr : &*it;
}

std::vector<CarriedDetection> LateDetections::Carry(std::size_t from, std::span<const core::Detection> detections,
                                                    std::size_t to) {
  while (!frames_.empty() && frames_.front().index < from) frames_.pop_front();
  std::vector<CarriedDetection> carried;
  carried.reserve(detections.size());
  if (from >= to) {
    for (const core::Detection& detection : detections) carried.push_back({detection, Carry::kNone});
    return carried;
  }
  const RememberedFrame* seen = Find(from);
  const RememberedFrame* now = Find(to);
  const double age = static_cast<double>(to - from);
  const cv::Rect2f image(0.0F, 0.0F, static_cast<float>(image_size_.width), static_cast<float>(image_size_.height));
  for (const core::Detection& detection : detections) {
    CarriedDetection late{detection, Carry::kGrown};
    std::optional<cv::Point2f> motion;
    if (seen != nullptr && now != nullptr) {
      std::vector<std::size_t> inside;
      for (std::size_t i = 0; i < seen->points.size(); ++i) {
        if (detection.box.contains(seen->points[i])) inside.push_back(i);
      }
      if (inside.size() > kMaxLateKeypoints) {
        std::vector<std::size_t> spread(kMaxLateKeypoints);
        for (std::size_t k = 0; k < kMaxLateKeypoints; ++k) spread[k] = inside[k * inside.size() / kMaxLateKeypoints];
        inside = std::move(spread);
      }
      const cv::Rect2f window = GrowBox(detection.box, options_.search_margin + options_.grow_per_frame * age);
      const auto max_motion = static_cast<float>(options_.max_motion + options_.max_motion_per_frame * age);
      motion = MedianKeypointMotion(seen->points, seen->descriptors, inside, now->keypoints, now->descriptors, window,
                                    max_motion);
    }
    if (motion) {
      late.detection.box = detection.box + *motion;
      late.carry = Carry::kKeypoints;
    } else {
      late.detection.box = GrowBox(detection.box, std::min(options_.max_grow, options_.grow_per_frame * age));
    }
    late.detection.box &= image;
    if (late.detection.box.area() > 0.0F) carried.push_back(std::move(late));
  }
  return carried;
}

}  // namespace hoidslam::hoid
