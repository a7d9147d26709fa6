#include "hoidslam/eval/statistics.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace hoidslam::eval {
namespace {

TEST(ComputeStatisticsTest, OddCountMatchesNumpy) {
  const std::vector<double> errors = {3.0, 1.0, 2.0};
  const ErrorStatistics s = ComputeStatistics(errors);
  EXPECT_EQ(s.count, 3U);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(14.0 / 3.0));
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(2.0 / 3.0));  // population std, as numpy.std
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 3.0);
}

TEST(ComputeStatisticsTest, EvenCountMedianIsMeanOfMiddleValues) {
  const std::vector<double> errors = {4.0, 1.0, 10.0, 2.0};
  EXPECT_DOUBLE_EQ(ComputeStatistics(errors).median, 3.0);
}

TEST(ComputeStatisticsTest, SingleValueHasZeroSpread) {
  const std::vector<double> errors = {0.25};
  const ErrorStatistics s = ComputeStatistics(errors);
  EXPECT_DOUBLE_EQ(s.rmse, 0.25);
  EXPECT_DOUBLE_EQ(s.std, 0.0);
  EXPECT_DOUBLE_EQ(s.median, 0.25);
}

TEST(ComputeStatisticsTest, EmptyIsRejected) {
  EXPECT_THROW(ComputeStatistics(std::vector<double>{}), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::eval
