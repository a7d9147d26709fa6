#include "hoidslam/bow/bow_vector.h"

#include <cmath>
#include <map>

#include <gtest/gtest.h>

namespace hoidslam::bow {
namespace {

// 1 - |a - b|_1 / 2 over the union of the words, as DBoW2 defines the L1 score.
double HalfL1Score(const BowVector& a, const BowVector& b) {
  std::map<WordId, double> difference;
  for (const WordWeight& entry : a) difference[entry.word] += entry.weight;
  for (const WordWeight& entry : b) difference[entry.word] -= entry.weight;
  double l1 = 0.0;
  for (const auto& [word, value] : difference) l1 += std::abs(value);
  return 1.0 - 0.5 * l1;
}

TEST(Score, IsOneForEqualVectorsZeroForDisjointOnesAndTheHalfL1ScoreBetween) {
  const BowVector a = {{1, 0.5}, {4, 0.25}, {9, 0.25}};
  const BowVector b = {{1, 0.25}, {5, 0.5}, {9, 0.25}};
  const BowVector c = {{2, 0.6}, {3, 0.4}};
  EXPECT_DOUBLE_EQ(Score(a, a), 1.0);
  EXPECT_DOUBLE_EQ(Score(a, c), 0.0);
  EXPECT_DOUBLE_EQ(Score(a, b), 0.5);
  EXPECT_DOUBLE_EQ(Score(a, b), HalfL1Score(a, b));
  EXPECT_DOUBLE_EQ(Score(b, a), Score(a, b));
  EXPECT_DOUBLE_EQ(Score({}, {}), 0.0);
}

}  // namespace
}  // namespace hoidslam::bow
