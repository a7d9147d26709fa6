#include "support/sliding_wall.h"

#include <random>

#include <opencv2/imgproc.hpp>

namespace hoidslam::testing::wall {

cv::Mat MakeTexture(std::uint32_t seed, cv::Size texture_size) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, texture_size.width - 1), y(0, texture_size.height - 1), size(4, 40),
      grey(0, 255);
  cv::Mat texture(texture_size, CV_8UC3, cv::Scalar::all(128));
  const int shapes = 1500 * texture_size.area() / (800 * 600);
  for (int k = 0; k < shapes; ++k) {
    // One draw per statement: the order in which a compiler evaluates arguments must not change the texture.
    // (This is the order GCC evaluates them in, which the tests were written against.)
    const cv::Scalar colour = cv::Scalar::all(grey(rng));
    const int p_y = y(rng);
    const cv::Point p(x(rng), p_y);
    if (k % 2 == 0) {
      const int height = size(rng);
      cv::rectangle(texture, cv::Rect(p, cv::Size(size(rng), height)), colour, cv::FILLED);
    } else {
      cv::circle(texture, p, size(rng) / 2, colour, cv::FILLED, cv::LINE_AA);
    }
  }
  return texture;
}

core::RgbdFrame MakeFrame(const cv::Mat& texture, int k) {
  core::RgbdFrame frame;
  frame.timestamp = 100.0 + k / 30.0;
  frame.rgb = texture(cv::Rect(80 - kShift * k, 60, 640, 480)).clone();
  frame.depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(kDepth));
  return frame;
}

}  // namespace hoidslam::testing::wall
