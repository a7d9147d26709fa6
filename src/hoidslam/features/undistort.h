#pragma once
// Keypoint positions without lens distortion: what tracking and mapping compute with. The images are never
// undistorted as a whole; only the keypoints found in them are.

#include <span>
#include <vector>

#include <opencv2/core/types.hpp>

#include "hoidslam/core/camera.h"

namespace hoidslam::features {

// The undistorted pixel position of every keypoint, through the camera's radial-tangential model (OpenCV order
// k1, k2, p1, p2, k3). Without distortion the positions are returned unchanged.
std::vector<cv::Point2f> UndistortKeypoints(std::span<const cv::KeyPoint> keypoints,
                                            const core::CameraIntrinsics& camera);

}  // namespace hoidslam::features
