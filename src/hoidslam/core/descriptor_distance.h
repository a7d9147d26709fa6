#pragma once
// The Hamming distance of two ORB descriptors: what every matcher in hoidslam compares (the tracker and the
// local mapper's, the loop closer's, hoidplus's and the real-time mode's carrying of boxes by their keypoints).

#include <cstdint>

#include <opencv2/core/mat.hpp>

namespace hoidslam::core {

inline constexpr int kOrbDescriptorBytes = 32;  // 256 bits

// Hamming distance between two 32-byte ORB descriptors.
int DescriptorDistance(const std::uint8_t* a, const std::uint8_t* b);
inline int DescriptorDistance(const cv::Mat& a, const cv::Mat& b) { return DescriptorDistance(a.ptr(), b.ptr()); }

}  // namespace hoidslam::core
