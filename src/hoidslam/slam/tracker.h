#pragma once
// Tracking: the pose of every frame from the map, ORB-SLAM's RGB-D way. The first frame with enough keypoints
// with depth starts the map. After that each frame is tracked by a constant-velocity prediction with a search by
// projection from the last frame, or, when that fails, by descriptor matching against the reference keyframe; the
// pose is then refined against the local map (the keyframes sharing points with the frame and their neighbours).
// A frame too bare for both (people fill the view), and a frame after a short loss, is searched for in the map
// around the last tracked frame where the motion model puts it, with strict descriptor matches and PnP RANSAC;
// after that the frame is relocalised by descriptor matching against keyframes and PnP RANSAC. A frame with few
// keypoints needs fewer inliers (TrackerOptions). The tracker decides when a frame becomes a keyframe and hands it
// to local mapping.
//
// The frames it is given hold only the keypoints the exclusion filter kept, so dropped keypoints take part in
// nothing: matching, optimisation, new map points and relocalisation never see them.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/local_mapper.h"
#include "hoidslam/slam/data/map.h"
#include "hoidslam/slam/optimize/pose_optimizer.h"

namespace hoidslam::slam {

enum class TrackingState { kNotInitialized, kOk, kLost };
std::string_view ToString(TrackingState state);

// How a frame's first pose estimate was found.
enum class TrackingMethod { kNone, kInitialization, kMotionModel, kReferenceKeyFrame, kRelocalization };
std::string_view ToString(TrackingMethod method);

// Why a frame was not tracked: it had fewer keypoints than the inliers it would need; its keypoints found too few
// map points to try a pose (or, after the first estimate, to confirm it against the local map); or the pose
// optimisation kept too few of its matches as inliers.
enum class TrackingFailure { kNone, kTooFewKeypoints, kTooFewMatches, kPoseRejected };
std::string_view ToString(TrackingFailure failure);

struct TrackerOptions {
  // Keypoints with depth a frame needs to start the map. ORB-SLAM asks for 500 keypoints; a room whose back wall
  // is beyond the sensor's range, with people's features dropped, can have fewer with depth in every frame.
  int min_initial_points = 300;
  double motion_search_radius = 7.0;   // pixels at level 0, search by projection from the last frame
  double local_search_radius = 3.0;    // pixels at level 0 (before the oblique-view factor), local-map search
  int min_inliers = 30;                // local-map inliers for a frame to count as tracked
  int min_inliers_after_relocalization = 50;  // the same during the first second after relocalising
  // And at least this share of the local-map matches: a pose the local map mostly contradicts is wrong however
  // many inliers it keeps. (On walking_xyz a motion-model guess after a jerk kept 32 of 530 matches; made a
  // keyframe, it bent the map for good: 56 mm ATE where the other runs had 3.5. On 150 frames of it at twice the
  // step, one keeping 75 of 421 took a deterministic run from 3.2 to 15 mm.) Tracked frames keep 60-75 %. The
  // reference keyframe is tried instead.
  double min_inlier_ratio = 0.3;
  // A motion-model pose that keeps fewer than this share of its local-map matches is doubtful: the reference keyframe
  // is tried as well, and the pose with more inliers kept: the prediction may have led the search to the wrong
  // corners. (On 150 frames of walking_xyz at 15 Hz with hoid2d, a motion-model pose kept 201 of 478 matches, was
  // 80 mm off and became a keyframe: 22 mm ATE. Tried from the reference keyframe too: 3.3 mm.)
  double doubtful_inlier_ratio = 0.5;
  // A frame with few keypoints (people fill the view, the filter dropped most of it) is tracked on what it has,
  // by support rather than count: an inlier whose depth is nearer than the close depth counts
  // close_inlier_weight times (its depth pins the point in 3D: three constraints on the pose where a far one gives
  // two), and the support needed falls to min_inlier_share of the frame's keypoints, never below
  // min_inliers_floor. The risk: a pose resting on a few points in one corner of the image is less certain, and a
  // wrong one corrupts the map; so the lower bar also asks that at least supported_inlier_ratio of the matches be
  // inliers (a wrong pose fits few). At half, crowd lost a median of 10 frames in 5 runs whose local maps kept 40-48 %
  // (22 of 50, 29 of 64); at 0.4 none, and the six other scenarios run as before.
  int min_inliers_floor = 15;
  double min_inlier_share = 0.3;
  double close_inlier_weight = 1.5;
  double supported_inlier_ratio = 0.4;
  // A loss shorter than this (seconds since the last tracked frame) is bridged by the motion model first.
  double max_motion_gap = 1.0;
  int max_local_keyframes = 80;
  int keyframe_max_interval = 30;      // frames; a keyframe at least this often (ORB-SLAM: the frame rate)
  // A new keyframe makes map points of all its untracked close keypoints and, nearest first, of far ones until it
  // has made this many. ORB-SLAM makes 100; with people's features dropped, far structure (walls beyond ThDepth)
  // is often all that is left, and more far points keep tracking alive there (walking_rpy: 6.0 → 4.0 mm).
  int keyframe_min_new_points = 1000;
  int relocalization_candidates = 10;  // keyframes tried per lost frame, besides the last reference's neighbours
  // A pose relocalisation finds after a short loss (max_motion_gap) must lie within the camera's reach of the
  // last tracked frame: reach_distance plus max_camera_speed times the time lost, and as much for the turn. A
  // place taken for another lands anywhere: in a 2-minute office path, a frame lost for two frames was
  // relocalised 0.9 m off on 65 inliers, and the map never recovered. A candidate out of reach is not taken; nor
  // is a pose the search around the motion model's prediction finds out of reach.
  double reach_distance = 0.1;     // metres
  double max_camera_speed = 1.5;   // metres per second: a hand-held or robot camera
  double reach_angle_deg = 10.0;
  double max_camera_turn_rate_deg = 180.0;  // degrees per second
  // Lost for this long (seconds), the camera is taken to be in new ground: a new map is opened in the Atlas
  // (map.h). Each frame is then looked for in every map (relocalisation), and the first one that is not found
  // there but has enough keypoints with depth starts the new map; loop closing merges it into an earlier map once it
  // recognises a place of that map. 0: never; the camera stays lost until relocalised in the map.
  double new_map_after = 1.0;
  // The geometric safety net (mode hoidplus): a map point whose measured depth misfits the tracked pose (off by
  // more than moving_point_depth of the predicted depth) this many times in a row, counted on well-tracked frames
  // where it is matched, is taken to be on something moving and erased from the map. 0: off. It catches what no
  // detector saw; a static point's depth rarely misfits thrice running.
  int moving_point_outliers = 0;
  double moving_point_depth = 0.1;
  // A frame that follows a tracked one (within max_motion_gap, not relocalised) is held to the motion model's
  // prediction in every pose optimisation by a soft prior (PosePrior), as loose as a
  // hand-held camera's motion may depart from constant velocity in the time τ since the last frame: by
  // motion_prior_acceleration · τ² metres and motion_prior_angular_acceleration_deg · τ² degrees (10 mm and 1° at
  // 30 Hz; a frame dropped, four times that). Where people leave only far background in one strip of the image a
  // sideways step looks like a turn, and without the prior the pose wandered 20-110 mm within a frame there; a
  // keyframe made on such a pose moved the map for good (crowd: 70 mm ATE where other runs had 8). Where the
  // keypoints fix the pose the prior changes nothing. 0 for either: no prior.
  double motion_prior_acceleration = 9.0;                // m/s²
  double motion_prior_angular_acceleration_deg = 900.0;  // °/s²
  PoseOptimizerOptions pose_optimizer;

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
  std::optional<core::Pose> T_cw;  // when tracked
  MapId map = 0;  // when tracked: the map it was tracked in (map.h); a later merge may move it into another
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
  // relative to its reference keyframe. Lost frames have no reference.
  struct FrameRecord {
    double timestamp = 0.0;
    KeyFrame* reference = nullptr;
    core::Pose T_cr = core::Pose::Identity();
  };
  const std::vector<FrameRecord>& records() const { return records_; }

 private:
  bool Initialize(Frame& frame);
  // The first pose estimates: kNone when found, else why not. The motion model predicts from the last tracked
  // frame by the last measured motion (none: standing still), scaled to the time elapsed, and searches within a
  // radius grown with the frames elapsed.
  TrackingFailure TrackWithMotionModel(Frame& frame);
  // Sets frame.T_cw where the motion model puts the camera: the last tracked frame's pose moved by the last
  // measured motion scaled to the time elapsed (no measured motion: standing still). Returns how many frames'
  // worth of motion that is, 1 to 4 (0 without a measured motion), by which search windows grow.
  double PredictPose(Frame& frame) const;
  // Where the measured motion puts the camera `elapsed` seconds after the last tracked frame (a motion measured).
  core::Pose Predicted(double elapsed) const;
  // The prediction as a soft prior (TrackerOptions::motion_prior_*), when there is a measured motion.
  std::optional<PosePrior> MotionPrior(const Frame& frame) const;
  const PosePrior* MotionPriorOrNull() const { return motion_prior_ ? &*motion_prior_ : nullptr; }
  // Lost for TrackerOptions::new_map_after: opens a new map, once.
  void OpenNewMapWhenLostLong(const Frame& frame);
  // For a frame the usual searches cannot track, or after a short loss: the local map of the last tracked frame
  // (the keyframes that see its points, and their neighbours) searched for where the motion model puts it, within a
  // window grown with the frames lost, matching only close descriptors (kDescriptorDistanceLow), then PnP RANSAC.
  // With people over most of the view most of those points are hidden, and a loose match grabs whatever corner
  // is near: on the crowd scenario 3 of 88 such matches were right, and no optimisation survived them.
  TrackingFailure TrackFromPrediction(Frame& frame);
  TrackingFailure TrackReferenceKeyFrame(Frame& frame);
  TrackingFailure Relocalize(Frame& frame);
  // Whether the frame's pose is within the camera's reach of the last tracked frame (TrackerOptions).
  bool WithinReach(const Frame& frame) const;
  // PnP RANSAC (EPnP, 4 px) over the frame's matches: sets frame.T_cw and keeps only the consistent matches, whose
  // number it returns (0 and the frame untouched when no pose is found).
  int EstimatePoseRansac(Frame& frame);
  // Refines the pose against the local map; fills result.matched / inliers; kNone when enough inliers remain.
  TrackingFailure TrackLocalMap(Frame& frame, TrackResult& result);
  // Whether a pose with these inliers stands (TrackerOptions: the count, or the support on a frame that has little).
  bool Accepted(const Frame& frame, int inliers, int matched, int min_inliers) const;
  // The keyframes that see the frame's matched points and their neighbours; `most_shared` becomes the one that
  // sees most of them (left as it is when none does).
  std::vector<KeyFrame*> LocalKeyFrames(const Frame& frame, KeyFrame*& most_shared) const;
  // The safety net: counts the frame's misfitting matches and collects the points that misfit too often.
  void FindMovingPoints(const Frame& frame, const TrackResult& result);
  bool NeedNewKeyFrame(const Frame& frame, int inliers) const;
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
  void CreateKeyFrame(Frame& frame);

  Map& map_;
  const bow::Vocabulary& vocabulary_;
  LocalMapper& local_mapper_;
  TrackerOptions options_;

  TrackingState state_ = TrackingState::kNotInitialized;
  bool localization_ = false;
  std::optional<double> lost_since_;  // the stamp of the first frame lost, while lost
  bool new_map_opened_ = false;       // lost long: a new map is open, and relocalisation looks in every map
  // The last tracked frame (the last frame while tracking, the one before the loss when lost) and its record.
  std::optional<Frame> last_frame_;
  FrameRecord last_record_;
  KeyFrame* last_keyframe_ = nullptr;
  KeyFrame* reference_keyframe_ = nullptr;
  // The last measured motion, T_cl (last camera to current camera), and the time it took: a prediction scales it
  // to the time since the last frame, so a dropped frame (TUM recordings have them) does not break the motion model.
  std::optional<core::Pose> velocity_;
  double velocity_seconds_ = 0.0;
  std::optional<PosePrior> motion_prior_;  // for the frame being tracked, when there is a measured motion
  std::uint64_t last_keyframe_frame_id_ = 0;
  std::optional<std::uint64_t> last_relocalization_frame_id_;
  std::vector<FrameRecord> records_;
  std::vector<MapPoint*> moving_points_;  // found by the safety net on the current frame, erased after tracking it
};

}  // namespace hoidslam::slam
