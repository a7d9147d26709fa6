#include "hoidslam/dense/dense_options.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::dense {
namespace {

using ::testing::HasSubstr;

// The message of the InputError `options.Check()` throws, or "" when it passes.
std::string CheckMessage(const DenseOptions& options) {
  try {
    options.Check();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(DenseOptions, TheDefaultsPass) { EXPECT_EQ(CheckMessage(DenseOptions{}), ""); }

TEST(DenseOptions, EachBadValueIsNamedByItsParameter) {
  const auto with = [](auto change) {
    DenseOptions options;
    change(options);
    return CheckMessage(options);
  };
  EXPECT_THAT(with([](DenseOptions& o) { o.voxel_size = 0.0; }), HasSubstr("--dense-voxel"));
  EXPECT_THAT(with([](DenseOptions& o) { o.voxel_size = -0.01; }), HasSubstr("--dense-voxel"));
  EXPECT_THAT(with([](DenseOptions& o) { o.truncation = 0.015; }), HasSubstr("--dense-truncation"));
  EXPECT_THAT(with([](DenseOptions& o) { o.max_depth = 0.2; }), HasSubstr("--dense-max-depth"));
  EXPECT_THAT(with([](DenseOptions& o) { o.mask_margin = -1; }), HasSubstr("--dense-mask-margin"));
  EXPECT_THAT(with([](DenseOptions& o) { o.depth_extent = -0.1; }), HasSubstr("--dense-depth-extent"));
  EXPECT_THAT(with([](DenseOptions& o) { o.box_margin = -0.05; }), HasSubstr("--dense-box-margin"));
  EXPECT_THAT(with([](DenseOptions& o) { o.occupancy.band_low = 2.0; }), HasSubstr("--occupancy-band"));
  EXPECT_THAT(with([](DenseOptions& o) { o.occupancy.resolution = 0.0; }), HasSubstr("--occupancy-resolution"));
}

TEST(DenseOptions, AVolumeThatWouldNotFitInMemoryIsRefusedBeforeTheRun) {
  DenseOptions options;
  options.memory_limit_mb = 2000;
  EXPECT_EQ(CheckMessage(options), "");  // 1 cm voxels: about 1.8 GiB for the reference room
  options.voxel_size = 0.005;
  options.truncation = 0.02;
  const std::string message = CheckMessage(options);
  EXPECT_THAT(message, HasSubstr("--dense-voxel"));
  EXPECT_THAT(message, HasSubstr("2000 MiB"));
}

TEST(DenseOptions, TheVolumeEstimateGrowsWithTheInverseSquareOfTheVoxel) {
  EXPECT_NEAR(VolumeBytesPerSquareMetre(0.005) / VolumeBytesPerSquareMetre(0.01), 4.0, 1e-9);
  // From the measured 2.3 layers of blocks, rounded up to 2.5, of 16³ voxels of 48 bytes: about 19 MB per m² at 1 cm.
  EXPECT_NEAR(VolumeBytesPerSquareMetre(0.01) / 1e6, 19.2, 0.5);
}

TEST(SetOccupancyBand, ReadsLowColonHighAndNamesTheParameterOtherwise) {
  OccupancyOptions options;
  SetOccupancyBand("0.2:1.5", options);
  EXPECT_DOUBLE_EQ(options.band_low, 0.2);
  EXPECT_DOUBLE_EQ(options.band_high, 1.5);
  SetOccupancyBand("-0.5:2", options);
  EXPECT_DOUBLE_EQ(options.band_low, -0.5);
  for (const char* bad : {"1.5", "a:b", "0.1:1.8m", ":1", ""}) {
    EXPECT_THROW(SetOccupancyBand(bad, options), core::InputError) << bad;
  }
  SetOccupancyBand("1.8:0.1", options);  // read as given; Check() refuses it upside down
  DenseOptions dense;
  dense.occupancy = options;
  EXPECT_THAT(CheckMessage(dense), HasSubstr("--occupancy-band"));
}

}  // namespace
}  // namespace hoidslam::dense
