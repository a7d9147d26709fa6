#pragma once
// How a box moved between two frames, told by the ORB keypoints inside it: the median image motion of its
// keypoints, each matched by descriptor to the other frame. Mode hoidplus carries a box the detector missed from
// one frame to the next with it; the real-time mode carries late detections from the frame the detector saw to
// the frame being tracked (late_detections.h).

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string_view>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

namespace hoidslam::hoid {

// How a box was placed on a frame the detector did not see it on.
enum class Carry : std::uint8_t {
  kNone,       // seen on this frame
  kKeypoints,  // moved by the median motion of its keypoints, matched by descriptor
  kVelocity,   // too few keypoint matches: moved by the box's recent velocity (hoidplus)
  kGrown,      // too few keypoint matches: left in place and grown by what it may have moved (real-time mode)
};
std::string_view ToString(Carry carry);

// Keypoints taken into a box's motion: at most this many, the first found.
inline constexpr std::size_t kMaxMotionKeypoints = 150;

// The median motion (pixels) of the keypoints `selected` of the earlier frame (`from_points`, with one ORB
// descriptor row each in `from_descriptors`) to the keypoints of the later frame inside `window`: each is matched
// to its nearest descriptor there when that is a good ORB match (Hamming distance ≤ 64) clearly better than the
// second nearest (ratio 0.8). Only keypoints within `max_motion` pixels of where a keypoint was are its
// candidates, which saves most descriptor comparisons when the motion is known to be small. nullopt with fewer
// than five matches, or when the descriptors are missing or not ORB's 32 bytes.
std::optional<cv::Point2f> MedianKeypointMotion(std::span<const cv::Point2f> from_points,
                                                const cv::Mat& from_descriptors,
                                                std::span<const std::size_t> selected,
                                                std::span<const cv::KeyPoint> to_keypoints,
                                                const cv::Mat& to_descriptors, const cv::Rect2f& window,
                                                float max_motion = std::numeric_limits<float>::infinity());

}  // namespace hoidslam::hoid
