#include "hoidslam/pipeline/depth_units.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace hoidslam::pipeline {
namespace {

using ::testing::HasSubstr;

// A room as a camera sees it: a floor from 0.8 m going away, a wall at 4 m behind a desk at 1.2 m.
cv::Mat Room(double scale = 1.0) {
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(4.0 * scale));
  depth(cv::Rect(0, 300, 640, 180)).setTo(cv::Scalar(1.2 * scale));
  for (int r = 400; r < 480; ++r) depth.row(r).setTo(cv::Scalar((0.8 + 0.01 * (480 - r)) * scale));
  return depth;
}

TEST(DepthUnits, ARoomPasses) {
  const std::optional<DepthSpread> spread = MeasureDepth(Room());
  ASSERT_TRUE(spread);
  EXPECT_DOUBLE_EQ(spread->valid_share, 1.0);
  EXPECT_NEAR(spread->median_m, 4.0, 1e-6);
  EXPECT_EQ(DepthUnitsProblem(*spread, 5000.0), "");
}

TEST(DepthUnits, MillimetresReadAsTumsUnitsAreFiveTimesTooNearAndSaidSo) {
  const std::optional<DepthSpread> spread = MeasureDepth(Room(1000.0 / 5000.0));
  ASSERT_TRUE(spread);
  const std::string problem = DepthUnitsProblem(*spread, 5000.0);
  EXPECT_THAT(problem, HasSubstr("too near for a room: read with 5000 units a metre"));
  EXPECT_THAT(problem, HasSubstr("1000 units a metre would put it where a room is"));
  EXPECT_THAT(problem, HasSubstr("--depth-factor"));
  EXPECT_THAT(problem, HasSubstr("Depth.checkUnits: 0"));
}

TEST(DepthUnits, DepthOfAMillimetreAndOfTensOfMetresAreRefused) {
  EXPECT_THAT(DepthUnitsProblem(*MeasureDepth(Room(0.001)), 5e6), HasSubstr("too near"));
  EXPECT_THAT(DepthUnitsProblem(*MeasureDepth(Room(10.0)), 100.0), HasSubstr("too far"));
}

TEST(DepthUnits, AFrameWithLittleDepthSaysNothing) {
  cv::Mat depth = Room();
  depth(cv::Rect(0, 0, 640, 400)).setTo(cv::Scalar(0.0F));  // a sixth of the pixels keep depth
  EXPECT_FALSE(MeasureDepth(depth));
  EXPECT_FALSE(MeasureDepth(cv::Mat()));
}

}  // namespace
}  // namespace hoidslam::pipeline
