#include "hoidslam/features/quadtree.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace hoidslam::features {

int QuadtreeDistributor::Split(const Node& node, std::span<const Corner> corners, Node (&children)[4]) {
  // Rounding the halves up keeps the boxes integral; a box one pixel wide then only splits in y, and a cell of
  // one pixel holds one corner at most, so splitting always ends.
  const int mx = node.x0 + (node.x1 - node.x0 + 1) / 2;
  const int my = node.y0 + (node.y1 - node.y0 + 1) / 2;
  // A counting sort by quadrant (top-left, top-right, bottom-left, bottom-right): branch-free, unlike partitions.
  const auto count = static_cast<std::size_t>(node.Count());
  quadrant_.resize(count);
  scratch_.resize(count);
  int start[5] = {};
  for (std::size_t k = 0; k < count; ++k) {
    const Corner& c = corners[order_[node.begin + k]];
    const int q = (c.y >= my ? 2 : 0) + (c.x >= mx ? 1 : 0);
    quadrant_[k] = static_cast<std::uint8_t>(q);
    ++start[q + 1];
  }
  for (int q = 1; q <= 4; ++q) start[q] += start[q - 1];
  int next[4] = {start[0], start[1], start[2], start[3]};
  for (std::size_t k = 0; k < count; ++k) scratch_[next[quadrant_[k]]++] = order_[node.begin + k];
  std::copy(scratch_.begin(), scratch_.end(), order_.begin() + node.begin);

  const int x[3] = {node.x0, mx, node.x1};
  const int y[3] = {node.y0, my, node.y1};
  int made = 0;
  for (int q = 0; q < 4; ++q) {
    if (start[q + 1] == start[q]) continue;
    children[made++] = {
        x[q % 2], y[q / 2], x[q % 2 + 1], y[q / 2 + 1], node.begin + start[q], node.begin + start[q + 1]};
  }
  return made;
}

void QuadtreeDistributor::SplitLargestFirst(std::span<const Corner> corners, int n) {
  const auto target = static_cast<std::size_t>(n);
  for (;;) {
    candidates_.clear();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (nodes_[i].Count() > 1) candidates_.push_back(static_cast<int>(i));
    }
    if (candidates_.empty()) return;
    // Cells never overlap, so their top-left corners order equal counts totally.
    std::sort(candidates_.begin(), candidates_.end(), [&](int a, int b) {
      const Node& na = nodes_[a];
      const Node& nb = nodes_[b];
      if (na.Count() != nb.Count()) return na.Count() > nb.Count();
      return na.y0 != nb.y0 ? na.y0 < nb.y0 : na.x0 < nb.x0;
    });
    for (int i : candidates_) {
      Node children[4];
      const int count = Split(nodes_[i], corners, children);
      nodes_[i] = children[0];
      nodes_.insert(nodes_.end(), children + 1, children + count);
      if (nodes_.size() >= target) return;
    }
  }
}

void QuadtreeDistributor::Distribute(std::span<const Corner> corners, const cv::Rect& region, int n,
                                     std::vector<int>& selected) {
  selected.clear();
  if (n <= 0 || corners.empty() || region.empty()) return;
  for (const Corner& c : corners) {
    if (!region.contains(cv::Point(c.x, c.y))) {
      throw std::invalid_argument("QuadtreeDistributor: corner (" + std::to_string(c.x) + ", " + std::to_string(c.y) +
                                  ") outside the region");
    }
  }

  // Start from about square cells side by side (ORB-SLAM: round(width / height) of them), so that a wide region
  // is not split into flat quadrants.
  const int ratio = static_cast<int>(std::lround(static_cast<double>(region.width) / region.height));
  const int columns = std::clamp(ratio, 1, std::min(n, region.width));
  const auto column_of = [&](const Corner& c) {
    return static_cast<int>(static_cast<long long>(c.x - region.x) * columns / region.width);
  };
  // Counting sort of the corners by column.
  column_start_.assign(static_cast<std::size_t>(columns) + 1, 0);
  for (const Corner& c : corners) ++column_start_[column_of(c) + 1];
  std::partial_sum(column_start_.begin(), column_start_.end(), column_start_.begin());
  order_.resize(corners.size());
  next_slot_.assign(column_start_.begin(), column_start_.end() - 1);
  for (std::size_t i = 0; i < corners.size(); ++i) order_[next_slot_[column_of(corners[i])]++] = static_cast<int>(i);
  nodes_.clear();
  for (int col = 0; col < columns; ++col) {
    const int begin = column_start_[col];
    const int end = column_start_[col + 1];
    if (end > begin) {
      const int x0 = region.x + static_cast<int>(static_cast<long long>(region.width) * col / columns);
      const int x1 = region.x + static_cast<int>(static_cast<long long>(region.width) * (col + 1) / columns);
      nodes_.push_back({x0, region.y, x1, region.y + region.height, begin, end});
    }
  }

  // Split every cell with more than one corner while that cannot make more than n cells (a split adds up to 3),
  // then the largest cells first.
  const auto target = static_cast<std::size_t>(n);
  while (nodes_.size() < target) {
    std::size_t splittable = 0;
    for (const Node& node : nodes_) splittable += node.Count() > 1 ? 1 : 0;
    if (splittable == 0) break;
    if (nodes_.size() + 3 * splittable > target) {
      SplitLargestFirst(corners, n);
      break;
    }
    next_.clear();
    for (const Node& node : nodes_) {
      if (node.Count() == 1) {
        next_.push_back(node);
        continue;
      }
      Node children[4];
      const int count = Split(node, corners, children);
      next_.insert(next_.end(), children, children + count);
    }
    nodes_.swap(next_);
  }

  // The strongest corner of each cell.
  const auto stronger = [&](int a, int b) {
    const Corner& ca = corners[a];
    const Corner& cb = corners[b];
    if (ca.response != cb.response) return ca.response > cb.response;
    return ca.y != cb.y ? ca.y < cb.y : ca.x < cb.x;  // equal scores: the topmost, then leftmost
  };
  selected.reserve(nodes_.size());
  for (const Node& node : nodes_) {
    int best = order_[node.begin];
    for (int k = node.begin + 1; k < node.end; ++k) best = std::min(best, order_[k], stronger);
    selected.push_back(best);
  }

  // The last split may overshoot n by up to 3 cells (ORB-SLAM keeps them): drop the weakest of those corners.
  if (selected.size() > target) {
    candidates_ = selected;
    std::nth_element(candidates_.begin(), candidates_.begin() + n - 1, candidates_.end(), stronger);
    const int weakest_kept = candidates_[static_cast<std::size_t>(n - 1)];
    std::erase_if(selected, [&](int i) { return stronger(weakest_kept, i); });
  }
}

}  // namespace hoidslam::features
