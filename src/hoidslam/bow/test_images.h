#pragma once
// Real images for the vocabulary's tests and benchmark, described as tracking describes its frames: grey, ORB with
// ORB-SLAM's defaults (1000 features, 8 levels, 1.2).

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/options.h"
#include "hoidslam/features/orb_extractor.h"

namespace hoidslam::bow::fixtures {

// Two colour frames of TUM fr3/walking_xyz, 3 s apart (the camera moved, people walked), which the shipped
// vocabulary was not trained on.
inline constexpr const char* kTumFrame = "data/tum/fr3_walking_xyz_pair/rgb/1341846313.592026.png";
inline constexpr const char* kLaterTumFrame = "data/tum/fr3_walking_xyz_pair/rgb/1341846316.570121.png";

inline cv::Mat ReadGray(const std::filesystem::path& path) { return cv::imread(path.string(), cv::IMREAD_GRAYSCALE); }

inline cv::Mat OrbDescriptors(const cv::Mat& gray) {
  features::OrbExtractor extractor(core::OrbOptions{});
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.Extract(gray, keypoints, descriptors);
  return descriptors;
}

}  // namespace hoidslam::bow::fixtures
