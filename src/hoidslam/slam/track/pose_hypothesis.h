#pragma once
// What one attempt at tracking a frame found: a pose with its matches, and the evidence it was judged on. The
// searches (frame_tracker.h, relocalizer.h) return hypotheses and change neither the frame nor the map; the
// tracker takes one and is the only one to write what it found into the map.

#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/track/pose_acceptance.h"

namespace hoidslam::slam {

// How a frame's first pose estimate was found.
enum class TrackingMethod { kNone, kInitialization, kMotionModel, kReferenceKeyFrame, kRelocalization };
std::string_view ToString(TrackingMethod method);

// Why a frame was not tracked: it had fewer keypoints than the inliers it would need; its keypoints found too few
// map points to try a pose (or, after the first estimate, to confirm it against the local map); the pose was
// refused (PoseRejection says why); or, provisional after a relocalisation, it did not confirm that relocalisation,
// which was withdrawn.
enum class TrackingFailure { kNone, kTooFewKeypoints, kTooFewMatches, kPoseRejected, kRelocalizationRefuted };
std::string_view ToString(TrackingFailure failure);

struct PoseHypothesis {
  TrackingMethod method = TrackingMethod::kNone;
  // Why the attempt found no pose to judge, or why its pose was refused; kNone when accepted.
  TrackingFailure failure = TrackingFailure::kTooFewMatches;
  // The frame as the attempt left it: pose, matches, outlier flags, and as reference keyframe the one of its local
  // map that sees most of its points. Empty when no first estimate was found.
  std::optional<Frame> frame;
  int matched = 0;  // keypoints matched before the final pose optimisation
  int inliers = 0;  // kept by it
  // The map points the local map predicted in view and the frame's own matches: each counts a frame in which it
  // should have been seen, once the hypothesis is taken (MapPoint::IncreaseVisible).
  std::vector<MapPoint*> visible;
  PoseEvidence evidence;
  PoseVerdict verdict;
  // The information of the final pose (pose_optimizer.h); its inverse is the pose's covariance.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();

  bool accepted() const { return verdict.accepted; }
};

}  // namespace hoidslam::slam
