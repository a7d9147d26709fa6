#include "hoidslam/slam/track/frame_placement.h"

#include <algorithm>
#include <cmath>

#include "hoidslam/slam/optimize/pose_optimizer.h"

namespace hoidslam::slam {
namespace {

constexpr double kStep = 0.25;  // pixels, of the position and the disparity

// `value` in steps of kStep, when it is in [0, 2^bits).
std::optional<std::uint64_t> Quarters(double value, int bits) {
  const double steps = std::round(value / kStep);
  if (!(steps >= 0.0 && steps < static_cast<double>(std::uint64_t{1} << bits))) return std::nullopt;
  return static_cast<std::uint64_t>(steps);
}

}  // namespace

std::optional<RecordedInlier> RecordedInlier::Make(MapPointId point, const Eigen::Vector2d& uv, int level,
                                                   std::optional<double> disparity) {
  const auto u = Quarters(uv.x(), 13);
  const auto v = Quarters(uv.y(), 13);
  // A disparity that rounds to 0 would read as no depth: one quarter pixel at the least (some 40 m at TUM's bf).
  const auto d = disparity ? Quarters(std::max(*disparity, kStep), 11) : std::optional<std::uint64_t>(0);
  if (point >= (MapPointId{1} << 24) || !u || !v || level < 0 || level > 7 || !d) return std::nullopt;
  return RecordedInlier(point << 40 | *u << 27 | *v << 14 | static_cast<std::uint64_t>(level) << 11 | *d);
}

Eigen::Vector2d RecordedInlier::uv() const {
  return {kStep * static_cast<double>((bits_ >> 27) & 0x1FFF), kStep * static_cast<double>((bits_ >> 14) & 0x1FFF)};
}

double RecordedInlier::disparity() const { return kStep * static_cast<double>(bits_ & 0x7FF); }

std::vector<RecordedInlier> RecordInliers(const Frame& frame) {
  const KeypointSet& keypoints = *frame.keypoints;
  std::vector<RecordedInlier> inliers;
  inliers.reserve(static_cast<std::size_t>(std::count_if(frame.map_points.begin(), frame.map_points.end(),
                                                         [](const MapPoint* p) { return p != nullptr; })));
  for (int i = 0; i < frame.size(); ++i) {
    if (!frame.IsInlier(i)) continue;
    const Eigen::Vector2d& uv = keypoints.undistorted(i);
    const std::optional<double> disparity =
        keypoints.has_depth(i) ? std::optional<double>(uv.x() - keypoints.right(i)) : std::nullopt;
    const auto inlier =
        RecordedInlier::Make(frame.map_points[static_cast<std::size_t>(i)]->id(), uv, keypoints.level(i), disparity);
    if (inlier) inliers.push_back(*inlier);
  }
  return inliers;
}

std::optional<core::Pose> PlaceByInliers(const Map& map, std::span<const RecordedInlier> inliers, const Sensor& sensor,
                                         const core::Pose& T_cw) {
  std::vector<Eigen::Vector3d> points;
  std::vector<KeypointMeasurement> measurements;
  points.reserve(inliers.size());
  measurements.reserve(inliers.size());
  for (const RecordedInlier& inlier : inliers) {
    const MapPoint* point = map.Point(inlier.point())->Current();
    if (point->bad()) continue;
    points.push_back(point->position());
    KeypointMeasurement& m = measurements.emplace_back();
    m.uv = inlier.uv();
    m.has_depth = inlier.has_depth();
    m.ur = m.uv.x() - inlier.disparity();
    m.inv_sigma2 = sensor.pyramid.inv_sigma2.at(static_cast<std::size_t>(inlier.level()));
  }
  if (points.size() < static_cast<std::size_t>(kMinPlacementInliers)) return std::nullopt;
  core::Pose placed = T_cw;
  std::vector<std::uint8_t> outlier;
  const int agreeing = OptimizePose(sensor.camera, points, measurements, placed, outlier);
  if (agreeing < kMinPlacementInliers || 2 * static_cast<std::size_t>(agreeing) < points.size()) return std::nullopt;
  return placed;
}

}  // namespace hoidslam::slam
