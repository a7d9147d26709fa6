#include "hoidslam/hoid/keypoint_motion.h"

#include <algorithm>
#include <limits>
#include <vector>

#include "hoidslam/core/descriptor_distance.h"

namespace hoidslam::hoid {
namespace {

// ORB's usual "good match" distance, a ratio test, and enough matches for a median to mean something.
constexpr int kMaxMatchDistance = 64;
constexpr float kMatchRatio = 0.8F;
constexpr std::size_t kMinMatches = 5;

float Median(std::vector<float>& values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace

std::string_view ToString(Carry carry) {
  switch (carry) {
    case Carry::kNone: return "none";
    case Carry::kKeypoints: return "keypoints";
    case Carry::kVelocity: return "velocity";
    case Carry::kGrown: return "grown";
  }
  return "unknown";
}

std::optional<cv::Point2f> MedianKeypointMotion(std::span<const cv::Point2f> from_points,
                                                const cv::Mat& from_descriptors,
                                                std::span<const std::size_t> selected,
                                                std::span<const cv::KeyPoint> to_keypoints,
                                                const cv::Mat& to_descriptors, const cv::Rect2f& window,
                                                float max_motion) {
  if (from_descriptors.empty() || to_descriptors.empty() || from_descriptors.cols != core::kOrbDescriptorBytes ||
      to_descriptors.cols != core::kOrbDescriptorBytes ||
      from_descriptors.type() != CV_8U || to_descriptors.type() != CV_8U ||
      static_cast<std::size_t>(from_descriptors.rows) != from_points.size() ||
      static_cast<std::size_t>(to_descriptors.rows) != to_keypoints.size()) {
    return std::nullopt;
  }
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < to_keypoints.size(); ++i) {
    if (window.contains(to_keypoints[i].pt)) candidates.push_back(i);
  }
  const float max_squared = max_motion * max_motion;
  std::vector<float> dx, dy;
  for (const std::size_t p : selected) {
    const std::uint8_t* a = from_descriptors.ptr<std::uint8_t>(static_cast<int>(p));
    int best = std::numeric_limits<int>::max(), second = best;
    std::size_t best_index = 0;
    for (const std::size_t c : candidates) {
      const cv::Point2f d = to_keypoints[c].pt - from_points[p];
      if (d.dot(d) > max_squared) continue;
      const int distance = core::DescriptorDistance(a, to_descriptors.ptr<std::uint8_t>(static_cast<int>(c)));
      if (distance < best) {
        second = best;
        best = distance;
        best_index = c;
      } else if (distance < second) {
        second = distance;
      }
    }
    if (best <= kMaxMatchDistance && static_cast<float>(best) < kMatchRatio * static_cast<float>(second)) {
      dx.push_back(to_keypoints[best_index].pt.x - from_points[p].x);
      dy.push_back(to_keypoints[best_index].pt.y - from_points[p].y);
    }
  }
  if (dx.size() < kMinMatches) return std::nullopt;
  return cv::Point2f(Median(dx), Median(dy));
}

}  // namespace hoidslam::hoid
