#pragma once
// The sliding wall that the SLAM tests and benchmarks track: a camera sliding along -x in front of a flat wall of
// random grey shapes at kDepth, the image content moving right by kShift pixels a frame. The first camera is the
// world frame.

#include <cstdint>

#include <opencv2/core.hpp>

#include "hoidslam/core/frame.h"

namespace hoidslam::testing::wall {

inline constexpr double kDepth = 2.0;  // metres
inline constexpr int kShift = 3;       // pixels per frame

// A texture of random grey rectangles and discs, larger than the image so that frames can be cut from it; 1500
// shapes on the default 800×600, as many per pixel on other sizes. The same seed gives the same texture.
cv::Mat MakeTexture(std::uint32_t seed, cv::Size texture_size = {800, 600});

// Frame k of the camera sliding along the wall `texture`: 640×480, the view whose top-left corner is at
// (80 - kShift k, 60) of the texture, every pixel kDepth deep, at 100 + k/30 seconds.
core::RgbdFrame MakeFrame(const cv::Mat& texture, int k);

}  // namespace hoidslam::testing::wall
