#include "hoidslam/slam/track/frame_tracker.h"

#include <algorithm>
#include <map>
#include <unordered_set>

#include <spdlog/spdlog.h>

#include "hoidslam/core/option_checks.h"
#include "hoidslam/core/pointer_set.h"
#include "hoidslam/slam/match/matcher.h"

namespace hoidslam::slam {
namespace {

// The points of `keyframes` that the frame has not matched yet and that project into it at frame.T_cw, within
// their scale range and viewing angle: each once, in the keyframes' order.
std::vector<ProjectedPoint> PointsInView(const std::vector<KeyFrame*>& keyframes, const Frame& frame) {
  std::size_t slots = frame.map_points.size();
  for (const KeyFrame* keyframe : keyframes) slots += keyframe->map_points().size();
  core::PointerSet<MapPoint> considered(slots);
  for (const MapPoint* p : frame.map_points) considered.Insert(p);
  std::vector<ProjectedPoint> projected;
  const Sensor& sensor = frame.keypoints->sensor();
  for (const KeyFrame* keyframe : keyframes) {
    for (MapPoint* p : keyframe->map_points()) {
      if (p == nullptr || p->bad() || !considered.Insert(p)) continue;
      ProjectedPoint candidate;
      if (ProjectIntoFrame(*p, frame.T_cw, sensor, 0.5, candidate)) projected.push_back(candidate);
    }
  }
  return projected;
}

PoseHypothesis NoEstimate(TrackingMethod method, TrackingFailure failure) {
  PoseHypothesis hypothesis;
  hypothesis.method = method;
  hypothesis.failure = failure;
  return hypothesis;
}

// `frame` at the pose the motion model predicts from the last tracked frame, with no match yet.
Frame PredictedFrame(const Frame& frame, const TrackingContext& context) {
  Frame estimate = frame;
  estimate.T_cw = context.motion->Predict(context.last->T_cw, frame.timestamp - context.last->timestamp);
  ClearMatches(estimate);
  return estimate;
}

}  // namespace

void ClearMatches(Frame& frame) {
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  std::fill(frame.outlier.begin(), frame.outlier.end(), 0);
}

int CountMatches(const Frame& frame) {
  return static_cast<int>(std::count_if(frame.map_points.begin(), frame.map_points.end(),
                                        [](const MapPoint* p) { return p != nullptr; }));
}

void FrameTrackerOptions::Check() const {
  core::CheckPositive(motion_search_radius, "Tracking.motionSearchRadius");
  core::CheckPositive(local_search_radius, "Tracking.localSearchRadius");
  core::CheckPositive(provisional_search_radius, "Tracking.provisionalSearchRadius");
  core::CheckPositive(max_local_keyframes, "Tracking.maxLocalKeyFrames");
  core::CheckInRange(min_projection_matches, 4, 10000, "Tracking.minProjectionMatches");
  core::CheckInRange(min_descriptor_matches, 4, 10000, "Tracking.minDescriptorMatches");
  core::CheckInRange(min_first_estimate_inliers, 3, 10000, "Tracking.minFirstEstimateInliers");
  core::CheckShare(reference_descriptor_ratio, "Tracking.referenceDescriptorRatio");
  ransac.Check();
  pose_optimizer.Check();
}

FrameTracker::FrameTracker(const FrameTrackerOptions& options, const PoseAcceptanceOptions& acceptance)
    : options_(options), acceptance_(acceptance) {
  options_.Check();
  acceptance_.Check();
}

PoseHypothesis FrameTracker::WithMotionModel(const Frame& frame, const TrackingContext& context) const {
  const Frame& last = *context.last;
  const double elapsed = frame.timestamp - last.timestamp;
  Frame estimate = PredictedFrame(frame, context);
  // After frames were lost the prediction is rougher: the window grows with them, as far as the motion is scaled.
  const double radius = options_.motion_search_radius * std::max(1.0, context.motion->IntervalsAhead(elapsed));
  int matches = SearchByProjection(estimate, last, radius);
  if (matches < options_.min_projection_matches) {
    ClearMatches(estimate);
    matches = SearchByProjection(estimate, last, 2.0 * radius);
  }
  if (matches < options_.min_projection_matches) {
    return NoEstimate(TrackingMethod::kMotionModel, TrackingFailure::kTooFewMatches);
  }
  return FromFirstEstimate(std::move(estimate), matches, TrackingMethod::kMotionModel, context);
}

PoseHypothesis FrameTracker::FromReferenceKeyFrame(const Frame& frame, const TrackingContext& context) const {
  const KeyFrame* reference = context.reference_keyframe;
  if (reference == nullptr || reference->bad()) {
    return NoEstimate(TrackingMethod::kReferenceKeyFrame, TrackingFailure::kTooFewMatches);
  }
  Frame estimate = frame;
  ClearMatches(estimate);
  const int matches =
      SearchByDescriptor(*reference, estimate, estimate.map_points, options_.reference_descriptor_ratio);
  estimate.T_cw = context.last->T_cw;
  if (matches < options_.min_descriptor_matches) {
    return NoEstimate(TrackingMethod::kReferenceKeyFrame, TrackingFailure::kTooFewMatches);
  }
  return FromFirstEstimate(std::move(estimate), matches, TrackingMethod::kReferenceKeyFrame, context);
}

PoseHypothesis FrameTracker::FromPrediction(const Frame& frame, const TrackingContext& context) const {
  const Frame& last = *context.last;
  const double elapsed = frame.timestamp - last.timestamp;
  Frame estimate = PredictedFrame(frame, context);
  // Without a measured motion the camera may have gone anywhere near: the widest window.
  const double intervals =
      context.motion->measured() ? context.motion->IntervalsAhead(elapsed) : context.motion->max_extrapolation();
  // The last tracked frame kept few points (the crowd had already come), so the map around it is searched. Its
  // reference keyframe, made amid the crowd, may hold few. Most of them are hidden by the people: only close
  // descriptors are taken, and RANSAC keeps those that agree on a pose.
  KeyFrame* most_shared = nullptr;
  const std::vector<ProjectedPoint> projected = PointsInView(LocalKeyFrames(last, most_shared), estimate);
  const int matches = SearchByProjection(estimate, projected, options_.motion_search_radius * intervals,
                                         kDescriptorDistanceLow);
  if (matches < options_.min_first_estimate_inliers) {
    return NoEstimate(TrackingMethod::kMotionModel, TrackingFailure::kTooFewMatches);
  }
  const int consistent = EstimatePoseRansac(estimate, options_.ransac);
  spdlog::debug("frame {}: prediction after {:.2f} s: {} matches, {} consistent", frame.id, elapsed, matches,
                consistent);
  if (consistent < options_.min_first_estimate_inliers) {
    return NoEstimate(TrackingMethod::kMotionModel, TrackingFailure::kPoseRejected);
  }
  return FromFirstEstimate(std::move(estimate), consistent, TrackingMethod::kMotionModel, context);
}

PoseHypothesis FrameTracker::FromFirstEstimate(Frame estimate, int matches, TrackingMethod method,
                                               const TrackingContext& context) const {
  const int inliers = OptimizeFramePose(estimate, options_.pose_optimizer, true, context.prior);
  spdlog::debug("frame {}: {}: {} matches, {} inliers", estimate.id, ToString(method), matches, inliers);
  if (inliers < options_.min_first_estimate_inliers) return NoEstimate(method, TrackingFailure::kPoseRejected);
  return ConfirmWithLocalMap(std::move(estimate), method, context);
}

PoseHypothesis FrameTracker::ConfirmWithLocalMap(Frame estimate, TrackingMethod method,
                                                 const TrackingContext& context) const {
  PoseHypothesis hypothesis;
  hypothesis.method = method;
  const std::vector<KeyFrame*> local_keyframes = LocalKeyFrames(estimate, estimate.reference_keyframe);
  for (MapPoint* p : estimate.map_points) {
    if (p != nullptr && !p->bad()) hypothesis.visible.push_back(p);
  }
  const std::vector<ProjectedPoint> projected = PointsInView(local_keyframes, estimate);
  for (const ProjectedPoint& candidate : projected) hypothesis.visible.push_back(candidate.point);
  const double radius = context.provisional ? options_.provisional_search_radius : options_.local_search_radius;
  const int found = SearchByProjection(estimate, projected, radius);

  hypothesis.matched = CountMatches(estimate);
  hypothesis.inliers =
      OptimizeFramePose(estimate, options_.pose_optimizer, false, context.prior, &hypothesis.information);
  hypothesis.evidence = MeasureEvidence(estimate, hypothesis.matched, context.prior, acceptance_);
  hypothesis.evidence.provisional = context.provisional;
  hypothesis.verdict = JudgePose(hypothesis.evidence, acceptance_);
  spdlog::debug("frame {}: local map: {} keyframes, {} points in view, {} found; {} matched, {} inliers, "
                "clustering {:.2f}, motion χ² {:.1f}: {}",
                estimate.id, local_keyframes.size(), projected.size(), found, hypothesis.matched, hypothesis.inliers,
                hypothesis.evidence.outlier_clustering, hypothesis.evidence.motion_chi2.value_or(-1.0),
                hypothesis.verdict.accepted ? "accepted" : ToString(hypothesis.verdict.rejection));
  if (hypothesis.verdict.accepted) {
    hypothesis.failure = TrackingFailure::kNone;
  } else {
    hypothesis.failure = hypothesis.matched < std::min(acceptance_.min_inliers_floor, acceptance_.min_inliers)
                             ? TrackingFailure::kTooFewMatches
                             : TrackingFailure::kPoseRejected;
  }
  hypothesis.frame = std::move(estimate);
  return hypothesis;
}

std::vector<KeyFrame*> FrameTracker::LocalKeyFrames(const Frame& frame, KeyFrame*& most_shared) const {
  // Keyframes that see the frame's points, by how many; keyed by id so the order never depends on addresses.
  std::map<KeyFrameId, std::pair<KeyFrame*, int>> seen;
  for (const MapPoint* p : frame.map_points) {
    if (p == nullptr || p->bad()) continue;
    for (const MapPoint::Observation& o : p->observations()) {
      auto& entry = seen[o.keyframe->id()];
      entry.first = o.keyframe;
      ++entry.second;
    }
  }
  std::vector<KeyFrame*> local;
  std::unordered_set<const KeyFrame*> included;
  const auto include = [&](KeyFrame* keyframe) {
    if (keyframe == nullptr || keyframe->bad() || !included.insert(keyframe).second) return false;
    local.push_back(keyframe);
    return true;
  };
  int best = 0;
  for (const auto& [id, entry] : seen) {
    if (entry.first->bad()) continue;
    include(entry.first);
    if (entry.second > best) {
      best = entry.second;
      most_shared = entry.first;
    }
  }
  // Their neighbours: one strong covisible keyframe, one child and the parent of each.
  const std::size_t direct = local.size();
  const auto max_local = static_cast<std::size_t>(options_.max_local_keyframes);
  for (std::size_t k = 0; k < direct && local.size() < max_local; ++k) {
    for (KeyFrame* neighbour : local[k]->BestCovisibles(10)) {
      if (include(neighbour)) break;
    }
    for (KeyFrame* child : local[k]->children()) {
      if (include(child)) break;
    }
    include(local[k]->parent());
  }
  return local;
}

}  // namespace hoidslam::slam
