#pragma once
// Spreading corners evenly over an image region, the idea of ORB-SLAM's DistributeOctTree: the region is split
// into quadrants, and quadrants with more than one corner again, until there are as many non-empty cells as
// corners wanted (or no cell can split); each cell then keeps its strongest corner. Strong corners crowded into
// one textured patch thus give way to weaker ones elsewhere, which is what tracking needs.

#include <cstdint>
#include <span>
#include <vector>

#include <opencv2/core/types.hpp>

namespace hoidslam::features {

// A FAST corner at one pyramid level: pixel position and score.
struct Corner {
  int x = 0;
  int y = 0;
  float response = 0.0F;
};

// Reusable (its buffers live from call to call); not thread-safe.
class QuadtreeDistributor {
 public:
  // Sets `selected` to the indices into `corners` of at most `n` corners spread over `region`, one per quadtree
  // cell, in the cells' order: n of them when there are at least n corners. Deterministic: ties (cells of equal count,
  // corners of equal response) are broken by position. Throws std::invalid_argument when a corner lies outside `region`
  // (half-open, like cv::Rect).
  void Distribute(std::span<const Corner> corners, const cv::Rect& region, int n, std::vector<int>& selected);

 private:
  // A cell: the half-open box [x0, x1) × [y0, y1) and its corners, order_[begin, end).
  struct Node {
    int x0, y0, x1, y1;
    int begin, end;
    int Count() const { return end - begin; }
  };

  // Partitions the node's corners into its four quadrants (top-left, top-right, bottom-left, bottom-right) and
  // writes the non-empty ones to `children`; returns how many.
  int Split(const Node& node, std::span<const Corner> corners, Node (&children)[4]);
  // Splits the largest cells first, one at a time, until there are at least `n` cells (ORB-SLAM's endgame).
  void SplitLargestFirst(std::span<const Corner> corners, int n);

  std::vector<int> order_;
  std::vector<int> column_start_;
  std::vector<int> next_slot_;
  std::vector<Node> nodes_;
  std::vector<Node> next_;
  std::vector<int> candidates_;
  std::vector<int> scratch_;
  std::vector<std::uint8_t> quadrant_;
};

}  // namespace hoidslam::features
