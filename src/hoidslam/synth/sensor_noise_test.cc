#include "hoidslam/synth/sensor_noise.h"

#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/error.h"

namespace hoidslam::synth {
namespace {

// Noise only: no holes, no dropout.
SensorNoiseOptions NoiseOnly() {
  SensorNoiseOptions options;
  options.dropout_probability = 0.0;
  options.edge_erosion_probability = 0.0;
  return options;
}

cv::Mat Plane(float z, cv::Size size = {200, 200}) { return cv::Mat(size, CV_32F, cv::Scalar(z)); }

struct Stats {
  double mean = 0.0;
  double std = 0.0;
};

// Statistics of the measured-minus-true depth over valid pixels, in metres.
Stats DepthErrorStats(const cv::Mat& measured, double truth, double depth_factor) {
  double sum = 0.0;
  double sum_sq = 0.0;
  int n = 0;
  for (int y = 0; y < measured.rows; ++y) {
    for (int x = 0; x < measured.cols; ++x) {
      const std::uint16_t value = measured.at<std::uint16_t>(y, x);
      if (value == 0) continue;
      const double error = value / depth_factor - truth;
      sum += error;
      sum_sq += error * error;
      ++n;
    }
  }
  const double mean = sum / n;
  return {mean, std::sqrt(sum_sq / n - mean * mean)};
}

TEST(SensorNoise, DepthNoiseFollowsTheKinectModel) {
  const SensorNoiseOptions options = NoiseOnly();
  for (const double z : {1.0, 3.0}) {
    const cv::Mat measured = ApplyDepthNoise(Plane(static_cast<float>(z)), options, 42);
    ASSERT_EQ(measured.type(), CV_16U);
    EXPECT_EQ(cv::countNonZero(measured), measured.rows * measured.cols) << "a flat plane has no holes";
    const Stats stats = DepthErrorStats(measured, z, options.depth_factor);
    const double sigma = core::KinectDepthSigma(z);
    EXPECT_NEAR(stats.mean, 0.0, 5.0 * sigma / 200.0 + 0.5 / options.depth_factor) << "at " << z << " m";
    EXPECT_NEAR(stats.std, sigma, 0.05 * sigma) << "at " << z << " m";
  }
  EXPECT_NEAR(core::KinectDepthSigma(1.0), 0.0012 + 0.0019 * 0.36, 1e-12);
}

TEST(SensorNoise, NoiseScaleZeroGivesTheQuantisedTruth) {
  SensorNoiseOptions options = NoiseOnly();
  options.depth_noise_scale = 0.0;
  const cv::Mat measured = ApplyDepthNoise(Plane(1.23456F), options, 1);
  double lo = 0.0;
  double hi = 0.0;
  cv::minMaxLoc(measured, &lo, &hi);
  EXPECT_EQ(lo, 6173.0);  // 1.23456 m x 5000, rounded
  EXPECT_EQ(hi, 6173.0);
}

TEST(SensorNoise, HolesAtADepthStep) {
  cv::Mat depth = Plane(1.0F);
  depth(cv::Rect(100, 0, 100, 200)).setTo(2.0F);
  SensorNoiseOptions options = NoiseOnly();
  const cv::Mat measured = ApplyDepthNoise(depth, options, 3);
  for (int x = 0; x < 200; ++x) {
    const int zeros = 200 - cv::countNonZero(measured.col(x));
    EXPECT_EQ(zeros, (x == 99 || x == 100) ? 200 : 0) << "column " << x;
  }
  // With certain erosion, the neighbours of the edge go too.
  options.edge_erosion_probability = 1.0;
  const cv::Mat eroded = ApplyDepthNoise(depth, options, 3);
  for (int x = 0; x < 200; ++x) {
    const int zeros = 200 - cv::countNonZero(eroded.col(x));
    EXPECT_EQ(zeros, (x >= 98 && x <= 101) ? 200 : 0) << "column " << x;
  }
  // A gentle slope is no edge.
  cv::Mat slope(200, 200, CV_32F);
  for (int x = 0; x < 200; ++x) slope.col(x).setTo(1.0F + 0.005F * static_cast<float>(x));
  EXPECT_EQ(cv::countNonZero(ApplyDepthNoise(slope, NoiseOnly(), 3)), 200 * 200);
}

TEST(SensorNoise, NoDepthOutsideTheRangeOrWhereNothingIs) {
  const SensorNoiseOptions options = NoiseOnly();
  EXPECT_EQ(cv::countNonZero(ApplyDepthNoise(Plane(5.0F), options, 1)), 0);
  EXPECT_EQ(cv::countNonZero(ApplyDepthNoise(Plane(0.3F), options, 1)), 0);
  EXPECT_EQ(cv::countNonZero(ApplyDepthNoise(Plane(0.0F), options, 1)), 0);
  // Near the far limit some noisy values pass, but none beyond it.
  const cv::Mat far = ApplyDepthNoise(Plane(4.49F), options, 1);
  double hi = 0.0;
  cv::minMaxLoc(far, nullptr, &hi);
  EXPECT_LE(hi, 4.5 * options.depth_factor);
  EXPECT_GT(cv::countNonZero(far), 0);
}

TEST(SensorNoise, DropoutRemovesTheRequestedShare) {
  SensorNoiseOptions options = NoiseOnly();
  options.dropout_probability = 0.1;
  const cv::Mat measured = ApplyDepthNoise(Plane(2.0F), options, 9);
  const double dropped = 1.0 - cv::countNonZero(measured) / (200.0 * 200.0);
  EXPECT_NEAR(dropped, 0.1, 0.01);
}

TEST(SensorNoise, DisparityStepsCoarsenFarDepth) {
  SensorNoiseOptions options = NoiseOnly();
  options.disparity_step = 2.85e-3;
  const cv::Mat measured = ApplyDepthNoise(Plane(4.0F), options, 5);
  std::set<std::uint16_t> levels;
  for (int y = 0; y < measured.rows; ++y) {
    for (int x = 0; x < measured.cols; ++x) levels.insert(measured.at<std::uint16_t>(y, x));
  }
  // sigma_z(4 m) = 2.6 cm; disparity steps at 4 m are about 4.6 cm apart: a handful of levels, not hundreds.
  EXPECT_LE(levels.size(), 8U);
  EXPECT_GE(levels.size(), 2U);
}

TEST(SensorNoise, SameSeedSameBytesOtherSeedOtherBytes) {
  cv::Mat depth = Plane(1.5F);
  depth(cv::Rect(50, 50, 60, 60)).setTo(0.9F);
  const SensorNoiseOptions options;
  const cv::Mat a = ApplyDepthNoise(depth, options, 11);
  const cv::Mat b = ApplyDepthNoise(depth, options, 11);
  const cv::Mat c = ApplyDepthNoise(depth, options, 12);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 0.0);

  const cv::Mat grey(100, 100, CV_8UC3, cv::Scalar(100, 120, 140));
  EXPECT_EQ(cv::norm(ApplyRgbNoise(grey, options, 4), ApplyRgbNoise(grey, options, 4), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(ApplyRgbNoise(grey, options, 4), ApplyRgbNoise(grey, options, 5), cv::NORM_L1), 0.0);
}

TEST(SensorNoise, RgbNoiseHasTheRequestedSpreadAndTheBlurSmoothsIt) {
  SensorNoiseOptions options;
  options.rgb_noise_sigma = 3.0;
  options.rgb_blur_sigma = 0.0;
  const cv::Mat grey(300, 300, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::Scalar mean;
  cv::Scalar std;
  cv::meanStdDev(ApplyRgbNoise(grey, options, 8).reshape(1), mean, std);
  EXPECT_NEAR(mean[0], 128.0, 0.05);
  EXPECT_NEAR(std[0], std::sqrt(9.0 + 1.0 / 12.0), 0.1);  // plus rounding to whole grey levels

  options.rgb_blur_sigma = 0.8;
  cv::meanStdDev(ApplyRgbNoise(grey, options, 8).reshape(1), mean, std);
  EXPECT_NEAR(mean[0], 128.0, 0.05);
  EXPECT_GT(std[0], 0.3 * 3.0);
  EXPECT_LT(std[0], 0.6 * 3.0);
}

TEST(SensorNoise, OptionsCheckNamesTheParameter) {
  const auto message_of = [](const SensorNoiseOptions& options) {
    try {
      options.Check();
    } catch (const core::InputError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_EQ(message_of(SensorNoiseOptions{}), "");
  SensorNoiseOptions options;
  options.max_range = 0.2;
  EXPECT_NE(message_of(options).find("noise.max_range"), std::string::npos);
  options = {};
  options.dropout_probability = 1.5;
  EXPECT_NE(message_of(options).find("parameter noise.dropout_probability: must be in [0, 1], got 1.5"),
            std::string::npos);
  options = {};
  options.rgb_noise_sigma = -1.0;
  EXPECT_NE(message_of(options).find("noise.rgb_noise_sigma"), std::string::npos);
  options = {};
  options.max_range = 20.0;  // 100000 units do not fit 16 bits
  EXPECT_NE(message_of(options).find("noise.max_range"), std::string::npos);
}

}  // namespace
}  // namespace hoidslam::synth
