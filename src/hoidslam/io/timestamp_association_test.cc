#include "hoidslam/io/timestamp_association.h"

#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::io {
namespace {

using ::testing::ElementsAre;

std::vector<TimestampMatch> Associate(const std::vector<double>& first, const std::vector<double>& second,
                                      double max_difference = 0.02, double offset = 0.0) {
  return AssociateTimestamps(first, second, max_difference, offset, "tolerance");
}

TEST(AssociateTimestamps, SmallestDifferenceWinsAndEachStampIsUsedOnce) {
  // (1.010, 1.007) is the closest pair, so 1.000 cannot take 1.007 and falls back to 1.019 (0.019 < 0.02).
  // Matching each first stamp to its nearest second stamp would use 1.007 twice.
  const std::vector<double> first = {1.000, 1.010};
  const std::vector<double> second = {1.007, 1.019};
  EXPECT_THAT(Associate(first, second), ElementsAre(TimestampMatch{0, 1}, TimestampMatch{1, 0}));
}

TEST(AssociateTimestamps, ResultIsSortedByFirstStampWhateverTheInputOrder) {
  const std::vector<double> first = {3.0, 1.0, 2.0};
  const std::vector<double> second = {2.001, 3.001, 1.001};
  EXPECT_THAT(Associate(first, second), ElementsAre(TimestampMatch{1, 2}, TimestampMatch{2, 0}, TimestampMatch{0, 1}));
}

TEST(AssociateTimestamps, DifferenceMustBeStrictlyBelowTolerance) {
  // 0.25 and 0.125 are exact in binary, so the differences are exactly the tolerance.
  const std::vector<double> first = {1.0, 2.0};
  const std::vector<double> second = {1.25, 2.125};
  EXPECT_THAT(Associate(first, second, 0.25), ElementsAre(TimestampMatch{1, 1}));
  EXPECT_THAT(Associate(first, second, 0.125), ElementsAre());
  EXPECT_THAT(Associate(first, second, 0.2500001), ElementsAre(TimestampMatch{0, 0}, TimestampMatch{1, 1}));
}

TEST(AssociateTimestamps, OffsetIsAddedToTheSecondStamps) {
  const std::vector<double> first = {10.0, 10.1, 10.2};
  const std::vector<double> second = {0.0, 0.1, 0.2};
  EXPECT_THAT(Associate(first, second), ElementsAre());
  EXPECT_THAT(Associate(first, second, 0.02, 10.0), ElementsAre(TimestampMatch{0, 0}, TimestampMatch{1, 1}, TimestampMatch{2, 2}));
  // An offset that is one step off pairs each stamp with its neighbour instead.
  EXPECT_THAT(Associate(first, second, 0.02, 10.1),
              ElementsAre(TimestampMatch{1, 0}, TimestampMatch{2, 1}));
}

TEST(AssociateTimestamps, EmptyInputsGiveNoMatches) {
  EXPECT_THAT(Associate({}, {1.0}), ElementsAre());
  EXPECT_THAT(Associate({1.0}, {}), ElementsAre());
}

TEST(AssociateTimestamps, HugeToleranceOnLongTrajectoriesIsRefusedNotExhaustingMemory) {
  std::vector<double> stamps(6000);
  for (std::size_t k = 0; k < stamps.size(); ++k) stamps[k] = 0.01 * static_cast<double>(k);
  EXPECT_THROW(Associate(stamps, stamps, 1e6), core::InputError);
}

}  // namespace
}  // namespace hoidslam::io
