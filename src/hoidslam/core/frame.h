#pragma once
// One RGB-D frame as it enters the system.

#include <string>

#include <opencv2/core/mat.hpp>

namespace hoidslam::core {

struct RgbdFrame {
  double timestamp = 0.0;  // seconds, the RGB image's timestamp
  // Seconds from the colour image to the depth image (a TUM sequence's associated depth stamp less the colour's;
  // fr1 up to 20 ms, fr3 under 1 ms). 0: taken together.
  double depth_delay = 0.0;
  cv::Mat rgb;             // CV_8UC3, BGR order (as cv::imread gives it)
  cv::Mat depth;           // CV_32FC1, metres; 0 where the sensor gave no depth
  std::string rgb_path;    // where the images came from, for messages and logs (empty when generated)
  std::string depth_path;
};

}  // namespace hoidslam::core
