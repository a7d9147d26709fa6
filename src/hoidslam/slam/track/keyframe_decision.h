#pragma once
// Whether a tracked frame becomes a keyframe: ORB-SLAM's rules as one pure function of a few counts, with its
// thresholds as options (keyframe_decision_test.cc has a row per rule).

namespace hoidslam::slam {

struct KeyFrameDecisionOptions {
  double max_interval = 1.0;  // seconds: a keyframe at least this often, when tracking has weakened (ORB-SLAM: 1 s)
  // Tracking has weakened against the reference keyframe when the frame's inliers fall below this share of the
  // points the reference keyframe tracks (reference_ratio_first while the map has a single keyframe) ...
  double reference_ratio = 0.75;
  double reference_ratio_first = 0.4;
  // ... or below this share, which is worth a keyframe even while local mapping is busy.
  double weak_ratio = 0.25;
  // Many close keypoints untracked is new structure worth mapping: fewer than close_tracked tracked, more than
  // close_untracked not.
  int close_tracked = 100;
  int close_untracked = 70;
  int min_inliers = 15;  // a frame with fewer inliers makes no keyframe however weak it is
  int max_queued = 3;    // keyframes local mapping may have waiting when it is busy

  void Check() const;
};

// What the decision looks at.
struct KeyFrameDecisionInput {
  bool mapper_paused = false;  // loop closing is correcting the map
  bool mapper_idle = true;
  int mapper_queued = 0;
  int map_keyframes = 0;        // in the active map
  int inliers = 0;              // the frame's local-map inliers
  int reference_points = 0;     // points of the reference keyframe that enough keyframes see
  int close_tracked = 0;        // the frame's keypoints with close depth that are inliers
  int close_untracked = 0;      // and that are not
  double since_keyframe = 0.0;  // seconds since the last keyframe
};

bool NeedNewKeyFrame(const KeyFrameDecisionInput& input, const KeyFrameDecisionOptions& options);

}  // namespace hoidslam::slam
