#include "hoidslam/eval/association.h"

#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {
namespace {

using ::testing::ElementsAre;

TEST(AssociateByTimestampTest, MatchesAsIoAssociateTimestampsWithTheOffset) {
  // The algorithm itself is tested beside it (io/timestamp_association_test.cc); here, that options reach it.
  const std::vector<double> first = {10.0, 10.1, 10.2};
  const std::vector<double> second = {0.0, 0.1, 0.2};
  EXPECT_THAT(AssociateByTimestamp(first, second, {.offset = 10.0}), ElementsAre(Match{0, 0}, Match{1, 1}, Match{2, 2}));
  EXPECT_THAT(AssociateByTimestamp(first, second, {.max_difference = 0.02, .offset = 10.1}),
              ElementsAre(Match{1, 0}, Match{2, 1}));
}

TEST(AssociateByTimestampTest, BadOptionsNameTheParameter) {
  const std::vector<double> stamps = {1.0};
  EXPECT_THROW(
      {
        try {
          AssociateByTimestamp(stamps, stamps, {.max_difference = 0.0});
        } catch (const core::InputError& e) {
          EXPECT_THAT(e.what(), ::testing::HasSubstr("--max-difference"));
          throw;
        }
      },
      core::InputError);
  EXPECT_THROW(AssociateByTimestamp(stamps, stamps, {.max_difference = -1.0}), core::InputError);
  EXPECT_THROW(AssociateByTimestamp(stamps, stamps, {.offset = std::nan("")}), core::InputError);
}

TEST(AssociateByTimestampTest, HugeToleranceIsRefusedNamingTheFlag) {
  std::vector<double> stamps(6000);
  for (std::size_t k = 0; k < stamps.size(); ++k) stamps[k] = 0.01 * static_cast<double>(k);
  try {
    AssociateByTimestamp(stamps, stamps, {.max_difference = 1e6});
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("--max-difference"));
  }
}

TEST(ClosestIndexTest, FindsNearestAndClampsAtTheEnds) {
  const std::vector<double> sorted = {0.0, 1.0, 2.0, 4.0};
  EXPECT_EQ(ClosestIndex(sorted, -5.0), 0U);
  EXPECT_EQ(ClosestIndex(sorted, 1.4), 1U);
  EXPECT_EQ(ClosestIndex(sorted, 1.6), 2U);
  EXPECT_EQ(ClosestIndex(sorted, 2.0), 2U);
  EXPECT_EQ(ClosestIndex(sorted, 3.0), 2U);  // a tie goes to the earlier stamp
  EXPECT_EQ(ClosestIndex(sorted, 3.1), 3U);
  EXPECT_EQ(ClosestIndex(sorted, 99.0), 3U);
}

TEST(SortedUniqueByTimeTest, SortsAndKeepsTheLastPoseOfARepeatedStamp) {
  core::Trajectory trajectory(4);
  const double stamps[] = {2.0, 1.0, 2.0, 0.5};
  for (std::size_t k = 0; k < 4; ++k) {
    trajectory[k].timestamp = stamps[k];
    trajectory[k].T_wc.translation().x() = static_cast<double>(k);
  }
  const core::Trajectory sorted = SortedUniqueByTime(trajectory);
  ASSERT_EQ(sorted.size(), 3U);
  EXPECT_THAT(Timestamps(sorted), ElementsAre(0.5, 1.0, 2.0));
  EXPECT_EQ(sorted[2].T_wc.translation().x(), 2.0);  // the later of the two poses at 2.0
}

TEST(SortedUniqueByTimeTest, RejectsNonFiniteStamps) {
  core::Trajectory trajectory(1);
  trajectory[0].timestamp = std::nan("");
  EXPECT_THROW(SortedUniqueByTime(trajectory), core::InputError);
}

}  // namespace
}  // namespace hoidslam::eval
