#include "hoidslam/slam/local_mapper.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <shared_mutex>
#include <unordered_map>
#include <unordered_set>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/core/pointer_set.h"
#include "hoidslam/slam/match/fusion.h"
#include "hoidslam/slam/match/matcher.h"

namespace hoidslam::slam {
namespace {

// A point seen by two cameras: the linear (DLT) triangulation of undistorted pixels uv1, uv2.
Eigen::Vector3d Triangulate(const RgbdCamera& camera, const core::Pose& T_c1w, const Eigen::Vector2d& uv1,
                            const core::Pose& T_c2w, const Eigen::Vector2d& uv2) {
  const auto rows = [&](const core::Pose& T, const Eigen::Vector2d& uv, Eigen::Matrix4d& A, int r) {
    const Eigen::Matrix<double, 3, 4> P = T.matrix().topRows<3>();
    const double x = (uv.x() - camera.cx) / camera.fx;
    const double y = (uv.y() - camera.cy) / camera.fy;
    A.row(r) = x * P.row(2) - P.row(0);
    A.row(r + 1) = y * P.row(2) - P.row(1);
  };
  Eigen::Matrix4d A;
  rows(T_c1w, uv1, A, 0);
  rows(T_c2w, uv2, A, 2);
  const Eigen::Vector4d X = Eigen::JacobiSVD<Eigen::Matrix4d>(A, Eigen::ComputeFullV).matrixV().col(3);
  return X.head<3>() / X.w();
}

// Whether keypoint i of `keyframe` explains point p_w within the χ² threshold of its measurement.
bool Reprojects(const KeyFrame& keyframe, int i, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_c = keyframe.T_cw() * p_w;
  if (p_c.z() <= 0.0) return false;
  const KeypointSet& keypoints = keyframe.keypoints();
  const RgbdCamera& camera = keypoints.sensor().camera;
  const KeypointMeasurement m = keypoints.Measurement(i);
  const Eigen::Vector2d uv = camera.Project(p_c);
  double error = (uv - m.uv).squaredNorm();
  if (m.has_depth) {
    const double ur = uv.x() - camera.bf / p_c.z();
    error += (ur - m.ur) * (ur - m.ur);
    return error * m.inv_sigma2 <= kChi2Stereo;
  }
  return error * m.inv_sigma2 <= kChi2Mono;
}

// The parallax (as a cosine) that a keypoint's depth measurement gives on its own: the angle one baseline
// subtends at that depth; 2 (no parallax at all) without depth.
double DepthParallaxCos(const KeypointSet& keypoints, int i) {
  if (!keypoints.has_depth(i)) return 2.0;
  const double baseline = keypoints.sensor().camera.bf / keypoints.sensor().camera.fx;
  return std::cos(2.0 * std::atan2(baseline / 2.0, keypoints.depth(i)));
}

}  // namespace

void LocalMapperOptions::Check() const {
  if (triangulation_neighbours < 1) {
    throw core::InputError::ForParameter("LocalMapping.triangulationNeighbours",
                                         fmt::format("must be >= 1, got {}", triangulation_neighbours));
  }
  if (fusion_neighbours < 1) {
    throw core::InputError::ForParameter("LocalMapping.fusionNeighbours",
                                         fmt::format("must be >= 1, got {}", fusion_neighbours));
  }
  if (!(redundant_ratio > 0.0 && redundant_ratio <= 1.0)) {
    throw core::InputError::ForParameter("LocalMapping.redundantRatio",
                                         fmt::format("must be in (0, 1], got {}", redundant_ratio));
  }
}

LocalMapper::LocalMapper(Map& map, const bow::Vocabulary& vocabulary, const LocalMapperOptions& options,
                         std::function<void(KeyFrame*)> mapped)
    : map_(map), vocabulary_(vocabulary), options_(options), mapped_(std::move(mapped)) {
  options_.Check();
}

LocalMapper::~LocalMapper() { Stop(); }

void LocalMapper::Insert(KeyFrame* keyframe) {
  {
    std::lock_guard lock(queue_mutex_);
    queue_.push_back(keyframe);
  }
  abort_bundle_adjustment_ = true;
  queue_changed_.notify_all();
}

bool LocalMapper::Idle() const {
  std::lock_guard lock(queue_mutex_);
  return queue_.empty() && !busy_;
}

std::size_t LocalMapper::Queued() const {
  std::lock_guard lock(queue_mutex_);
  return queue_.size();
}

KeyFrame* LocalMapper::NextKeyFrame() {
  std::lock_guard lock(queue_mutex_);
  if (queue_.empty()) return nullptr;
  KeyFrame* keyframe = queue_.front();
  queue_.pop_front();
  busy_ = true;
  abort_bundle_adjustment_ = false;
  return keyframe;
}

LocalMapper::PauseGuard LocalMapper::Pause() {
  {
    std::lock_guard lock(queue_mutex_);
    paused_ = true;
  }
  WaitUntilIdle();
  return PauseGuard(*this);
}

void LocalMapper::WaitUntilIdle() {
  std::unique_lock lock(queue_mutex_);
  queue_changed_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void LocalMapper::Resume() {
  {
    std::lock_guard lock(queue_mutex_);
    paused_ = false;
  }
  queue_changed_.notify_all();
}

bool LocalMapper::Paused() const {
  std::lock_guard lock(queue_mutex_);
  return paused_;
}

void LocalMapper::ProcessQueue() {
  while (KeyFrame* keyframe = NextKeyFrame()) {
    Process(keyframe);
    if (mapped_) mapped_(keyframe);
    {
      std::lock_guard lock(queue_mutex_);
      busy_ = false;
    }
    queue_changed_.notify_all();
  }
}

void LocalMapper::Start() {
  if (!thread_.joinable()) thread_ = std::jthread([this](std::stop_token stop) { Loop(stop); });
}

void LocalMapper::Stop() {
  if (!thread_.joinable()) return;
  thread_.request_stop();
  queue_changed_.notify_all();
  thread_.join();
}

void LocalMapper::Loop(std::stop_token stop) {
  for (;;) {
    {
      std::unique_lock lock(queue_mutex_);
      // Returns when there is work, or when asked to stop.
      queue_changed_.wait(lock, stop, [this] { return !queue_.empty(); });
      if (queue_.empty()) return;  // stop requested and nothing left to do
    }
    ProcessQueue();
  }
}


void LocalMapper::Process(KeyFrame* keyframe) {
  // Its keypoints never change: described without the lock, entered into the database with it.
  bow::ImageWords words = DescribePlace(vocabulary_, keyframe->keypoints());
  {
    std::unique_lock lock(map_.mutex());
    map_.IndexKeyFrame(keyframe, std::move(words));
    // The points tracking matched and created get their descriptors, normals and ranges; the keyframe its edges.
    for (MapPoint* p : keyframe->map_points()) {
      if (p == nullptr || p->bad()) continue;
      map_.UpdatePoint(p);
      if (p->first_keyframe_id() == keyframe->id()) recent_points_.push_back(p);
    }
    map_.UpdateConnections(keyframe);
    CullRecentPoints(keyframe);
    CreateNewPoints(keyframe);
  }
  if (Queued() > 0) return;  // catch up first; the neighbourhood is refined with the last keyframe of a burst
  {
    std::unique_lock lock(map_.mutex());
    FuseNeighbours(keyframe);
  }
  if (Queued() > 0) return;
  RunLocalBundleAdjustment(keyframe);
  std::unique_lock lock(map_.mutex());
  CullKeyFrames(keyframe);
}

void LocalMapper::CullRecentPoints(const KeyFrame* keyframe) {
  // A new point stays if tracking finds it in at least a quarter of the frames it should appear in, and if it is
  // seen by at least 3 keyframes (depth counting double) once two more keyframes have come.
  std::erase_if(recent_points_, [&](MapPoint* p) {
    if (p->bad()) return true;
    const KeyFrameId age = keyframe->id() - p->first_keyframe_id();
    if (p->FoundRatio() < 0.25F || (age >= 2 && p->num_observations() <= 3)) {
      map_.ErasePoint(p);
      return true;
    }
    return age >= 3;  // survived probation
  });
}

namespace {

// The fundamental matrix taking undistorted pixels of keyframe 1 to epipolar lines in keyframe 2.
Eigen::Matrix3d Fundamental(const KeyFrame& keyframe1, const KeyFrame& keyframe2, const RgbdCamera& camera) {
  const core::Pose T21 = keyframe2.T_cw() * keyframe1.T_wc();
  const Eigen::Vector3d& t = T21.translation();
  Eigen::Matrix3d t_cross;
  t_cross << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  Eigen::Matrix3d K;
  K << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1;
  const Eigen::Matrix3d K_inv = K.inverse();
  return K_inv.transpose() * t_cross * T21.linear() * K_inv;
}

// The free keypoint of `neighbour` (no map point yet) that keypoint i of `keyframe` most likely shows, or -1. With
// depth, it is searched near the position the depth predicts; without, along the epipolar line (away from the
// epipole, where the line says little), as ORB-SLAM's search for triangulation does.
int FindPartner(const KeyFrame& keyframe, int i, const KeyFrame& neighbour, const Eigen::Matrix3d& F21,
                const Eigen::Vector2d& epipole, const std::vector<int>& free) {
  const KeypointSet& keypoints = keyframe.keypoints();
  const KeypointSet& other = neighbour.keypoints();
  const Sensor& sensor = keypoints.sensor();
  const int level = keypoints.level(i);
  NearestTwo nearest(keypoints.descriptor(i), kDescriptorDistanceLow);
  if (keypoints.has_depth(i)) {
    const Eigen::Vector3d p_c = neighbour.T_cw() * (keyframe.T_wc() * keypoints.Unproject(i));
    if (p_c.z() <= 0.0) return -1;
    const Eigen::Vector2d uv = sensor.camera.Project(p_c);
    if (!sensor.InImage(uv.x(), uv.y())) return -1;
    const double radius = 5.0 * sensor.pyramid.scale[static_cast<std::size_t>(level)];
    for (const int j : other.FeaturesInArea(uv.x(), uv.y(), radius, std::max(0, level - 1), level + 1)) {
      if (neighbour.map_point(j) == nullptr) nearest.Offer(j, other.descriptor(j));
    }
    return nearest.best();
  }
  const Eigen::Vector3d line = F21 * keypoints.undistorted(i).homogeneous();
  const double line_norm2 = line.head<2>().squaredNorm();
  if (line_norm2 <= 0.0) return -1;
  for (const int j : free) {
    const Eigen::Vector2d& uv2 = other.undistorted(j);
    const double level_scale = sensor.pyramid.scale[static_cast<std::size_t>(other.level(j))];
    if ((uv2 - epipole).squaredNorm() < 100.0 * level_scale) continue;
    const double distance = line.dot(uv2.homogeneous());
    if (distance * distance / line_norm2 < 3.84 * sensor.pyramid.sigma2[static_cast<std::size_t>(other.level(j))]) {
      nearest.Offer(j, other.descriptor(j));
    }
  }
  // A line crosses many keypoints: a match must stand out from the next best along it.
  return nearest.best_distance() < 0.8 * nearest.second_distance() ? nearest.best() : -1;
}

}  // namespace

void LocalMapper::CreateNewPoints(KeyFrame* keyframe) {
  const KeypointSet& keypoints = keyframe->keypoints();
  const Sensor& sensor = keypoints.sensor();
  const RgbdCamera& camera = sensor.camera;
  const double baseline = camera.bf / camera.fx;
  const double ratio_factor = 1.5 * sensor.pyramid.scale[std::min<std::size_t>(1, sensor.pyramid.scale.size() - 1)];

  for (KeyFrame* neighbour : keyframe->BestCovisibles(static_cast<std::size_t>(options_.triangulation_neighbours))) {
    if ((neighbour->center() - keyframe->center()).norm() < baseline) continue;
    const KeypointSet& other = neighbour->keypoints();
    const Eigen::Matrix3d F21 = Fundamental(*keyframe, *neighbour, camera);
    const Eigen::Vector3d centre_in_neighbour = neighbour->T_cw() * keyframe->center();
    const Eigen::Vector2d epipole = centre_in_neighbour.z() > 0.0 ? camera.Project(centre_in_neighbour)
                                                                   : Eigen::Vector2d(-1e9, -1e9);
    std::vector<int> free;
    for (int j = 0; j < other.size(); ++j) {
      if (neighbour->map_point(j) == nullptr) free.push_back(j);
    }
    std::vector<int> partner(static_cast<std::size_t>(keypoints.size()), -1);
    std::vector<float> angle_change(partner.size(), 0.0F);
    for (int i = 0; i < keypoints.size(); ++i) {
      if (keyframe->map_point(i) != nullptr) continue;
      const int j = FindPartner(*keyframe, i, *neighbour, F21, epipole, free);
      if (j < 0) continue;
      partner[static_cast<std::size_t>(i)] = j;
      angle_change[static_cast<std::size_t>(i)] = keypoints.keypoint(i).angle - other.keypoint(j).angle;
    }
    KeepConsistentRotations(partner, angle_change);

    for (int i = 0; i < keypoints.size(); ++i) {
      const int best = partner[static_cast<std::size_t>(i)];
      if (best < 0 || keyframe->map_point(i) != nullptr || neighbour->map_point(best) != nullptr) continue;

      // Triangulate when the two rays see the point from further apart than either depth measurement does;
      // otherwise take the depth measurement with the most parallax, if there is one.
      const Eigen::Vector2d& uv1 = keypoints.undistorted(i);
      const Eigen::Vector2d& uv2 = other.undistorted(best);
      const Eigen::Vector3d ray1 = keyframe->T_wc().linear() *
                                   Eigen::Vector3d((uv1.x() - camera.cx) / camera.fx, (uv1.y() - camera.cy) / camera.fy, 1.0);
      const Eigen::Vector3d ray2 = neighbour->T_wc().linear() *
                                   Eigen::Vector3d((uv2.x() - camera.cx) / camera.fx, (uv2.y() - camera.cy) / camera.fy, 1.0);
      const double rays_cos = ray1.dot(ray2) / (ray1.norm() * ray2.norm());
      const double depth_cos1 = DepthParallaxCos(keypoints, i);
      const double depth_cos2 = DepthParallaxCos(other, best);
      Eigen::Vector3d p_w;
      if (rays_cos > 0.0 && rays_cos < std::min(depth_cos1, depth_cos2) && rays_cos < 0.9998) {
        p_w = Triangulate(camera, keyframe->T_cw(), uv1, neighbour->T_cw(), uv2);
      } else if (keypoints.has_depth(i) && depth_cos1 <= depth_cos2) {
        p_w = keyframe->T_wc() * keypoints.Unproject(i);
      } else if (other.has_depth(best)) {
        p_w = neighbour->T_wc() * other.Unproject(best);
      } else {
        continue;  // neither depth nor enough parallax
      }
      if (!p_w.allFinite() || !Reprojects(*keyframe, i, p_w) || !Reprojects(*neighbour, best, p_w)) continue;

      // The two keypoints' pyramid levels must agree with the two distances.
      const double distance1 = (p_w - keyframe->center()).norm();
      const double distance2 = (p_w - neighbour->center()).norm();
      if (distance1 <= 0.0 || distance2 <= 0.0) continue;
      const double distance_ratio = distance2 / distance1;
      const double level_ratio = sensor.pyramid.scale[static_cast<std::size_t>(keypoints.level(i))] /
                                 sensor.pyramid.scale[static_cast<std::size_t>(other.level(best))];
      if (distance_ratio * ratio_factor < level_ratio || distance_ratio > level_ratio * ratio_factor) continue;

      MapPoint* point = map_.CreateMapPoint(p_w, keyframe, i);
      map_.AddObservation(point, neighbour, best);
      map_.UpdatePoint(point);
      recent_points_.push_back(point);
    }
  }
}


void LocalMapper::FuseNeighbours(KeyFrame* keyframe) {
  std::vector<KeyFrame*> targets;
  std::unordered_set<const KeyFrame*> included = {keyframe};
  for (KeyFrame* neighbour : keyframe->BestCovisibles(static_cast<std::size_t>(options_.fusion_neighbours))) {
    if (neighbour->bad() || !included.insert(neighbour).second) continue;
    targets.push_back(neighbour);
  }
  const std::size_t direct = targets.size();
  for (std::size_t k = 0; k < direct; ++k) {
    for (KeyFrame* second : targets[k]->BestCovisibles(5)) {
      if (!second->bad() && included.insert(second).second) targets.push_back(second);
    }
  }

  // The keyframe's points into its neighbours, then the neighbours' points into the keyframe.
  for (KeyFrame* target : targets) {
    std::vector<MapPoint*> points;
    for (MapPoint* p : keyframe->map_points()) {
      if (p != nullptr && !p->bad()) points.push_back(p);
    }
    FuseByProjection(map_, target, points, 3.0);
  }
  std::vector<MapPoint*> candidates;
  core::PointerSet<MapPoint> seen(targets.size() * keyframe->map_points().size());
  for (const KeyFrame* target : targets) {
    for (MapPoint* p : target->map_points()) {
      if (p != nullptr && !p->bad() && seen.Insert(p)) candidates.push_back(p);
    }
  }
  FuseByProjection(map_, keyframe, candidates, 3.0);

  for (MapPoint* p : keyframe->map_points()) {
    if (p != nullptr) map_.UpdatePoint(p);
  }
  map_.UpdateConnections(keyframe);
}

void LocalMapper::RunLocalBundleAdjustment(KeyFrame* keyframe) {
  BundleAdjustmentProblem problem;
  std::vector<KeyFrame*> keyframes;    // problem index → keyframe
  std::vector<MapPoint*> points;       // problem index → point
  {
    std::shared_lock lock(map_.mutex());
    if (map_.NumKeyFrames(keyframe->map_id()) < 2) return;
    problem.camera = keyframe->keypoints().sensor().camera;
    std::unordered_map<const KeyFrame*, int> keyframe_index;
    const auto add_keyframe = [&](KeyFrame* k, bool fixed) {
      keyframe_index.emplace(k, static_cast<int>(keyframes.size()));
      keyframes.push_back(k);
      problem.T_cw.push_back(k->T_cw());
      // The first keyframe anchors the world frame and the scale of nothing else: it never moves.
      problem.pose_fixed.push_back(fixed || map_.IsOrigin(k) ? 1 : 0);
    };
    add_keyframe(keyframe, false);
    for (const auto& [neighbour, weight] : keyframe->covisibles()) {
      if (!neighbour->bad()) add_keyframe(neighbour, false);
    }
    const std::size_t local = keyframes.size();
    core::PointerSet<MapPoint> seen(local * keyframe->map_points().size());
    for (std::size_t k = 0; k < local; ++k) {
      for (MapPoint* p : keyframes[k]->map_points()) {
        if (p != nullptr && !p->bad() && seen.Insert(p)) points.push_back(p);
      }
    }
    // Keyframes outside the neighbourhood that see its points hold it in place.
    for (const MapPoint* p : points) {
      for (const MapPoint::Observation& o : p->observations()) {
        if (!o.keyframe->bad() && !keyframe_index.contains(o.keyframe)) add_keyframe(o.keyframe, true);
      }
    }
    if (std::none_of(problem.pose_fixed.begin(), problem.pose_fixed.end(), [](std::uint8_t f) { return f != 0; })) {
      problem.pose_fixed[local - 1] = 1;
    }
    for (std::size_t pi = 0; pi < points.size(); ++pi) {
      problem.points_w.push_back(points[pi]->position());
      for (const MapPoint::Observation& o : points[pi]->observations()) {
        const auto it = keyframe_index.find(o.keyframe);
        if (it == keyframe_index.end()) continue;
        problem.observations.push_back({it->second, static_cast<int>(pi), o.keyframe->keypoints().Measurement(o.index)});
      }
    }
  }

  const BundleAdjustmentResult result = RunBundleAdjustment(problem, options_.bundle_adjustment, &abort_bundle_adjustment_);

  std::unique_lock lock(map_.mutex());
  for (std::size_t e = 0; e < problem.observations.size(); ++e) {
    if (result.outlier[e] == 0) continue;
    const auto& o = problem.observations[e];
    MapPoint* point = points[static_cast<std::size_t>(o.point)];
    KeyFrame* observer = keyframes[static_cast<std::size_t>(o.keyframe)];
    if (!point->bad() && !observer->bad()) map_.EraseObservation(point, observer);
  }
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    if (problem.pose_fixed[k] == 0 && !keyframes[k]->bad()) keyframes[k]->SetPose(problem.T_cw[k]);
  }
  for (std::size_t pi = 0; pi < points.size(); ++pi) {
    if (points[pi]->bad()) continue;
    points[pi]->SetPosition(problem.points_w[pi]);
    map_.UpdatePoint(points[pi]);
  }
}

void LocalMapper::CullKeyFrames(KeyFrame* keyframe) {
  // A keyframe is redundant when nearly all of its close points are seen by at least three other keyframes at the
  // same or a finer scale.
  const std::vector<KeyFrame*> neighbours = keyframe->BestCovisibles(keyframe->covisibles().size());
  for (KeyFrame* candidate : neighbours) {
    if (candidate->bad() || map_.IsOrigin(candidate)) continue;
    const KeypointSet& keypoints = candidate->keypoints();
    int close_points = 0, redundant = 0;
    for (int i = 0; i < keypoints.size(); ++i) {
      const MapPoint* p = candidate->map_point(i);
      if (p == nullptr || p->bad()) continue;
      if (!keypoints.has_depth(i) || keypoints.depth(i) > keypoints.sensor().close_depth) continue;
      ++close_points;
      if (p->num_observations() <= 3) continue;
      int others = 0;
      for (const MapPoint::Observation& o : p->observations()) {
        if (o.keyframe == candidate) continue;
        if (o.keyframe->keypoints().level(o.index) <= keypoints.level(i) + 1 && ++others >= 3) break;
      }
      if (others >= 3) ++redundant;
    }
    if (close_points > 0 && redundant > options_.redundant_ratio * close_points) map_.EraseKeyFrame(candidate);
  }
}

}  // namespace hoidslam::slam
