#include "hoidslam/slam/loop_closer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <random>
#include <shared_mutex>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "hoidslam/core/error.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/match/fusion.h"
#include "hoidslam/slam/match/matcher.h"

namespace hoidslam::slam {
namespace {

// A verification match: a map point of the recognised place (world coordinates, as the map has it) and where the
// keyframe measured it (its own camera coordinates).
struct PointPair {
  int keypoint = 0;
  Eigen::Vector3d p_w;
  Eigen::Vector3d p_c;
};

// ORB-SLAM's threshold for a point reprojected between the two ends of a loop (χ², 2 dof, 99 %).
constexpr double kChi2Loop = 9.21;

bool ReprojectsInto(const KeyFrame& keyframe, int i, const core::Pose& T_cw, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_c = T_cw * p_w;
  if (p_c.z() <= 0.0) return false;
  const KeypointMeasurement m = keyframe.keypoints().Measurement(i);
  const Eigen::Vector2d uv = keyframe.keypoints().sensor().camera.Project(p_c);
  return (uv - m.uv).squaredNorm() * m.inv_sigma2 <= kChi2Loop;
}

// The pose of the keyframe (world of the place to its camera) that most pairs agree with: RANSAC over rigid
// alignments of three pairs (Umeyama, no scale), a pair agreeing when the place's point reprojects onto the
// keyframe's keypoint and the keyframe's measurement onto the place's keypoint. Returns the agreeing pairs' indices.
std::vector<std::size_t> RigidRansac(const KeyFrame& keyframe, const KeyFrame& place, std::span<const PointPair> pairs,
                                     std::vector<MapPoint*> const& matches, int iterations, core::Pose& T_cw) {
  std::mt19937 rng(static_cast<std::uint32_t>(keyframe.id()));  // the same draws on every run
  std::uniform_int_distribution<std::size_t> pick(0, pairs.size() - 1);
  std::vector<std::size_t> best;
  for (int it = 0; it < iterations; ++it) {
    std::array<std::size_t, 3> sample{};
    sample[0] = pick(rng);
    do sample[1] = pick(rng); while (sample[1] == sample[0]);
    do sample[2] = pick(rng); while (sample[2] == sample[0] || sample[2] == sample[1]);
    Eigen::Matrix3d src, dst;
    for (int k = 0; k < 3; ++k) {
      src.col(k) = pairs[sample[static_cast<std::size_t>(k)]].p_w;
      dst.col(k) = pairs[sample[static_cast<std::size_t>(k)]].p_c;
    }
    const core::Pose T(Eigen::umeyama(src, dst, false));
    if (!T.matrix().allFinite()) continue;
    const core::Pose T_inv = T.inverse();
    std::vector<std::size_t> agreeing;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const PointPair& pair = pairs[k];
      const int j = matches[static_cast<std::size_t>(pair.keypoint)]->IndexIn(&place);
      if (j >= 0 && ReprojectsInto(keyframe, pair.keypoint, T, pair.p_w) &&
          ReprojectsInto(place, j, place.T_cw(), T_inv * pair.p_c)) {
        agreeing.push_back(k);
      }
    }
    if (agreeing.size() > best.size()) {
      best = std::move(agreeing);
      T_cw = T;
    }
  }
  return best;
}

}  // namespace

void FinalAdjustmentOptions::Check() const {
  if (!(depth_noise.factor > 0.0 && std::isfinite(depth_noise.factor))) {
    throw core::InputError::ForParameter("Depth.noiseFactor", fmt::format("must be > 0, got {}", depth_noise.factor));
  }
  if (huber_iterations < 1 || iterations < 0) {
    throw core::InputError::ForParameter(
        "FinalAdjustment.iterations",
        fmt::format("must be >= 1 with the Huber kernel and >= 0 after it, got {} and {}", huber_iterations,
                    iterations));
  }
}

void LoopClosingOptions::Check() const {
  const auto at_least = [](const char* name, int value, int minimum) {
    if (value < minimum) {
      throw core::InputError::ForParameter(name, fmt::format("must be >= {}, got {}", minimum, value));
    }
  };
  at_least("LoopClosing.minKeyFrames", min_keyframes, 1);
  at_least("LoopClosing.consistentKeyFrames", consistent_keyframes, 1);
  at_least("LoopClosing.minRansacInliers", min_ransac_inliers, 3);
  at_least("LoopClosing.minInliers", min_inliers, min_ransac_inliers);
  at_least("LoopClosing.ransacIterations", ransac_iterations, 1);
  if (!(max_drift_m >= 0.0 && max_drift_share >= 0.0 && max_drift_deg >= 0.0 && max_drift_deg_per_m >= 0.0)) {
    throw core::InputError::ForParameter("LoopClosing.maxDrift", "every drift limit must be >= 0");
  }
  at_least("LoopClosing.checkedNeighbours", checked_neighbours, 0);
  at_least("LoopClosing.confirmingNeighbours", confirming_neighbours, 0);
  if (confirming_neighbours > checked_neighbours) {
    throw core::InputError::ForParameter("LoopClosing.confirmingNeighbours",
                                         fmt::format("must be <= LoopClosing.checkedNeighbours ({}), got {}",
                                                     checked_neighbours, confirming_neighbours));
  }
  at_least("LoopClosing.globalIterations", global_iterations, 1);
  at_least("LoopClosing.essentialGraphIterations", essential_graph.iterations, 1);
  at_least("LoopClosing.essentialGraphMinWeight", essential_graph_min_weight, 1);
  if (!(max_neighbour_disagreement_m > 0.0) || !(max_neighbour_disagreement_deg > 0.0)) {
    throw core::InputError::ForParameter("LoopClosing.maxNeighbourDisagreement",
                                         fmt::format("must be > 0, got {} m and {}°", max_neighbour_disagreement_m,
                                                     max_neighbour_disagreement_deg));
  }
  if (!(projection_radius > 0.0)) {
    throw core::InputError::ForParameter("LoopClosing.projectionRadius",
                                         fmt::format("must be > 0, got {}", projection_radius));
  }
}

LoopCloser::LoopCloser(Map& map, LocalMapper& local_mapper, const LoopClosingOptions& options)
    : map_(map), local_mapper_(local_mapper), options_(options) {
  options_.Check();
}

LoopCloser::~LoopCloser() { Stop(); }

void LoopCloser::Insert(KeyFrame* keyframe) {
  {
    std::lock_guard lock(queue_mutex_);
    queue_.push_back(keyframe);
  }
  queue_changed_.notify_all();
}

KeyFrame* LoopCloser::NextKeyFrame() {
  std::lock_guard lock(queue_mutex_);
  if (queue_.empty()) return nullptr;
  KeyFrame* keyframe = queue_.front();
  queue_.pop_front();
  return keyframe;
}

void LoopCloser::ProcessQueue() {
  while (KeyFrame* keyframe = NextKeyFrame()) Process(keyframe);
}

void LoopCloser::Start() {
  if (thread_.joinable()) return;
  threaded_ = true;
  thread_ = std::jthread([this](std::stop_token stop) { Loop(stop); });
}

void LoopCloser::Stop() {
  if (thread_.joinable()) {
    thread_.request_stop();
    queue_changed_.notify_all();
    thread_.join();
  }
  if (global_thread_.joinable()) global_thread_.join();  // the map it refines is the final one
  threaded_ = false;
}

void LoopCloser::Loop(std::stop_token stop) {
  for (;;) {
    {
      std::unique_lock lock(queue_mutex_);
      queue_changed_.wait(lock, stop, [this] { return !queue_.empty(); });
      if (queue_.empty()) return;  // stop requested and nothing left to do
    }
    ProcessQueue();
  }
}

std::vector<LoopClosure> LoopCloser::closures() const {
  std::lock_guard lock(closures_mutex_);
  return closures_;
}

LoopCloser::Timings LoopCloser::timings() const {
  std::lock_guard lock(closures_mutex_);
  return timings_;
}

void LoopCloser::Process(KeyFrame* keyframe) {
  VerifiedLoop loop;
  {
    std::shared_lock lock(map_.mutex());
    if (keyframe->bad()) return;
    const auto min_keyframes = static_cast<KeyFrameId>(options_.min_keyframes);
    const bool loops = options_.enabled && map_.NumKeyFrames(keyframe->map_id()) >= min_keyframes &&
                       !(last_loop_keyframe_id_ && keyframe->id() < *last_loop_keyframe_id_ + min_keyframes);
    const bool merges = options_.merge_maps && map_.Maps().size() > 1;
    if (!loops && !merges) return;
    core::Stopwatch watch;
    const std::vector<KeyFrame*> candidates = ConsistentCandidates(keyframe, loops, merges);
    std::vector<double> detection_ms = {watch.ElapsedMilliseconds()}, verification_ms;
    for (KeyFrame* candidate : candidates) {
      watch.Restart();
      const bool verified = Verify(keyframe, candidate, loop);
      verification_ms.push_back(watch.ElapsedMilliseconds());
      if (verified) break;
    }
    std::lock_guard timings_lock(closures_mutex_);
    timings_.detection_ms.insert(timings_.detection_ms.end(), detection_ms.begin(), detection_ms.end());
    timings_.verification_ms.insert(timings_.verification_ms.end(), verification_ms.begin(), verification_ms.end());
  }
  if (loop.loop == nullptr) return;
  StopGlobalBundleAdjustment();  // it refines a map about to change
  // (Map ids change only under the exclusive lock, which only this thread takes to merge.)
  if (loop.loop->map_id() == keyframe->map_id()) {
    Correct(keyframe, loop);
  } else {
    Merge(keyframe, loop);
  }
  if (options_.enabled && options_.global_bundle_adjustment) StartGlobalBundleAdjustment(loop.loop->map_id());
}

std::unique_lock<std::shared_mutex> LoopCloser::LockStillMap() {
  std::unique_lock lock(map_.mutex());
  // A keyframe tracking made just before the pause: let local mapping connect it first.
  while (!local_mapper_.Idle()) {
    lock.unlock();
    local_mapper_.WaitUntilIdle();
    lock.lock();
  }
  return lock;
}

void LoopCloser::StartGlobalBundleAdjustment(MapId map) {
  abort_global_ = false;
  BundleAdjustmentOptions adjustment;
  adjustment.first_iterations = options_.global_iterations;
  adjustment.second_iterations = 0;  // its outliers are left in the map: local mapping judges them
  adjustment.sparse = true;
  if (threaded_) {
    global_thread_ = std::jthread([this, map, adjustment] { RunGlobalBundleAdjustment(map, adjustment); });
  } else {
    RunGlobalBundleAdjustment(map, adjustment);
  }
}

void LoopCloser::AdjustFinally(MapId map, const FinalAdjustmentOptions& options) {
  StopGlobalBundleAdjustment();
  abort_global_ = false;
  BundleAdjustmentOptions adjustment;
  adjustment.first_iterations = options.huber_iterations;
  adjustment.second_iterations = options.iterations;
  adjustment.sparse = true;
  RunGlobalBundleAdjustment(map, adjustment, &options.depth_noise);
}

void LoopCloser::StopGlobalBundleAdjustment() {
  if (!global_thread_.joinable()) return;
  abort_global_ = true;
  global_thread_.join();
}

void LoopCloser::RunGlobalBundleAdjustment(MapId map, const BundleAdjustmentOptions& adjustment,
                                           const core::DepthNoiseModel* depth_noise) {
  BundleAdjustmentProblem problem;
  std::vector<KeyFrame*> keyframes;
  std::vector<MapPoint*> points;
  std::unordered_map<const KeyFrame*, std::size_t> keyframe_index;
  {
    std::shared_lock lock(map_.mutex());
    keyframes = map_.KeyFrames(map);
    if (keyframes.size() < 2) return;
    problem.camera = keyframes.front()->keypoints().sensor().camera;
    for (KeyFrame* k : keyframes) {
      keyframe_index.emplace(k, problem.T_cw.size());
      problem.T_cw.push_back(k->T_cw());
      problem.pose_fixed.push_back(map_.IsOrigin(k) ? 1 : 0);
    }
    for (MapPoint* p : map_.MapPoints(map)) {
      // A point one keyframe sees tells the adjustment nothing (it moves with that keyframe, below), and leaving
      // it out keeps the problem small.
      if (p->observations().size() < 2) continue;
      const int index = static_cast<int>(points.size());
      for (const MapPoint::Observation& o : p->observations()) {
        const auto k = keyframe_index.find(o.keyframe);
        if (k == keyframe_index.end()) continue;
        problem.observations.push_back(
            {static_cast<int>(k->second), index, o.keyframe->keypoints().Measurement(o.index)});
      }
      points.push_back(p);
      problem.points_w.push_back(p->position());
    }
  }
  if (depth_noise != nullptr) {
    for (BundleAdjustmentProblem::Observation& o : problem.observations) {
      KeypointMeasurement& m = o.measurement;
      if (!m.has_depth) continue;
      const double depth = problem.camera.bf / (m.uv.x() - m.ur);  // ur = u − bf / z
      m.disparity_information = depth_noise->DisparityInformation(problem.camera.bf, depth);
    }
  }
  if (RunBundleAdjustment(problem, adjustment, &abort_global_).aborted) return;

  const LocalMapper::PauseGuard pause = local_mapper_.Pause();
  const std::unique_lock lock = LockStillMap();
  // Each keyframe's pose before and after; keyframes made since the copy move with their parent (an older one).
  std::unordered_map<const KeyFrame*, std::pair<core::Pose, core::Pose>> moved;
  for (KeyFrame* k : map_.KeyFrames(map)) {
    const auto index = keyframe_index.find(k);
    if (index != keyframe_index.end()) {
      moved.emplace(k, std::pair(k->T_cw(), problem.T_cw[index->second]));
    } else if (const auto parent = moved.find(k->parent()); parent != moved.end()) {
      const auto& [parent_before, parent_after] = parent->second;
      moved.emplace(k, std::pair(k->T_cw(), k->T_cw() * parent_before.inverse() * parent_after));
    }
  }
  // Points take their adjusted positions; points left out, or made since, move with their reference keyframe.
  std::unordered_map<const MapPoint*, std::size_t> point_index;
  for (std::size_t i = 0; i < points.size(); ++i) point_index.emplace(points[i], i);
  for (MapPoint* p : map_.MapPoints(map)) {
    if (const auto index = point_index.find(p); index != point_index.end()) {
      p->SetPosition(problem.points_w[index->second]);
    } else if (const auto reference = moved.find(p->reference_keyframe()); reference != moved.end()) {
      const auto& [before, after] = reference->second;
      p->SetPosition(after.inverse() * (before * p->position()));
    }
  }
  for (KeyFrame* k : map_.KeyFrames(map)) {
    if (const auto m = moved.find(k); m != moved.end()) k->SetPose(m->second.second);
  }
  for (MapPoint* p : map_.MapPoints(map)) map_.UpdatePoint(p);
  ++global_adjustments_;
  spdlog::debug("global bundle adjustment: {} keyframes, {} points", keyframes.size(), points.size());
}

std::vector<KeyFrame*> LoopCloser::ConsistentCandidates(KeyFrame* keyframe, bool loops, bool merges) {
  // A candidate must look at least as much like the keyframe as the keyframe's least similar neighbour does.
  double min_score = 1.0;
  for (const auto& [neighbour, weight] : keyframe->covisibles()) {
    if (!neighbour->bad()) min_score = std::min(min_score, bow::Score(keyframe->words().bow, neighbour->words().bow));
  }
  std::vector<KeyFrame*> candidates;
  if (loops) candidates = map_.database().LoopCandidates(*keyframe, min_score);
  if (merges) {
    const std::vector<KeyFrame*> other_maps = map_.database().MergeCandidates(*keyframe, min_score);
    candidates.insert(candidates.end(), other_maps.begin(), other_maps.end());
  }

  // Each candidate's place (it and its neighbours) continues a place the previous keyframe saw, or starts anew.
  std::vector<ConsistentGroup> groups;
  std::vector<KeyFrame*> consistent;
  for (KeyFrame* candidate : candidates) {
    ConsistentGroup group;
    group.keyframes.insert(candidate);
    for (const auto& [neighbour, weight] : candidate->covisibles()) group.keyframes.insert(neighbour);
    int consistency = 1;
    for (std::size_t g = 0; g < consistent_groups_.size(); ++g) {
      const std::set<const KeyFrame*>& previous = consistent_groups_[g].keyframes;
      if (std::none_of(group.keyframes.begin(), group.keyframes.end(),
                       [&](const KeyFrame* k) { return previous.contains(k); })) {
        continue;
      }
      consistency = std::max(consistency, consistent_groups_[g].consistency + 1);
    }
    group.consistency = consistency;
    if (consistency >= options_.consistent_keyframes) consistent.push_back(candidate);
    groups.push_back(std::move(group));
  }
  consistent_groups_ = std::move(groups);
  return consistent;
}

bool LoopCloser::Verify(KeyFrame* keyframe, KeyFrame* candidate, VerifiedLoop& loop) const {
  Frame probe(keyframe->frame_id(), keyframe->timestamp(), keyframe->shared_keypoints());
  probe.T_cw = keyframe->T_cw();
  std::vector<MapPoint*> matches;
  if (SearchByBoW(*candidate, probe, keyframe->words().features, matches, 0.75F) < options_.min_ransac_inliers) {
    return false;
  }

  // The keyframe's side of each match in its own camera: measured by depth, or its own map point.
  const KeypointSet& keypoints = keyframe->keypoints();
  std::vector<PointPair> pairs;
  for (int i = 0; i < keypoints.size(); ++i) {
    const MapPoint* p = matches[static_cast<std::size_t>(i)];
    if (p == nullptr || p->bad()) continue;
    const MapPoint* own = keyframe->map_point(i);
    if (keypoints.has_depth(i)) {
      pairs.push_back({i, p->position(), keypoints.Unproject(i)});
    } else if (own != nullptr && !own->bad()) {
      pairs.push_back({i, p->position(), keyframe->T_cw() * own->position()});
    }
  }
  if (std::ssize(pairs) < options_.min_ransac_inliers) return false;
  core::Pose T_cw = core::Pose::Identity();
  const std::vector<std::size_t> agreeing =
      RigidRansac(*keyframe, *candidate, pairs, matches, options_.ransac_iterations, T_cw);
  spdlog::debug("loop: keyframe {} (frame {}) and keyframe {} (frame {}): {} matches, {} agree on one SE(3)",
                keyframe->id(), keyframe->frame_id(), candidate->id(), candidate->frame_id(), pairs.size(),
                agreeing.size());
  if (std::ssize(agreeing) < options_.min_ransac_inliers) return false;

  // The pose refined on the agreeing matches, then on the place's whole neighbourhood projected with it.
  for (const std::size_t k : agreeing) {
    const auto i = static_cast<std::size_t>(pairs[k].keypoint);
    probe.map_points[i] = matches[i];
  }
  probe.T_cw = T_cw;
  if (OptimizeFramePose(probe, PoseOptimizerOptions{}, true) < options_.min_ransac_inliers) return false;
  std::unordered_set<const MapPoint*> matched(probe.map_points.begin(), probe.map_points.end());
  std::vector<ProjectedPoint> projected;
  const auto project = [&](const KeyFrame* k) {
    for (MapPoint* p : k->map_points()) {
      ProjectedPoint point;
      if (p != nullptr && !p->bad() && matched.insert(p).second &&
          ProjectIntoFrame(*p, probe.T_cw, keypoints.sensor(), 0.5, point)) {
        projected.push_back(point);
      }
    }
  };
  project(candidate);
  for (const auto& [neighbour, weight] : candidate->covisibles()) {
    if (!neighbour->bad()) project(neighbour);
  }
  SearchByProjection(probe, projected, options_.projection_radius, kDescriptorDistanceLow);
  const int inliers = OptimizeFramePose(probe, PoseOptimizerOptions{}, true);
  spdlog::debug("loop: keyframe {} and keyframe {}: {} inliers with the place's neighbourhood", keyframe->id(),
                candidate->id(), inliers);
  if (inliers < options_.min_inliers) return false;

  // The correction must be one the drift since the place could have made: a texture met twice elsewhere puts the
  // keyframe where the other copy is. (Between two maps there is no drift to compare with.)
  if (candidate->map_id() == keyframe->map_id()) {
    double path = 0.0;
    const KeyFrame* previous = nullptr;
    for (const KeyFrame* k : map_.KeyFrames(keyframe->map_id())) {
      if (k->id() < candidate->id() || k->id() > keyframe->id()) continue;
      if (previous != nullptr) path += (k->center() - previous->center()).norm();
      previous = k;
    }
    const core::Pose correction = probe.T_cw * keyframe->T_wc();
    const double correction_m = correction.inverse().translation().norm();
    const double correction_deg = core::RotationAngleDegrees(correction.linear());
    if (correction_m > options_.max_drift_m + options_.max_drift_share * path ||
        correction_deg > options_.max_drift_deg + options_.max_drift_deg_per_m * path) {
      spdlog::debug("loop: keyframe {} and keyframe {}: a correction of {:.3f} m and {:.2f}° after {:.2f} m of path "
                    "is more than drift", keyframe->id(), candidate->id(), correction_m, correction_deg, path);
      return false;
    }
  }

  // A place that only looks like the one seen (a texture met twice) fits one view; the keyframe's neighbours, moved
  // with it, must find the place too, where the loop puts them.
  int confirming = 0;
  const std::vector<KeyFrame*> neighbours = keyframe->BestCovisibles(static_cast<std::size_t>(options_.checked_neighbours));
  for (KeyFrame* neighbour : neighbours) {
    Frame view(neighbour->frame_id(), neighbour->timestamp(), neighbour->shared_keypoints());
    const core::Pose T_cw_moved = neighbour->T_cw() * keyframe->T_wc() * probe.T_cw;
    view.T_cw = T_cw_moved;
    std::vector<ProjectedPoint> visible;
    for (const ProjectedPoint& p : projected) {
      ProjectedPoint point;
      if (ProjectIntoFrame(*p.point, view.T_cw, keypoints.sensor(), 0.5, point)) visible.push_back(point);
    }
    for (const MapPoint* p : probe.map_points) {
      ProjectedPoint point;
      if (p != nullptr && ProjectIntoFrame(*p, view.T_cw, keypoints.sensor(), 0.5, point)) visible.push_back(point);
    }
    SearchByProjection(view, visible, options_.projection_radius, kDescriptorDistanceLow);
    const int found = OptimizeFramePose(view, PoseOptimizerOptions{}, true);
    const core::Pose disagreement = view.T_cw * T_cw_moved.inverse();
    const bool agrees = found >= options_.min_ransac_inliers &&
                        disagreement.translation().norm() <= options_.max_neighbour_disagreement_m &&
                        core::RotationAngleDegrees(disagreement.linear()) <= options_.max_neighbour_disagreement_deg;
    spdlog::debug("loop: keyframe {} and keyframe {}: neighbour {} finds the place with {} inliers, {:.3f} m off: {}",
                  keyframe->id(), candidate->id(), neighbour->id(), found, disagreement.translation().norm(),
                  agrees ? "agrees" : "disagrees");
    if (agrees) ++confirming;
  }
  if (confirming < std::min<int>(options_.confirming_neighbours, static_cast<int>(neighbours.size()))) return false;
  loop = {candidate, probe.T_cw, std::move(probe.map_points), inliers};
  return true;
}

void LoopCloser::Correct(KeyFrame* keyframe, const VerifiedLoop& loop) {
  const LocalMapper::PauseGuard pause = local_mapper_.Pause();
  std::unique_lock lock = LockStillMap();
  KeyFrame* place = loop.loop;
  if (keyframe->bad() || place->bad()) return;
  const core::Pose T_cw_before = keyframe->T_cw();

  // The keyframe's neighbourhood moves with it to where the loop puts it, its points with them.
  const std::vector<KeyFrame*> connected = Neighbourhood(keyframe);
  std::unordered_map<const KeyFrame*, core::Pose> uncorrected;  // their poses before, for the essential graph
  std::unordered_map<const MapPoint*, const KeyFrame*> corrected_by;
  for (KeyFrame* k : connected) uncorrected.emplace(k, k->T_cw());
  for (KeyFrame* k : connected) {
    const core::Pose T_cw = (k->T_cw() * keyframe->T_wc()) * loop.T_cw;
    const core::Pose move = T_cw.inverse() * k->T_cw();  // old world → new world, as this keyframe sees it
    for (MapPoint* p : k->map_points()) {
      if (p == nullptr || p->bad() || !corrected_by.emplace(p, k).second) continue;
      p->SetPosition(move * p->position());
    }
    k->SetPose(T_cw);
  }
  for (KeyFrame* k : connected) {
    for (MapPoint* p : k->map_points()) {
      if (p != nullptr && !p->bad()) map_.UpdatePoint(p);
    }
  }

  const std::vector<std::pair<KeyFrame*, KeyFrame*>> loop_connections = Join(keyframe, connected, loop);

  // The essential graph: the spanning tree, earlier loops and strong covisibility as they were measured (the
  // neighbourhood's poses before this correction), and the new connections across the loop as they are now.
  PoseGraphProblem problem;
  const MapId map = keyframe->map_id();
  const std::vector<KeyFrame*> keyframes = map_.KeyFrames(map);
  std::unordered_map<const KeyFrame*, int> index;
  for (KeyFrame* k : keyframes) {
    index.emplace(k, static_cast<int>(problem.T_cw.size()));
    problem.T_cw.push_back(k->T_cw());
    problem.pose_fixed.push_back(k == place || map_.IsOrigin(k) ? 1 : 0);
  }
  const auto measured = [&](const KeyFrame* k) {
    const auto it = uncorrected.find(k);
    return it != uncorrected.end() ? it->second : k->T_cw();
  };
  std::set<std::pair<int, int>> joined;
  const auto add_edge = [&](const KeyFrame* a, const KeyFrame* b, const core::Pose& T_a_b) {
    const auto ia = index.find(a), ib = index.find(b);
    if (ia == index.end() || ib == index.end() || ia->second == ib->second) return;
    if (!joined.emplace(std::minmax(ia->second, ib->second)).second) return;
    problem.edges.push_back({ia->second, ib->second, T_a_b});
  };
  for (const auto& [a, b] : loop_connections) add_edge(a, b, a->T_cw() * b->T_wc());
  for (const KeyFrame* k : keyframes) {
    if (k->parent() != nullptr) add_edge(k, k->parent(), measured(k) * measured(k->parent()).inverse());
    for (const KeyFrame* other : k->loop_edges()) add_edge(k, other, measured(k) * measured(other).inverse());
    for (const auto& [neighbour, weight] : k->covisibles()) {
      if (weight >= options_.essential_graph_min_weight) {
        add_edge(k, neighbour, measured(k) * measured(neighbour).inverse());
      }
    }
  }
  std::vector<core::Pose> T_cw_before_graph = problem.T_cw;
  lock.unlock();

  // Tracking goes on meanwhile (it makes no keyframe): the graph needs no lock.
  OptimizePoseGraph(problem, options_.essential_graph);

  lock.lock();
  // Each point moves with the keyframe that placed it: the one that corrected it above, or its reference.
  const std::vector<MapPoint*> points = map_.MapPoints(map);
  for (MapPoint* p : points) {
    const auto by = corrected_by.find(p);
    const KeyFrame* reference = by != corrected_by.end() ? by->second : p->reference_keyframe();
    auto it = reference != nullptr ? index.find(reference) : index.end();
    for (auto o = p->observations().begin(); it == index.end() && o != p->observations().end(); ++o) {
      it = index.find(o->keyframe);
    }
    if (it == index.end()) continue;
    const auto k = static_cast<std::size_t>(it->second);
    p->SetPosition(problem.T_cw[k].inverse() * (T_cw_before_graph[k] * p->position()));
  }
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    if (!keyframes[k]->bad()) keyframes[k]->SetPose(problem.T_cw[k]);
  }
  for (MapPoint* p : points) map_.UpdatePoint(p);
  map_.AddLoopEdge(keyframe, place);
  last_loop_keyframe_id_ = keyframe->id();
  Record(keyframe, loop, T_cw_before, std::nullopt);
}

void LoopCloser::Merge(KeyFrame* keyframe, const VerifiedLoop& loop) {
  const LocalMapper::PauseGuard pause = local_mapper_.Pause();
  const std::unique_lock lock = LockStillMap();
  KeyFrame* place = loop.loop;
  if (keyframe->bad() || place->bad() || keyframe->map_id() == place->map_id()) return;
  const MapId from = keyframe->map_id();
  const core::Pose T_cw_before = keyframe->T_cw();
  // The whole map moves rigidly to where the keyframe's verified pose puts it in the place's map: an RGB-D map has
  // its scale, and what it drifted since it started is left to local mapping and the next loop.
  map_.MergeMaps(from, place->map_id(), loop.T_cw.inverse() * keyframe->T_cw());
  const std::vector<KeyFrame*> connected = Neighbourhood(keyframe);
  Join(keyframe, connected, loop);
  map_.AddLoopEdge(keyframe, place);
  Record(keyframe, loop, T_cw_before, from);
}

std::vector<KeyFrame*> LoopCloser::Neighbourhood(KeyFrame* keyframe) {
  map_.UpdateConnections(keyframe);
  std::vector<KeyFrame*> connected = {keyframe};
  for (const auto& [neighbour, weight] : keyframe->covisibles()) {
    if (!neighbour->bad()) connected.push_back(neighbour);
  }
  return connected;
}

std::vector<std::pair<KeyFrame*, KeyFrame*>> LoopCloser::Join(KeyFrame* keyframe,
                                                               const std::vector<KeyFrame*>& connected,
                                                               const VerifiedLoop& loop) {
  const KeyFrame* place = loop.loop;
  const KeypointSet& keypoints = keyframe->keypoints();
  for (int i = 0; i < keypoints.size(); ++i) {
    MapPoint* point = loop.matches[static_cast<std::size_t>(i)];
    if (point == nullptr || point->bad()) continue;
    MapPoint* existing = keyframe->map_point(i);
    if (existing == point) continue;
    if (existing != nullptr && !existing->bad()) {
      map_.ReplacePoint(existing, point);
    } else {
      map_.AddObservation(point, keyframe, i);
    }
    map_.UpdatePoint(point);
  }
  std::vector<MapPoint*> place_points;
  std::unordered_set<const MapPoint*> seen;
  const auto collect = [&](const KeyFrame* k) {
    for (MapPoint* p : k->map_points()) {
      if (p != nullptr && !p->bad() && seen.insert(p).second) place_points.push_back(p);
    }
  };
  collect(place);
  for (const auto& [neighbour, weight] : place->covisibles()) {
    if (!neighbour->bad()) collect(neighbour);
  }
  std::unordered_map<const KeyFrame*, std::unordered_set<const KeyFrame*>> neighbours_before;
  for (KeyFrame* k : connected) {
    auto& before = neighbours_before[k];
    for (const auto& [neighbour, weight] : k->covisibles()) before.insert(neighbour);
    FuseByProjection(map_, k, place_points, 4.0);
  }
  // The edges the fusion made across the loop.
  const std::unordered_set<const KeyFrame*> connected_set(connected.begin(), connected.end());
  std::vector<std::pair<KeyFrame*, KeyFrame*>> loop_connections;
  for (KeyFrame* k : connected) {
    map_.UpdateConnections(k);
    for (const auto& [neighbour, weight] : k->covisibles()) {
      if (!neighbour->bad() && !connected_set.contains(neighbour) && !neighbours_before[k].contains(neighbour)) {
        loop_connections.emplace_back(k, neighbour);
      }
    }
  }
  return loop_connections;
}

void LoopCloser::Record(const KeyFrame* keyframe, const VerifiedLoop& loop, const core::Pose& T_cw_before,
                        std::optional<MapId> merged_map) {
  const KeyFrame* place = loop.loop;
  LoopClosure closure;
  closure.frame_id = keyframe->frame_id();
  closure.timestamp = keyframe->timestamp();
  closure.loop_frame_id = place->frame_id();
  closure.loop_timestamp = place->timestamp();
  closure.T_loop_current = place->T_cw() * keyframe->T_wc();
  closure.inliers = loop.inliers;
  closure.map = place->map_id();
  closure.merged_map = merged_map;
  if (!merged_map) {
    const core::Pose moved = keyframe->T_cw() * T_cw_before.inverse();
    closure.correction_m = (keyframe->center() - T_cw_before.inverse().translation()).norm();
    closure.correction_deg = core::RotationAngleDegrees(moved.linear());
  }
  spdlog::debug("{}: keyframe {} (frame {}) with keyframe {} (frame {}), {} inliers, corrected {:.3f} m {:.2f}°",
                merged_map ? fmt::format("map {} merged into map {}", *merged_map, closure.map) : "loop closed",
                keyframe->id(), keyframe->frame_id(), place->id(), place->frame_id(), loop.inliers,
                closure.correction_m, closure.correction_deg);
  std::lock_guard closures_lock(closures_mutex_);
  closures_.push_back(closure);
}

}  // namespace hoidslam::slam
