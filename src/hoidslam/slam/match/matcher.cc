#include "hoidslam/slam/match/matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/features2d.hpp>

#include "hoidslam/features/orb_extractor.h"

namespace hoidslam::slam {
namespace {

constexpr int kRotationBins = 30;  // 12° each

// Whether keypoint i of `frame` is free to take a new match: unmatched, or matched to a point no keyframe sees.
bool IsFree(const Frame& frame, int i) {
  const MapPoint* p = frame.map_points[static_cast<std::size_t>(i)];
  return p == nullptr || p->num_observations() == 0;
}

// Applies new matches found for `frame` (new_matches[i] set) after the rotation-consistency check.
int ApplyMatches(Frame& frame, std::vector<MapPoint*>& new_matches, std::span<const float> angle_change) {
  KeepConsistentRotations(new_matches, angle_change);
  int n = 0;
  for (std::size_t i = 0; i < new_matches.size(); ++i) {
    if (new_matches[i] == nullptr) continue;
    frame.map_points[i] = new_matches[i];
    frame.outlier[i] = 0;
    ++n;
  }
  return n;
}

}  // namespace

int DescriptorDistance(const MapPoint& point, const KeypointSet& keypoints, int i) {
  return features::DescriptorDistance(point.descriptor().ptr(), keypoints.descriptor(i));
}

namespace {

// Which matches (matched[i] != 0) have an orientation change in one of the three most common 12° bins.
std::vector<std::uint8_t> ConsistentRotations(std::span<const std::uint8_t> matched, std::span<const float> angle_change) {
  std::array<int, kRotationBins> counts{};
  const auto bin_of = [&](std::size_t i) {
    float change = std::fmod(angle_change[i], 360.0F);
    if (change < 0.0F) change += 360.0F;
    return std::min(kRotationBins - 1, static_cast<int>(change * kRotationBins / 360.0F));
  };
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (matched[i] != 0) ++counts[static_cast<std::size_t>(bin_of(i))];
  }
  // The three fullest bins; the second and third only if they hold a tenth of the first.
  std::array<int, kRotationBins> order{};
  for (int b = 0; b < kRotationBins; ++b) order[static_cast<std::size_t>(b)] = b;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return counts[static_cast<std::size_t>(a)] > counts[static_cast<std::size_t>(b)];
  });
  std::array<bool, kRotationBins> keep{};
  const int top = counts[static_cast<std::size_t>(order[0])];
  for (int k = 0; k < 3; ++k) {
    const int c = counts[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
    if (c > 0 && (k == 0 || c >= 0.1 * top)) keep[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = true;
  }
  std::vector<std::uint8_t> consistent(matched.size(), 0);
  for (std::size_t i = 0; i < matched.size(); ++i) {
    consistent[i] = matched[i] != 0 && keep[static_cast<std::size_t>(bin_of(i))] ? 1 : 0;
  }
  return consistent;
}

}  // namespace

void KeepConsistentRotations(std::vector<MapPoint*>& matches, std::span<const float> angle_change) {
  std::vector<std::uint8_t> matched(matches.size());
  for (std::size_t i = 0; i < matches.size(); ++i) matched[i] = matches[i] != nullptr ? 1 : 0;
  const std::vector<std::uint8_t> keep = ConsistentRotations(matched, angle_change);
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (keep[i] == 0) matches[i] = nullptr;
  }
}

void KeepConsistentRotations(std::vector<int>& partner, std::span<const float> angle_change) {
  std::vector<std::uint8_t> matched(partner.size());
  for (std::size_t i = 0; i < partner.size(); ++i) matched[i] = partner[i] >= 0 ? 1 : 0;
  const std::vector<std::uint8_t> keep = ConsistentRotations(matched, angle_change);
  for (std::size_t i = 0; i < partner.size(); ++i) {
    if (keep[i] == 0) partner[i] = -1;
  }
}

int SearchByProjection(Frame& current, const Frame& last, double radius) {
  const KeypointSet& cur = *current.keypoints;
  const KeypointSet& prev = *last.keypoints;
  const Sensor& sensor = cur.sensor();
  const auto& scale = sensor.pyramid.scale;
  const int top_level = sensor.pyramid.levels() - 1;

  // Moving forward (more than one baseline along the optical axis) points look larger, so they are found at the
  // same or coarser levels; moving backward at the same or finer ones.
  const Eigen::Vector3d t_lc = last.T_cw * current.center();
  const double baseline = sensor.camera.bf / sensor.camera.fx;
  const bool forward = t_lc.z() > baseline;
  const bool backward = -t_lc.z() > baseline;

  std::vector<MapPoint*> found(static_cast<std::size_t>(cur.size()), nullptr);
  std::vector<int> found_distance(static_cast<std::size_t>(cur.size()), std::numeric_limits<int>::max());
  std::vector<float> angle_change(static_cast<std::size_t>(cur.size()), 0.0F);
  std::vector<int> nearby;
  for (int i = 0; i < prev.size(); ++i) {
    if (!last.IsInlier(i)) continue;
    MapPoint* point = last.map_points[static_cast<std::size_t>(i)];
    if (point->bad()) continue;
    const Eigen::Vector3d p_c = current.T_cw * point->position();
    if (p_c.z() <= 0.0) continue;
    const Eigen::Vector2d uv = sensor.camera.Project(p_c);
    if (!sensor.InImage(uv.x(), uv.y())) continue;
    const int last_level = prev.level(i);
    const double r = radius * scale[static_cast<std::size_t>(last_level)];
    const int min_level = forward ? last_level : backward ? 0 : std::max(0, last_level - 1);
    const int max_level = forward ? top_level : backward ? last_level : std::min(top_level, last_level + 1);
    const double ur = uv.x() - sensor.camera.bf / p_c.z();

    int best_distance = std::numeric_limits<int>::max();
    int best = -1;
    cur.FeaturesInArea(uv.x(), uv.y(), r, min_level, max_level, nearby);
    for (const int j : nearby) {
      if (!IsFree(current, j)) continue;
      if (cur.has_depth(j) && std::abs(ur - cur.right(j)) > r) continue;
      const int d = DescriptorDistance(*point, cur, j);
      if (d < best_distance) {
        best_distance = d;
        best = j;
      }
    }
    if (best < 0 || best_distance > kDescriptorDistanceHigh) continue;
    const auto b = static_cast<std::size_t>(best);
    if (best_distance >= found_distance[b]) continue;  // a better candidate already took this keypoint
    found[b] = point;
    found_distance[b] = best_distance;
    angle_change[b] = prev.keypoint(i).angle - cur.keypoint(best).angle;
  }
  return ApplyMatches(current, found, angle_change);
}

bool ProjectIntoFrame(const MapPoint& point, const core::Pose& T_cw, const Sensor& sensor, double min_view_cos,
                      ProjectedPoint& projected) {
  const Eigen::Vector3d p_c = T_cw * point.position();
  if (p_c.z() <= 0.0) return false;
  const Eigen::Vector2d uv = sensor.camera.Project(p_c);
  if (!sensor.InImage(uv.x(), uv.y())) return false;
  const Eigen::Vector3d ray = point.position() - T_cw.inverse().translation();
  const double distance = ray.norm();
  if (distance < point.min_distance() || distance > point.max_distance()) return false;
  const double view_cos = ray.dot(point.normal()) / distance;
  if (view_cos < min_view_cos) return false;
  projected.point = const_cast<MapPoint*>(&point);
  projected.uv = uv;
  projected.ur = uv.x() - sensor.camera.bf / p_c.z();
  projected.level = point.PredictLevel(distance, sensor.pyramid);
  projected.view_cos = view_cos;
  return true;
}

int SearchByProjection(Frame& frame, std::span<const ProjectedPoint> points, double radius, int max_distance) {
  const KeypointSet& keypoints = *frame.keypoints;
  const auto& scale = keypoints.sensor().pyramid.scale;
  int matches = 0;
  std::vector<int> nearby;
  for (const ProjectedPoint& projected : points) {
    const MapPoint& point = *projected.point;
    if (point.bad()) continue;
    const double level_scale = scale[static_cast<std::size_t>(projected.level)];
    // Oblique views make the descriptor less predictable: search wider.
    const double r = radius * (projected.view_cos > 0.998 ? 2.5 : 4.0) * level_scale;
    int best_distance = 256, second_distance = 256, best_level = -1, second_level = -1, best = -1;
    keypoints.FeaturesInArea(projected.uv.x(), projected.uv.y(), r, projected.level - 1, projected.level, nearby);
    for (const int j : nearby) {
      if (!IsFree(frame, j)) continue;
      if (keypoints.has_depth(j) && std::abs(projected.ur - keypoints.right(j)) > r) continue;
      const int d = DescriptorDistance(point, keypoints, j);
      if (d < best_distance) {
        second_distance = best_distance;
        second_level = best_level;
        best_distance = d;
        best_level = keypoints.level(j);
        best = j;
      } else if (d < second_distance) {
        second_distance = d;
        second_level = keypoints.level(j);
      }
    }
    if (best < 0 || best_distance > max_distance) continue;
    // Ambiguous between two keypoints of the same level: leave it.
    if (best_level == second_level && best_distance > 0.8 * second_distance) continue;
    frame.map_points[static_cast<std::size_t>(best)] = projected.point;
    frame.outlier[static_cast<std::size_t>(best)] = 0;
    ++matches;
  }
  return matches;
}

int SearchByDescriptor(const KeyFrame& keyframe, const Frame& frame, std::vector<MapPoint*>& matches, float ratio) {
  const KeypointSet& kf = keyframe.keypoints();
  const KeypointSet& fr = *frame.keypoints;
  matches.assign(static_cast<std::size_t>(fr.size()), nullptr);
  std::vector<int> rows;
  for (int i = 0; i < kf.size(); ++i) {
    const MapPoint* p = keyframe.map_point(i);
    if (p != nullptr && !p->bad()) rows.push_back(i);
  }
  if (rows.empty() || fr.size() < 2) return 0;
  cv::Mat query(static_cast<int>(rows.size()), 32, CV_8UC1);
  for (std::size_t r = 0; r < rows.size(); ++r) kf.descriptors().row(rows[r]).copyTo(query.row(static_cast<int>(r)));

  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(query, fr.descriptors(), knn, 2);
  std::vector<int> taken_distance(static_cast<std::size_t>(fr.size()), std::numeric_limits<int>::max());
  std::vector<float> angle_change(static_cast<std::size_t>(fr.size()), 0.0F);
  for (std::size_t r = 0; r < knn.size(); ++r) {
    if (knn[r].size() < 2) continue;
    const cv::DMatch& best = knn[r][0];
    const auto distance = static_cast<int>(best.distance);
    if (distance > kDescriptorDistanceLow || best.distance > ratio * knn[r][1].distance) continue;
    const auto j = static_cast<std::size_t>(best.trainIdx);
    if (distance >= taken_distance[j]) continue;
    matches[j] = keyframe.map_point(rows[r]);
    taken_distance[j] = distance;
    angle_change[j] = kf.keypoint(rows[r]).angle - fr.keypoint(best.trainIdx).angle;
  }
  KeepConsistentRotations(matches, angle_change);
  return static_cast<int>(std::count_if(matches.begin(), matches.end(), [](const MapPoint* p) { return p != nullptr; }));
}

int SearchByBoW(const KeyFrame& keyframe, const Frame& frame, const bow::FeatureVector& frame_features,
                std::vector<MapPoint*>& matches, float ratio) {
  const KeypointSet& kf = keyframe.keypoints();
  const KeypointSet& fr = *frame.keypoints;
  matches.assign(static_cast<std::size_t>(fr.size()), nullptr);
  std::vector<int> taken_distance(static_cast<std::size_t>(fr.size()), std::numeric_limits<int>::max());
  std::vector<float> angle_change(static_cast<std::size_t>(fr.size()), 0.0F);
  const bow::FeatureVector& keyframe_features = keyframe.words().features;
  auto a = keyframe_features.begin();
  auto b = frame_features.begin();
  while (a != keyframe_features.end() && b != frame_features.end()) {
    if (a->node != b->node) {
      (a->node < b->node ? ++a : ++b);
      continue;
    }
    for (const int i : a->keypoints) {
      MapPoint* p = keyframe.map_point(i);
      if (p == nullptr || p->bad()) continue;
      NearestTwo nearest(kf.descriptor(i));
      for (const int j : b->keypoints) nearest.Offer(j, fr.descriptor(j));
      const int best = nearest.best(), best_distance = nearest.best_distance();
      if (best < 0 || best_distance > kDescriptorDistanceLow ||
          static_cast<float>(best_distance) > ratio * static_cast<float>(nearest.second_distance())) {
        continue;
      }
      const auto j = static_cast<std::size_t>(best);
      if (best_distance >= taken_distance[j]) continue;
      matches[j] = p;
      taken_distance[j] = best_distance;
      angle_change[j] = kf.keypoint(i).angle - fr.keypoint(best).angle;
    }
    ++a;
    ++b;
  }
  KeepConsistentRotations(matches, angle_change);
  return static_cast<int>(std::count_if(matches.begin(), matches.end(), [](const MapPoint* p) { return p != nullptr; }));
}

}  // namespace hoidslam::slam
