#pragma once
// Whether a camera's depth is read in the right unit. Read with the wrong DepthMapFactor every depth is off by one
// factor: a camera's millimetres read as TUM's 5000 units a metre come out five times too near, and the map, the
// trajectory and the ATE shrink with them while every frame still "tracks". A room seen by an RGB-D camera has its
// valid depth spread over metres; depth read in the wrong unit does not look like one. Judged once, on the first
// frame with depth over a fifth of its pixels (docs/settings.md, Depth.checkUnits).

#include <optional>
#include <string>

#include <opencv2/core/mat.hpp>

namespace hoidslam::pipeline {

// How a frame's valid depth (finite, > 0) is spread.
struct DepthSpread {
  double valid_share = 0.0;  // of the pixels
  double median_m = 0.0;
  double p90_m = 0.0;        // 90 % of the valid depth is nearer
};

// The spread of `depth_m` (CV_32FC1 metres), or nullopt when under a fifth of its pixels have depth (a covered lens,
// a blank wall too near): such a frame says nothing of the unit.
std::optional<DepthSpread> MeasureDepth(const cv::Mat& depth_m);

// What is likely wrong with depth spread as no room is, read with `depth_factor` units a metre: a median under
// 0.3 m or over 12 m, or 90 % of it within a metre. Empty when the spread is that of a room.
std::string DepthUnitsProblem(const DepthSpread& spread, double depth_factor);

}  // namespace hoidslam::pipeline
