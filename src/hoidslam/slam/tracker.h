#pragma once
// Tracking: the pose of every frame from the map, ORB-SLAM's RGB-D way, as a small state machine over searches
// that return hypotheses (track/frame_tracker.h, track/relocalizer.h) judged by the evidence of their own data
// (track/pose_acceptance.h). The first frame with enough keypoints with depth starts the map. After that each frame
// is tracked from the motion model's prediction, or from the reference keyframe when that fails or is doubtful,
// or — too bare for both — in the map around the last tracked frame; every estimate is confirmed against the local
// map and judged. A lost frame is looked for where the motion model puts it (after a short loss), then by
// relocalisation.
//
// States: not initialised → ok ⇄ lost, and lost → provisional → ok. A pose found after a loss is provisional: the
// frame is reported with its pose, but nothing is written to the map from it — no keyframe, no map point, no
// tracking statistics, no erased point, and so no loop and no merge — until the frames that follow confirm it
// (TrackerOptions::confirmation_*): each tracked against the local map around it, accepted, and moving as the
// motion measured since allows. A well-backed frame moving as no camera does, or no confirmation within a second,
// is a refutation: the relocalisation is withdrawn, its frames are reported lost (TrackResult::withdrawn) and
// tracking goes back to where it stood before the loss.
// The tracker is the only one that writes to the map, once per frame, from the hypothesis it took; it decides
// when a frame becomes a keyframe (track/keyframe_decision.h) and hands it to local mapping.
//
// The frames it is given hold only the keypoints the exclusion filter kept, so dropped keypoints take part in
// nothing: matching, optimisation, new map points and relocalisation never see them.

#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/data/map.h"
#include "hoidslam/slam/local_mapper.h"
#include "hoidslam/slam/track/frame_placement.h"
#include "hoidslam/slam/track/frame_tracker.h"
#include "hoidslam/slam/track/keyframe_decision.h"
#include "hoidslam/slam/track/motion_model.h"
#include "hoidslam/slam/track/pose_acceptance.h"
#include "hoidslam/slam/track/pose_hypothesis.h"
#include "hoidslam/slam/track/relocalizer.h"

namespace hoidslam::slam {

enum class TrackingState { kNotInitialized, kOk, kProvisional, kLost };
std::string_view ToString(TrackingState state);

struct TrackerOptions {
  // Keypoints with depth a frame needs to start the map. ORB-SLAM asks for 500 keypoints; a room whose back wall
  // is beyond the sensor's range, with people's features dropped, can have fewer with depth in every frame.
  int min_initial_points = 300;
  // A loss shorter than this (seconds since the last tracked frame) is bridged by the motion model first, and the
  // motion model's prediction judges what is found then.
  double max_motion_gap = 1.0;
  // A new keyframe makes map points of all its untracked close keypoints and, nearest first, of far ones until it
  // has made this many. ORB-SLAM makes 100; with people's features dropped, far structure (walls beyond ThDepth)
  // is often all that is left, and more far points keep tracking alive there (walking_rpy: 6.0 → 4.0 mm).
  int keyframe_min_new_points = 1000;
  // Lost for this long (seconds), the camera is taken to be in new ground: a new map is opened in the Atlas
  // (map.h). Each frame is then looked for in every map (relocalisation), and the first one that is not found
  // there but has enough keypoints with depth starts the new map; loop closing merges it into an earlier map once it
  // recognises a place of that map. 0: never; the camera stays lost until relocalised in the map.
  double new_map_after = 1.0;
  // A pose found after a loss stays provisional until it has been tracked, frame after frame, for
  // confirmation_seconds and over confirmation_frames frames, itself included — three frames make two motions, the
  // second checked against the first: a pose that the local map corrects on the next frame leaves a jump the frame
  // after cannot continue. A frame lost in between starts the count again.
  double confirmation_seconds = 0.2;
  int confirmation_frames = 3;
  // A provisional pose is refuted by a frame whose pose a good share of its matches backs (PoseAcceptanceOptions::
  // min_inlier_ratio) yet the motion since rules out, or when it has not been confirmed this long after it was
  // found (seconds). A frame too weak to say either way (blurred, bare) is lost, and the pose stays provisional.
  double max_provisional_seconds = 1.0;
  // The geometric safety net (mode hoidplus): a map point whose measured depth misfits the tracked pose (off by
  // more than moving_point_depth of the predicted depth) this many times in a row, counted on well-tracked frames
  // where it is matched, is taken to be on something moving and erased from the map. 0: off. It catches what no
  // detector saw; a static point's depth rarely misfits thrice running.
  int moving_point_outliers = 0;
  double moving_point_depth = 0.1;
  // A depth image taken apart from the colour image (core::RgbdFrame::depth_delay) sees a point where the camera
  // had moved it to: a depth edge lands on the wrong side of a keypoint and a static point misfits. A point that
  // moved more than this many pixels in the image over the delay (by the motion since the last frame) is neither
  // accused nor cleared on that frame.
  double moving_point_max_delay_shift = 1.0;
  // Each tracked frame keeps its inliers (track/frame_placement.h), to be placed again once the map is adjusted at
  // the end (PlaceFramesInAdjustedMap). System turns it on with its final adjustment.
  bool record_inliers = false;
  MotionModelOptions motion;
  PoseAcceptanceOptions acceptance;
  FrameTrackerOptions search;
  RelocalizationOptions relocalization;
  KeyFrameDecisionOptions keyframes;

  void Check() const;
};

struct TrackResult {
  TrackingState state = TrackingState::kNotInitialized;
  TrackingMethod method = TrackingMethod::kNone;
  int keypoints = 0;  // the frame's keypoints (after the exclusion filter)
  int matched = 0;    // keypoints matched to map points before the final pose optimisation
  int inliers = 0;    // of those, kept by it
  bool keyframe = false;  // the frame became a keyframe
  int moving_points = 0;  // map points the safety net erased on this frame
  TrackingFailure failure = TrackingFailure::kNone;  // when not tracked (after initialisation)
  PoseRejection rejection = PoseRejection::kNone;    // when the last pose tried was refused: why
  // The evidence the pose taken (or, when none was, the last one refused) was judged on; nullopt when no pose
  // got that far (initialisation, too few matches for a first estimate).
  std::optional<PoseEvidence> evidence;
  std::optional<core::Pose> T_cw;  // when tracked, provisionally or not
  MapId map = 0;  // when tracked: the map it was tracked in (map.h); a later merge may move it into another
  // This frame refuted a provisional relocalisation: the ids of the frames tracked provisionally since, now lost.
  std::vector<std::uint64_t> withdrawn;
};

// Where a frame tracked against a keyframe stands once that keyframe has moved (a loop corrected, a map merged into
// another's world frame, a bundle adjustment): the frame keeps its pose relative to the keyframe. Bit for bit T_cw
// when the keyframe has not moved.
core::Pose FollowKeyFrame(const core::Pose& T_cw, const core::Pose& keyframe_T_cw_then,
                          const core::Pose& keyframe_T_cw_now);

class Tracker {
 public:
  // Lost frames are described with `vocabulary` to find their place; it must outlive the tracker.
  Tracker(Map& map, const bow::Vocabulary& vocabulary, LocalMapper& local_mapper, const TrackerOptions& options);

  // Tracks the next frame (frame ids increase by one from 0). Takes the map's lock as map.h describes.
  TrackResult Track(Frame frame);

  // Tracks in a map loaded before the first frame: that frame is relocalised in it rather than starting a map. In
  // localisation, frames are only tracked: no keyframe is made and the safety net erases no point, so the map
  // stays as it was loaded.
  void StartInLoadedMap(bool localization);

  // Where each frame stands, to place it once the map has been refined (as ORB-SLAM saves trajectories): its pose
  // relative to its reference keyframe. Lost frames, and frames of a withdrawn relocalisation, have no reference.
  struct FrameRecord {
    double timestamp = 0.0;
    KeyFrame* reference = nullptr;
    core::Pose T_cr = core::Pose::Identity();
    // The frame's inliers (TrackerOptions::record_inliers; none for a frame that became a keyframe).
    std::vector<RecordedInlier> inliers;

    // Its reference keyframe now and its pose relative to it: a culled keyframe kept its pose relative to its
    // parent, so the chain is followed to a live one. Needs a reference.
    std::pair<KeyFrame*, core::Pose> Resolved() const;
  };
  const std::vector<FrameRecord>& records() const { return records_; }

  // Once the map is adjusted at the end (System::Finish), each frame that is not a keyframe is placed again by its
  // recorded inliers against the adjusted points (track/frame_placement.h), from where its reference keyframe now
  // puts it; a frame whose inliers no longer agree on a pose stays with its keyframe. Takes the map's lock.
  void PlaceFramesInAdjustedMap();

 private:
  // Where tracking stood after the last tracked frame: what a refuted relocalisation goes back to.
  struct Standing {
    std::optional<Frame> last_frame;
    FrameRecord last_record;
    MotionModel motion;
    KeyFrame* reference_keyframe = nullptr;
  };
  // A relocalisation not confirmed yet.
  struct Provisional {
    double since = 0.0;             // stamp of the frame found again
    std::size_t first_record = 0;   // its index in records_
    std::vector<std::uint64_t> frames;  // ids of the frames tracked since, itself included
    Standing before;                // tracking before the loss
    // The frames tracked in a row up to the last one, and the stamp of the first of them: a frame lost between
    // starts the count again, since the motion is checked from frame to frame.
    int streak = 0;
    double streak_since = 0.0;
  };

  bool Initialize(Frame& frame);
  // Lost for TrackerOptions::new_map_after: opens a new map, once.
  void OpenNewMapWhenLostLong(const Frame& frame);
  // Local mapping may have fused points the last tracked frame matched, or moved its reference keyframe.
  void RefreshLastFrame();
  // The searches of a frame that follows a tracked one: the motion model, the reference keyframe (also when the
  // motion model's pose is doubtful: the pose more inliers back is kept), and for a bare frame the map around the
  // last frame. The accepted hypothesis, or the last one refused.
  PoseHypothesis TrackFollowing(const Frame& frame, const TrackingContext& context) const;
  // A lost frame: around the motion model's prediction after a short loss, else by relocalisation.
  PoseHypothesis Recover(const Frame& frame, const TrackingContext& context, double gap) const;
  // What an accepted, confirmed hypothesis leaves on the map points: visible and found counts, and the safety net's
  // outlier streaks; returns the points the safety net takes to be moving. `last`: the last tracked frame, `gap`
  // seconds before (the motion that tells how far a point moved over the depth image's delay).
  std::vector<MapPoint*> CountOnMapPoints(const PoseHypothesis& hypothesis, const Frame* last, double gap) const;
  bool NeedNewKeyFrame(const Frame& frame, int inliers) const;
  // The provisional relocalisation is refuted: its frames are withdrawn and tracking stands where it did before.
  std::vector<std::uint64_t> Withdraw();
  // The keyframe a tracked frame was placed against, and that keyframe's pose, taken under the lock the frame's pose
  // was found under. Loop closing may move the map before tracking takes the lock again to make a keyframe or record
  // the frame (in a merge, by a whole map's change of world frame): the frame then follows its keyframe
  // (FollowKeyFrame), or the keyframe and the record would be made from a pose in the old frame.
  struct Placement {
    const KeyFrame* keyframe = nullptr;
    core::Pose keyframe_T_cw = core::Pose::Identity();
  };
  static Placement PlaceAgainst(const KeyFrame* keyframe) { return {keyframe, keyframe->T_cw()}; }
  static void Follow(Frame& frame, const Placement& placement);
  // Records the frame as tracked, placed as its keyframe now stands, and it becomes the last tracked frame.
  void Record(Frame frame, const Placement& placement, double gap, TrackingMethod method);
  void CreateKeyFrame(Frame& frame);

  Map& map_;
  const bow::Vocabulary& vocabulary_;
  LocalMapper& local_mapper_;
  TrackerOptions options_;
  FrameTracker searches_;
  Relocalizer relocalizer_;

  TrackingState state_ = TrackingState::kNotInitialized;
  bool localization_ = false;
  std::optional<double> lost_since_;  // the stamp of the first frame lost, until tracking is confirmed again
  bool new_map_opened_ = false;       // lost long: a new map is open, and relocalisation looks in every map
  Standing standing_;
  std::optional<Provisional> provisional_;
  KeyFrame* last_keyframe_ = nullptr;
  double last_keyframe_timestamp_ = 0.0;
  std::vector<FrameRecord> records_;
};

}  // namespace hoidslam::slam
