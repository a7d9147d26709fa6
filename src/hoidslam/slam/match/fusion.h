#pragma once
// Map point fusion: points projected into a keyframe merge with the keypoints they land on, so that one place is
// one point. Local mapping fuses a new keyframe with its neighbourhood; loop closing fuses the two ends of a loop.

#include <span>

#include "hoidslam/slam/data/map.h"

namespace hoidslam::slam {

// Projects `points` into `keyframe` and merges each with the keypoint it lands on (within `radius` pixels at level
// 0, scaled with the level, and a close descriptor): a keypoint that has a point already keeps the better-observed
// of the two, a free one takes the projected point. Map::mutex() held exclusively.
void FuseByProjection(Map& map, KeyFrame* keyframe, std::span<MapPoint* const> points, double radius);

}  // namespace hoidslam::slam
