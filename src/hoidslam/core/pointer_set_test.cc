#include "hoidslam/core/pointer_set.h"

#include <random>
#include <unordered_set>
#include <vector>

#include <gtest/gtest.h>

namespace hoidslam::core {
namespace {

TEST(PointerSet, InsertsEachPointerOnceAndNeverNull) {
  std::vector<int> values(3);
  PointerSet<int> set;
  EXPECT_TRUE(set.Insert(&values[0]));
  EXPECT_FALSE(set.Insert(&values[0]));
  EXPECT_TRUE(set.Insert(&values[2]));
  EXPECT_FALSE(set.Insert(nullptr));
  EXPECT_EQ(set.size(), 2U);
  EXPECT_TRUE(set.Contains(&values[0]));
  EXPECT_FALSE(set.Contains(&values[1]));
  EXPECT_TRUE(set.Contains(&values[2]));
  EXPECT_FALSE(set.Contains(nullptr));
}

// Far more elements than it was made for, in random order with repeats: it grows and agrees with
// std::unordered_set on every insert.
TEST(PointerSet, GrowsAndAgreesWithUnorderedSet) {
  std::vector<double> values(20000);
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, values.size() - 1);
  PointerSet<double> set(10);
  std::unordered_set<const double*> reference;
  for (int i = 0; i < 60000; ++i) {
    const double* p = &values[pick(rng)];
    ASSERT_EQ(set.Insert(p), reference.insert(p).second) << i;
  }
  EXPECT_EQ(set.size(), reference.size());
  for (const double& v : values) EXPECT_EQ(set.Contains(&v), reference.contains(&v));
}

}  // namespace
}  // namespace hoidslam::core
