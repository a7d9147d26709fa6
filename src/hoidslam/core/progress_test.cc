#include "hoidslam/core/progress.h"

#include <gtest/gtest.h>

namespace hoidslam::core {
namespace {

TEST(FormatDuration, MinutesAndHours) {
  EXPECT_EQ(FormatDuration(0.0), "0:00");
  EXPECT_EQ(FormatDuration(59.6), "1:00");
  EXPECT_EQ(FormatDuration(754.0), "12:34");
  EXPECT_EQ(FormatDuration(3723.0), "1:02:03");
  EXPECT_EQ(FormatDuration(-5.0), "0:00");
}

}  // namespace
}  // namespace hoidslam::core
