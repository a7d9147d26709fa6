#pragma once
// The searches that find a frame's pose while it is being tracked: from the motion model's prediction, from the
// reference keyframe, and — for a frame too bare for both, or after a short loss — in the map around the last
// tracked frame where the motion model puts it. Each ends by confirming its first estimate against the local map
// and judging the result (pose_acceptance.h), and returns a hypothesis: none changes the frame it is given or
// the map. Callers hold Map::mutex(), shared at least.

#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/data/keyframe.h"
#include "hoidslam/slam/optimize/pose_optimizer.h"
#include "hoidslam/slam/track/motion_model.h"
#include "hoidslam/slam/track/pnp_ransac.h"
#include "hoidslam/slam/track/pose_acceptance.h"
#include "hoidslam/slam/track/pose_hypothesis.h"

namespace hoidslam::slam {

struct FrameTrackerOptions {
  double motion_search_radius = 7.0;  // pixels at level 0: search by projection from the last frame (twice that
                                      // when too few match)
  double local_search_radius = 3.0;   // pixels at level 0 (before the oblique-view factor): the local-map search
  double provisional_search_radius = 5.0;  // the same while a relocalisation is provisional
  int max_local_keyframes = 80;
  // Matches needed before a pose optimisation is worth trying, and inliers after it for a first estimate.
  int min_projection_matches = 20;
  int min_descriptor_matches = 15;
  int min_first_estimate_inliers = 10;
  float reference_descriptor_ratio = 0.7F;  // ratio test of matching the reference keyframe by descriptor
  PnpRansacOptions ransac;
  PoseOptimizerOptions pose_optimizer;

  void Check() const;
};

// What the searches know of the frames before.
struct TrackingContext {
  const Frame* last = nullptr;                // the last tracked frame, its points and pose current
  const MotionModel* motion = nullptr;        // the motion measured up to it
  const PosePrior* prior = nullptr;           // the motion model's prediction as a prior, when there is one
  KeyFrame* reference_keyframe = nullptr;     // the keyframe tracking relied on last
  bool provisional = false;                   // judging a relocalisation not yet confirmed
};

class FrameTracker {
 public:
  FrameTracker(const FrameTrackerOptions& options, const PoseAcceptanceOptions& acceptance);

  // The motion model's prediction (standing still without a measured motion): the last frame's points searched for
  // where it puts them.
  PoseHypothesis WithMotionModel(const Frame& frame, const TrackingContext& context) const;
  // The reference keyframe's points matched by descriptor, from the last frame's pose.
  PoseHypothesis FromReferenceKeyFrame(const Frame& frame, const TrackingContext& context) const;
  // The local map of the last frame (the keyframes that see its points, and their neighbours) searched where the
  // motion model puts the camera, within a window grown with the time elapsed, matching only close descriptors
  // (kDescriptorDistanceLow), then PnP RANSAC. With people over most of the view most of those points are hidden,
  // and a loose match grabs whatever corner is near: on the crowd scenario 3 of 88 such matches were right.
  PoseHypothesis FromPrediction(const Frame& frame, const TrackingContext& context) const;
  // A first estimate (`estimate`, its pose and matches) confirmed against the local map: the local keyframes' points
  // that project into it searched for, the pose optimised against every match (with the prior, when there is
  // one), and the result judged.
  PoseHypothesis ConfirmWithLocalMap(Frame estimate, TrackingMethod method, const TrackingContext& context) const;

  // The keyframes that see the frame's matched points, and their neighbours (up to max_local_keyframes); the one
  // that sees most of them is written to `most_shared` (left as it is when none does).
  std::vector<KeyFrame*> LocalKeyFrames(const Frame& frame, KeyFrame*& most_shared) const;

  const FrameTrackerOptions& options() const { return options_; }

 private:
  // The first estimate's pose optimised against its matches (outliers dropped), then confirmed: or why not.
  PoseHypothesis FromFirstEstimate(Frame estimate, int matches, TrackingMethod method,
                                   const TrackingContext& context) const;

  FrameTrackerOptions options_;
  PoseAcceptanceOptions acceptance_;
};

// The frame with no match: every map point cleared, every outlier flag too.
void ClearMatches(Frame& frame);
int CountMatches(const Frame& frame);

}  // namespace hoidslam::slam
