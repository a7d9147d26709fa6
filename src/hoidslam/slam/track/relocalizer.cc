#include "hoidslam/slam/track/relocalizer.h"

#include <algorithm>
#include <unordered_set>

#include <spdlog/spdlog.h>

#include "hoidslam/core/option_checks.h"
#include "hoidslam/slam/match/matcher.h"
#include "hoidslam/slam/track/pnp_ransac.h"

namespace hoidslam::slam {

void RelocalizationOptions::Check() const {
  core::CheckPositive(candidates, "Tracking.relocalizationCandidates");
  core::CheckNotNegative(reference_neighbours, "Tracking.relocalizationReferenceNeighbours");
  core::CheckShare(descriptor_ratio, "Tracking.relocalizationDescriptorRatio");
  core::CheckPositive(projection_radius, "Tracking.relocalizationProjectionRadius");
  core::CheckPositive(min_inliers, "Tracking.minInliersAfterRelocalization");
  core::CheckInRange(max_poses, 1, 100, "Tracking.relocalizationMaxPoses");
  core::CheckInRange(max_tries, 1, 1000, "Tracking.relocalizationMaxTries");
  core::CheckPositive(ambiguous_distance, "Tracking.relocalizationAmbiguousDistance");
  core::CheckPositive(ambiguous_angle_deg, "Tracking.relocalizationAmbiguousAngle");
  core::CheckShare(ambiguous_share, "Tracking.relocalizationAmbiguousShare");
}

Relocalizer::Relocalizer(const Map& map, const RelocalizationOptions& options, const FrameTrackerOptions& tracking)
    : map_(map), options_(options), tracking_(tracking) {
  options_.Check();
  tracking_.Check();
}

std::vector<KeyFrame*> Relocalizer::Candidates(const bow::ImageWords& words, KeyFrame* reference,
                                               std::optional<MapId> map) const {
  std::vector<KeyFrame*> candidates;
  std::unordered_set<const KeyFrame*> included;
  const auto consider = [&](KeyFrame* keyframe) {
    if (keyframe != nullptr && !keyframe->bad() && included.insert(keyframe).second) candidates.push_back(keyframe);
  };
  if (reference != nullptr) {
    consider(reference);
    for (KeyFrame* neighbour : reference->BestCovisibles(static_cast<std::size_t>(options_.reference_neighbours))) {
      consider(neighbour);
    }
  }
  for (KeyFrame* keyframe : map_.database().RelocalizationCandidates(
           words.bow, static_cast<std::size_t>(options_.candidates), map)) {
    consider(keyframe);
  }
  return candidates;
}

std::vector<std::pair<int, std::size_t>> Relocalizer::RankByMatches(const Frame& frame, const bow::ImageWords& words,
                                                                    const std::vector<KeyFrame*>& candidates,
                                                                    std::vector<std::vector<MapPoint*>>& matches) const {
  matches.assign(candidates.size(), {});
  std::vector<std::pair<int, std::size_t>> ranked;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    // Guided by the vocabulary's tree; a keyframe local mapping has not described yet, by every descriptor.
    const KeyFrame& candidate = *candidates[c];
    const int count = candidate.words().features.empty()
                          ? SearchByDescriptor(candidate, frame, matches[c], options_.descriptor_ratio)
                          : SearchByBoW(candidate, frame, words.features, matches[c], options_.descriptor_ratio);
    if (count >= tracking_.min_descriptor_matches) ranked.emplace_back(count, c);
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  return ranked;
}

std::optional<RelocalizedPose> Relocalizer::TryCandidate(const Frame& frame, KeyFrame& candidate,
                                                        std::vector<MapPoint*> matches) const {
  Frame estimate = frame;
  ClearMatches(estimate);
  estimate.map_points = std::move(matches);
  const int consistent = EstimatePoseRansac(estimate, tracking_.ransac);
  if (consistent < tracking_.min_first_estimate_inliers) return std::nullopt;
  int good = OptimizeFramePose(estimate, tracking_.pose_optimizer, true);
  if (good < tracking_.min_first_estimate_inliers) return std::nullopt;
  if (good < options_.min_inliers) {
    // More matches from the candidate's points projected with the estimate.
    std::vector<ProjectedPoint> projected;
    for (MapPoint* p : candidate.map_points()) {
      ProjectedPoint candidate_point;
      if (p != nullptr && !p->bad() &&
          std::find(estimate.map_points.begin(), estimate.map_points.end(), p) == estimate.map_points.end() &&
          ProjectIntoFrame(*p, estimate.T_cw, estimate.keypoints->sensor(), 0.0, candidate_point)) {
        projected.push_back(candidate_point);
      }
    }
    SearchByProjection(estimate, projected, options_.projection_radius);
    good = OptimizeFramePose(estimate, tracking_.pose_optimizer, true);
  }
  spdlog::debug("frame {}: relocalisation candidate keyframe {}: {} PnP inliers, {} after optimisation", frame.id,
                candidate.id(), consistent, good);
  if (good < options_.min_inliers) return std::nullopt;
  estimate.reference_keyframe = &candidate;
  return RelocalizedPose{std::move(estimate), good};
}

std::vector<RelocalizedPose> Relocalizer::Relocalize(const Frame& frame, const bow::ImageWords& words,
                                                     const std::vector<KeyFrame*>& candidates,
                                                     TrackingFailure& failure) const {
  failure = TrackingFailure::kTooFewMatches;
  std::vector<RelocalizedPose> poses;
  if (frame.size() < tracking_.min_descriptor_matches || candidates.empty()) return poses;
  std::vector<std::vector<MapPoint*>> matches;
  int tries = 0;
  for (const auto& [count, c] : RankByMatches(frame, words, candidates, matches)) {
    if (tries++ >= options_.max_tries || static_cast<int>(poses.size()) >= options_.max_poses) break;
    spdlog::debug("frame {}: relocalisation candidate keyframe {}: {} matches", frame.id, candidates[c]->id(), count);
    failure = TrackingFailure::kPoseRejected;
    std::optional<RelocalizedPose> found = TryCandidate(frame, *candidates[c], std::move(matches[c]));
    if (!found) continue;
    // Two candidates of one place give one pose: the better backed is kept.
    const auto same = std::find_if(poses.begin(), poses.end(),
                                   [&](const RelocalizedPose& p) { return SamePlace(p, *found); });
    if (same == poses.end()) {
      poses.push_back(std::move(*found));
    } else if (found->inliers > same->inliers) {
      *same = std::move(*found);
    }
  }
  std::stable_sort(poses.begin(), poses.end(),
                   [](const RelocalizedPose& a, const RelocalizedPose& b) { return a.inliers > b.inliers; });
  if (!poses.empty()) failure = TrackingFailure::kNone;
  return poses;
}

bool Relocalizer::Ambiguous(const RelocalizedPose& best, const RelocalizedPose& other) const {
  return !SamePlace(best, other) && other.inliers >= options_.ambiguous_share * best.inliers;
}

bool Relocalizer::SamePlace(const RelocalizedPose& a, const RelocalizedPose& b) const {
  const core::Pose relative = a.frame.T_cw * b.frame.T_cw.inverse();
  return relative.translation().norm() <= options_.ambiguous_distance &&
         core::RotationAngleDegrees(relative.linear()) <= options_.ambiguous_angle_deg;
}

}  // namespace hoidslam::slam
