#pragma once
// Pictures a user can look at: detection boxes drawn over a frame, coloured by what happens to their features,
// and the keypoints kept or dropped.

#include <cstdint>
#include <span>
#include <string>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

namespace hoidslam::report {

struct BoxAnnotation {
  cv::Rect2f box;        // pixels
  std::string caption;   // drawn above the box, e.g. "cup 0.81: held by person#0 (62%)"
  bool dynamic = false;  // dynamic boxes are drawn red and their features are dropped; static ones green
};

// A copy of `bgr` (CV_8UC3) with every annotation drawn; dynamic boxes are drawn last so they stay visible.
cv::Mat DrawBoxAnnotations(const cv::Mat& bgr, std::span<const BoxAnnotation> annotations);

// Draws every keypoint into `image` (CV_8UC3) as a small ring: green when kept for tracking (keep[i] != 0), red
// when dropped. `keep` is as long as `keypoints`.
void DrawKeptAndDropped(cv::Mat& image, std::span<const cv::KeyPoint> keypoints, std::span<const std::uint8_t> keep);

}  // namespace hoidslam::report
