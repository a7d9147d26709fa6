#include "hoidslam/features/quadtree.h"

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace hoidslam::features {
namespace {

// `count` corners at distinct random positions of `region`, random scores.
std::vector<Corner> RandomCorners(const cv::Rect& region, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> ux(region.x, region.x + region.width - 1);
  std::uniform_int_distribution<int> uy(region.y, region.y + region.height - 1);
  std::uniform_real_distribution<float> score(7.0F, 100.0F);
  std::set<std::pair<int, int>> used;
  std::vector<Corner> corners;
  while (static_cast<int>(corners.size()) < count) {
    const int x = ux(rng);
    const int y = uy(rng);
    if (used.insert({x, y}).second) corners.push_back({x, y, score(rng)});
  }
  return corners;
}

std::vector<std::pair<int, int>> Positions(const std::vector<Corner>& corners, const std::vector<int>& selected) {
  std::vector<std::pair<int, int>> p;
  for (int i : selected) p.emplace_back(corners[static_cast<std::size_t>(i)].x, corners[static_cast<std::size_t>(i)].y);
  return p;
}

TEST(Quadtree, KeepsExactlyNDistinctCornersWhenThereAreMore) {
  const cv::Rect region(16, 16, 608, 448);
  const std::vector<Corner> corners = RandomCorners(region, 5000, 1);
  QuadtreeDistributor quadtree;
  for (int n : {1, 2, 3, 7, 50, 217, 1000}) {
    std::vector<int> selected;
    quadtree.Distribute(corners, region, n, selected);
    EXPECT_EQ(static_cast<int>(selected.size()), n) << "n=" << n;
    EXPECT_EQ(std::set<int>(selected.begin(), selected.end()).size(), selected.size());
  }
}

TEST(Quadtree, KeepsEveryCornerWhenFewerThanN) {
  const cv::Rect region(0, 0, 100, 80);
  const std::vector<Corner> corners = RandomCorners(region, 40, 2);
  QuadtreeDistributor quadtree;
  std::vector<int> selected;
  quadtree.Distribute(corners, region, 100, selected);
  std::sort(selected.begin(), selected.end());
  std::vector<int> all(40);
  for (int i = 0; i < 40; ++i) all[static_cast<std::size_t>(i)] = i;
  EXPECT_EQ(selected, all);
}

TEST(Quadtree, WeakIsolatedCornerBeatsStrongCrowd) {
  // A crowd of strong corners top-left, a single weak one bottom-right: with two cells, both regions are served.
  const cv::Rect region(0, 0, 200, 200);
  std::vector<Corner> corners;
  for (int y = 10; y < 30; y += 2) {
    for (int x = 10; x < 30; x += 2) corners.push_back({x, y, 100.0F + static_cast<float>(x + y)});
  }
  corners.push_back({180, 170, 8.0F});
  QuadtreeDistributor quadtree;
  std::vector<int> selected;
  quadtree.Distribute(corners, region, 2, selected);
  ASSERT_EQ(selected.size(), 2U);
  const auto positions = Positions(corners, selected);
  const std::set<std::pair<int, int>> kept(positions.begin(), positions.end());
  EXPECT_TRUE(kept.count({180, 170}));
  EXPECT_TRUE(kept.count({28, 28}));  // the strongest of the crowd
}

TEST(Quadtree, SpreadsOverTheRegionWhateverTheScores) {
  // Scores grow to the right: a top-N by score would take the right edge only.
  const cv::Rect region(0, 0, 400, 400);
  std::vector<Corner> corners;
  for (int y = 0; y < 400; y += 5) {
    for (int x = 0; x < 400; x += 5) corners.push_back({x, y, static_cast<float>(x)});
  }
  QuadtreeDistributor quadtree;
  std::vector<int> selected;
  quadtree.Distribute(corners, region, 64, selected);
  ASSERT_EQ(selected.size(), 64U);
  int counts[2][2] = {};
  for (int i : selected) {
    const Corner& c = corners[static_cast<std::size_t>(i)];
    ++counts[c.y / 200][c.x / 200];
  }
  for (const auto& row : counts) {
    for (int count : row) EXPECT_EQ(count, 16);
  }
}

TEST(Quadtree, ResultDoesNotDependOnInputOrder) {
  const cv::Rect region(16, 16, 300, 200);
  std::vector<Corner> corners = RandomCorners(region, 2000, 3);
  // Ties on purpose: many equal scores.
  for (std::size_t i = 0; i < corners.size(); i += 3) corners[i].response = 50.0F;
  QuadtreeDistributor quadtree;
  std::vector<int> selected;
  quadtree.Distribute(corners, region, 150, selected);
  const auto expected = Positions(corners, selected);

  std::mt19937 rng(4);
  std::shuffle(corners.begin(), corners.end(), rng);
  quadtree.Distribute(corners, region, 150, selected);
  EXPECT_EQ(Positions(corners, selected), expected);
}

TEST(Quadtree, WideRegionStartsWithSideBySideCells) {
  // 3:1 region, corners only in the right third: n = 3 must still pick 3 corners there.
  const cv::Rect region(0, 0, 300, 100);
  const std::vector<Corner> corners = RandomCorners(cv::Rect(200, 0, 100, 100), 50, 5);
  QuadtreeDistributor quadtree;
  std::vector<int> selected;
  quadtree.Distribute(corners, region, 3, selected);
  EXPECT_EQ(selected.size(), 3U);
}

TEST(Quadtree, EdgeCases) {
  QuadtreeDistributor quadtree;
  std::vector<int> selected = {1, 2};
  const std::vector<Corner> one = {{5, 5, 10.0F}};
  quadtree.Distribute(one, cv::Rect(0, 0, 10, 10), 0, selected);
  EXPECT_TRUE(selected.empty());
  quadtree.Distribute({}, cv::Rect(0, 0, 10, 10), 5, selected);
  EXPECT_TRUE(selected.empty());
  quadtree.Distribute(one, cv::Rect(0, 0, 10, 10), 5, selected);
  EXPECT_EQ(selected, std::vector<int>{0});
  // Half-open region: x = 10 lies outside [0, 10).
  const std::vector<Corner> outside = {{10, 5, 10.0F}};
  EXPECT_THROW(quadtree.Distribute(outside, cv::Rect(0, 0, 10, 10), 5, selected), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::features
