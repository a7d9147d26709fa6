#pragma once
// Depth-refined exclusion (mode hoidplus, part 1): what inside a detector's box belongs to the thing the box was
// drawn around, told apart from the background behind it by depth. A person's box also holds the wall behind
// them; the paper drops all of it. Here the dominant depth mode of the box's centre is taken as the foreground,
// and only keypoints at or in front of it (or without depth) are dropped.

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/options.h"
#include "hoidslam/hoid/filter.h"

namespace hoidslam::hoid {

// The depth extent of a box's foreground, metres.
struct DepthCluster {
  float near = 0.0F;    // where the foreground mode starts
  float far = 0.0F;     // where it ends
  float median = 0.0F;  // of the samples between
  float cut = 0.0F;     // keypoints nearer than this belong to the foreground (or stand in front of it): far,
                        // or HoidPlusOptions::depth_extent behind either mode's median when that is farther
  // (median is the central mode's: the thing the box is about.)
  std::size_t samples = 0;
};

// The foreground of `box` in `depth` (CV_32FC1, metres, 0 or non-finite = invalid). The box's valid depths,
// sampled on a grid of at most about 500 points, go into a histogram over log depth (bins options.depth_bin of
// the depth wide), smoothed and cut into modes where the density falls below options.valley of the mode's peak
// so far. The foreground spans the mode that holds most of the box's centre (samples weighted 1 there, falling to
// 0 at the edges) and the nearest mode holding options.foreground_share of the samples. nullopt when the box
// holds fewer than 10 valid samples. Throws std::invalid_argument unless depth is CV_32FC1.
std::optional<DepthCluster> ForegroundDepth(const cv::Mat& depth, const cv::Rect2f& box,
                                            const core::HoidPlusOptions& options);

// Where keypoints are dropped: inside `box` (half-open, as cv::Rect2f::contains), those without valid depth and
// those whose depth, or any valid depth within `edge_margin` pixels of them, is nearer than `cut` (+inf: all
// inside). The margin drops corners on a moving outline, whose own pixel may see the background, with it.
struct ExclusionRegion {
  cv::Rect2f box;
  float cut = std::numeric_limits<float>::infinity();
  int edge_margin = 0;
};

// keep[i] = 0 when keypoints[i] is dropped by some region, else 1 (`keep` is resized). With an empty `depth`
// every keypoint inside a region is dropped.
void MarkKeypointsBehindForeground(std::span<const cv::KeyPoint> keypoints, const cv::Mat& depth,
                                   std::span<const ExclusionRegion> regions, std::vector<std::uint8_t>& keep);

// The pixels the regions drop, as a CV_8UC1 mask of `size` (255 dropped), by the same test.
cv::Mat PaintExclusionRegions(std::span<const ExclusionRegion> regions, const cv::Mat& depth, cv::Size size);

// `box` grown by `margin` of its width and height on each side.
cv::Rect2f GrowBox(const cv::Rect2f& box, double margin);

}  // namespace hoidslam::hoid
