#include "hoidslam/core/options.h"

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::core {
namespace {

TEST(FilterMode, RoundTripsEveryName) {
  for (const char* name : {"none", "person", "classes", "hoid2d", "hoid3d"}) {
    EXPECT_EQ(ToString(ParseFilterMode(name)), name);
  }
}

TEST(FilterMode, UnknownNameIsNamedInTheError) {
  try {
    ParseFilterMode("hoid4d");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("HOID.mode"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("hoid4d"), std::string::npos);
  }
}

TEST(HoidOptions, DefaultsAreThePapers) {
  const HoidOptions options;
  EXPECT_DOUBLE_EQ(options.min_interaction_area, 0.4);
  EXPECT_DOUBLE_EQ(options.depth_threshold, 0.2);
  EXPECT_EQ(options.sample_box_size, 20);
  EXPECT_TRUE(options.IsPotentiallyDynamic("person"));
  EXPECT_TRUE(options.IsPotentiallyDynamic("tv"));
  EXPECT_FALSE(options.IsPotentiallyDynamic("bus"));
  EXPECT_NO_THROW(options.Check());
}

TEST(HoidOptions, CheckRejectsOutOfRangeValuesByName) {
  HoidOptions options;
  options.min_interaction_area = 1.5;
  EXPECT_THROW(options.Check(), InputError);
  options.min_interaction_area = 0.0;
  EXPECT_THROW(options.Check(), InputError);
  options = {};
  options.depth_threshold = -0.1;
  try {
    options.Check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("HOID.depthThreshold"), std::string::npos);
  }
  options = {};
  options.sample_box_size = 0;
  EXPECT_THROW(options.Check(), InputError);
}

TEST(OrbOptions, CheckRejectsMinThresholdAboveInitial) {
  OrbOptions options;
  EXPECT_NO_THROW(options.Check());
  options.min_th_fast = 30;
  EXPECT_THROW(options.Check(), InputError);
  options = {};
  options.scale_factor = 1.0;
  EXPECT_THROW(options.Check(), InputError);
}

}  // namespace
}  // namespace hoidslam::core
