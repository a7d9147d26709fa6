#include "hoidslam/slam/match/fusion.h"

#include "hoidslam/slam/match/matcher.h"

namespace hoidslam::slam {

void FuseByProjection(Map& map, KeyFrame* keyframe, std::span<MapPoint* const> points, double radius) {
  const KeypointSet& keypoints = keyframe->keypoints();
  const Sensor& sensor = keypoints.sensor();
  std::vector<int> nearby;
  for (MapPoint* point : points) {
    if (point->bad() || point->IndexIn(keyframe) >= 0) continue;
    ProjectedPoint projected;
    if (!ProjectIntoFrame(*point, keyframe->T_cw(), sensor, 0.5, projected)) continue;
    const double r = radius * sensor.pyramid.scale[static_cast<std::size_t>(projected.level)];
    int best = -1, best_distance = 256;
    keypoints.FeaturesInArea(projected.uv.x(), projected.uv.y(), r, projected.level - 1, projected.level, nearby);
    for (const int j : nearby) {
      const KeypointMeasurement m = keypoints.Measurement(j);
      double error = (projected.uv - m.uv).squaredNorm();
      if (m.has_depth) error += (projected.ur - m.ur) * (projected.ur - m.ur);
      if (error * m.inv_sigma2 > (m.has_depth ? kChi2Stereo : kChi2Mono)) continue;
      const int d = DescriptorDistance(*point, keypoints, j);
      if (d < best_distance) {
        best_distance = d;
        best = j;
      }
    }
    if (best < 0 || best_distance > kDescriptorDistanceLow) continue;
    MapPoint* existing = keyframe->map_point(best);
    if (existing != nullptr && !existing->bad()) {
      if (existing->num_observations() > point->num_observations()) {
        map.ReplacePoint(point, existing);
      } else {
        map.ReplacePoint(existing, point);
      }
    } else {
      map.AddObservation(point, keyframe, best);
    }
  }
}

}  // namespace hoidslam::slam
