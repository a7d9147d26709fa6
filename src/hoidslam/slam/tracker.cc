#include "hoidslam/slam/tracker.h"

#include <algorithm>
#include <limits>
#include <mutex>
#include <shared_mutex>

#include <spdlog/spdlog.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/option_checks.h"
#include "hoidslam/slam/data/keyframe_database.h"

namespace hoidslam::slam {
namespace {

constexpr core::EnumNames<TrackingState, 4> kStateNames = {{
    {TrackingState::kNotInitialized, "not_initialized"},
    {TrackingState::kOk, "ok"},
    {TrackingState::kProvisional, "provisional"},
    {TrackingState::kLost, "lost"},
}};
constexpr core::EnumNames<TrackingMethod, 5> kMethodNames = {{
    {TrackingMethod::kNone, "none"},
    {TrackingMethod::kInitialization, "initialization"},
    {TrackingMethod::kMotionModel, "motion_model"},
    {TrackingMethod::kReferenceKeyFrame, "reference_keyframe"},
    {TrackingMethod::kRelocalization, "relocalization"},
}};
constexpr core::EnumNames<TrackingFailure, 5> kFailureNames = {{
    {TrackingFailure::kNone, "none"},
    {TrackingFailure::kTooFewKeypoints, "too_few_keypoints"},
    {TrackingFailure::kTooFewMatches, "too_few_matches"},
    {TrackingFailure::kPoseRejected, "pose_rejected"},
    {TrackingFailure::kRelocalizationRefuted, "relocalization_refuted"},
}};

// Of two hypotheses, the one to keep: an accepted one over a refused one, of two accepted the one more inliers
// back, of two refused the later (its failure says why the frame is lost).
PoseHypothesis Better(PoseHypothesis first, PoseHypothesis second) {
  if (first.accepted() && (!second.accepted() || second.inliers <= first.inliers)) return first;
  return second;
}

}  // namespace

core::Pose FollowKeyFrame(const core::Pose& T_cw, const core::Pose& keyframe_T_cw_then,
                          const core::Pose& keyframe_T_cw_now) {
  if (keyframe_T_cw_now.matrix() == keyframe_T_cw_then.matrix()) return T_cw;
  return T_cw * keyframe_T_cw_then.inverse() * keyframe_T_cw_now;
}

std::string_view ToString(TrackingState state) { return core::EnumName(kStateNames, state); }
std::string_view ToString(TrackingMethod method) { return core::EnumName(kMethodNames, method); }
std::string_view ToString(TrackingFailure failure) { return core::EnumName(kFailureNames, failure); }

void TrackerOptions::Check() const {
  core::CheckPositive(min_initial_points, "Tracking.minInitialPoints");
  core::CheckPositive(max_motion_gap, "Tracking.maxMotionGap");
  core::CheckPositive(keyframe_min_new_points, "Tracking.keyFrameMinNewPoints");
  if (!(new_map_after >= 0.0)) {
    throw core::InputError::ForParameter("Tracking.newMapAfter",
                                         fmt::format("must be >= 0 seconds (0: never), got {}", new_map_after));
  }
  core::CheckNotNegative(confirmation_seconds, "Tracking.confirmationSeconds");
  core::CheckInRange(confirmation_frames, 1, 1000, "Tracking.confirmationFrames");
  core::CheckPositive(max_provisional_seconds, "Tracking.maxProvisionalSeconds");
  core::CheckNotNegative(moving_point_outliers, "Tracking.movingPointOutliers");
  core::CheckPositive(moving_point_depth, "Tracking.movingPointDepth");
  core::CheckPositive(moving_point_max_delay_shift, "Tracking.movingPointMaxDelayShift");
  motion.Check();
  acceptance.Check();
  search.Check();
  relocalization.Check();
  keyframes.Check();
}

Tracker::Tracker(Map& map, const bow::Vocabulary& vocabulary, LocalMapper& local_mapper,
                 const TrackerOptions& options)
    : map_(map),
      vocabulary_(vocabulary),
      local_mapper_(local_mapper),
      options_(options),
      searches_(options.search, options.acceptance),
      relocalizer_(map, options.relocalization, options.search) {
  options_.Check();
  standing_.motion = MotionModel(options_.motion);
}

TrackResult Tracker::Track(Frame frame) {
  TrackResult result;
  result.keypoints = frame.size();
  OpenNewMapWhenLostLong(frame);
  PoseHypothesis chosen;
  bool confirms = false;  // a provisional relocalisation is confirmed by this frame
  bool make_keyframe = false;
  Placement placement;
  std::vector<MapPoint*> moving;
  double gap = std::numeric_limits<double>::infinity();
  {
    std::shared_lock lock(map_.mutex());
    // Initialisation writes the map: done below under the exclusive lock.
    if (state_ != TrackingState::kNotInitialized) {
      RefreshLastFrame();
      const std::optional<Frame>& last = standing_.last_frame;
      if (last) gap = frame.timestamp - last->timestamp;
      const std::optional<PosePrior> prior =
          gap <= options_.max_motion_gap ? standing_.motion.Prior(last->T_cw, gap) : std::nullopt;
      TrackingContext context;
      context.last = last ? &*last : nullptr;
      context.motion = &standing_.motion;
      context.prior = prior ? &*prior : nullptr;
      context.reference_keyframe = standing_.reference_keyframe;
      context.provisional = state_ != TrackingState::kOk;
      chosen = state_ == TrackingState::kLost ? Recover(frame, context, gap) : TrackFollowing(frame, context);
      if (chosen.accepted()) {
        if (state_ == TrackingState::kProvisional) {
          // The frames tracked in a row, this one included. (Less a microsecond: stamps at an exact rate land a
          // hair short of the interval they span.)
          const int streak = provisional_->streak + 1;
          const double since = provisional_->streak > 0 ? provisional_->streak_since : frame.timestamp;
          confirms = streak >= options_.confirmation_frames &&
                     frame.timestamp - since >= options_.confirmation_seconds - 1e-6;
        }
        if ((state_ == TrackingState::kOk || confirms) && chosen.verdict.mappable) {
          moving = CountOnMapPoints(chosen, last ? &*last : nullptr, gap);
          make_keyframe = !localization_ && NeedNewKeyFrame(*chosen.frame, chosen.inliers);
        }
        const KeyFrame* reference = chosen.frame->reference_keyframe != nullptr ? chosen.frame->reference_keyframe
                                                                                 : standing_.reference_keyframe;
        placement = PlaceAgainst(reference);
      }
    }
  }
  const bool accepted = chosen.accepted();
  if (chosen.method != TrackingMethod::kNone) {
    result.method = chosen.method;
    result.matched = chosen.matched;
    result.inliers = chosen.inliers;
    result.rejection = chosen.verdict.rejection;
    if (chosen.frame) result.evidence = chosen.evidence;
  }
  if (accepted) frame = std::move(*chosen.frame);
  if (!moving.empty()) {
    std::unique_lock lock(map_.mutex());
    for (MapPoint* p : moving) map_.ErasePoint(p);
    for (MapPoint*& p : frame.map_points) {
      if (p != nullptr && p->bad()) p = nullptr;
    }
    result.moving_points = static_cast<int>(moving.size());
  }
  bool initialized = false;
  if (state_ == TrackingState::kNotInitialized || (!accepted && new_map_opened_ && state_ == TrackingState::kLost)) {
    // The first map, or a new one: the frame was not found in any map.
    std::unique_lock lock(map_.mutex());
    initialized = Initialize(frame);
    if (initialized) {
      placement = PlaceAgainst(frame.reference_keyframe);
      result.method = TrackingMethod::kInitialization;
      result.keyframe = true;
      result.matched = result.inliers = frame.keypoints->num_with_depth();
      result.rejection = PoseRejection::kNone;
      result.evidence.reset();
      local_mapper_.Insert(last_keyframe_);
      standing_.motion.Reset();
      new_map_opened_ = false;
    }
  } else if (confirms && new_map_opened_) {
    // Found again in a map and confirmed: tracking goes on there, and the new map, still empty, is forgotten.
    std::unique_lock lock(map_.mutex());
    const KeyFrame* reference =
        frame.reference_keyframe != nullptr ? frame.reference_keyframe : standing_.reference_keyframe;
    map_.ActivateMap(reference->map_id());
    new_map_opened_ = false;
  } else if (make_keyframe) {
    // Queued under the lock, and not at all while a loop is being corrected (LocalMapper::Pause).
    std::unique_lock lock(map_.mutex());
    if (!local_mapper_.Paused()) {
      Follow(frame, placement);
      CreateKeyFrame(frame);
      placement = PlaceAgainst(frame.reference_keyframe);
      result.keyframe = true;
      local_mapper_.Insert(last_keyframe_);
    }
  }

  if (initialized) {
    state_ = TrackingState::kOk;
    provisional_.reset();
    lost_since_.reset();
    Record(std::move(frame), placement, gap, TrackingMethod::kInitialization);
  } else if (accepted) {
    if (state_ == TrackingState::kLost) {
      // Found again: provisional until the next frames confirm it.
      provisional_ = Provisional{frame.timestamp, records_.size(), {}, standing_};
      state_ = TrackingState::kProvisional;
    }
    if (state_ == TrackingState::kProvisional) {
      if (provisional_->streak++ == 0) provisional_->streak_since = frame.timestamp;
      provisional_->frames.push_back(frame.id);
    }
    if (confirms) {
      spdlog::debug("frame {}: the pose found at {:.3f} is confirmed after {} frames", frame.id, provisional_->since,
                    provisional_->frames.size());
      provisional_.reset();
      state_ = TrackingState::kOk;
      lost_since_.reset();
    }
    Record(std::move(frame), placement, gap, chosen.method);
  } else {
    if (state_ == TrackingState::kProvisional) {
      const bool ruled_out = chosen.verdict.rejection == PoseRejection::kAgainstMotion &&
                             chosen.evidence.inlier_ratio() >= options_.acceptance.min_inlier_ratio;
      if (ruled_out || frame.timestamp - provisional_->since > options_.max_provisional_seconds) {
        result.withdrawn = Withdraw();
        result.failure = TrackingFailure::kRelocalizationRefuted;
      } else {
        provisional_->streak = 0;
      }
    } else if (state_ == TrackingState::kOk) {
      state_ = TrackingState::kLost;
    }
    if (state_ == TrackingState::kLost && !lost_since_) lost_since_ = frame.timestamp;
    records_.push_back({frame.timestamp, nullptr, core::Pose::Identity(), {}});
    if (state_ != TrackingState::kNotInitialized && result.failure == TrackingFailure::kNone) {
      result.failure =
          frame.size() < options_.acceptance.min_inliers_floor ? TrackingFailure::kTooFewKeypoints : chosen.failure;
    }
  }
  if (accepted || initialized) {
    result.T_cw = standing_.last_frame->T_cw;
    result.map = standing_.last_record.reference->map_id();
  }
  // A frame lost while a pose is provisional is reported lost; the pose stays provisional.
  result.state = result.T_cw || state_ != TrackingState::kProvisional ? state_ : TrackingState::kLost;
  return result;
}

void Tracker::Record(Frame frame, const Placement& placement, double gap, TrackingMethod method) {
  if (frame.reference_keyframe == nullptr) frame.reference_keyframe = standing_.reference_keyframe;
  standing_.reference_keyframe = frame.reference_keyframe;
  // The motion since the last tracked frame; over a long loss, or from a relocalisation, it says nothing of the next.
  if (gap <= options_.max_motion_gap && method != TrackingMethod::kRelocalization && standing_.last_frame) {
    standing_.motion.Measure(standing_.last_frame->T_cw, frame.T_cw, gap);
  } else {
    standing_.motion.Reset();
  }
  {
    // Local mapping's bundle adjustment may be moving the reference keyframe right now, and loop closing may have
    // moved it since the frame was tracked.
    std::shared_lock lock(map_.mutex());
    Follow(frame, placement);
    records_.push_back({frame.timestamp, frame.reference_keyframe, frame.T_cw * frame.reference_keyframe->T_wc(), {}});
  }
  standing_.last_record = records_.back();
  if (options_.record_inliers && frame.reference_keyframe->timestamp() != frame.timestamp) {
    records_.back().inliers = RecordInliers(frame);  // (point ids never change: no lock needed)
  }
  // The next frame searches from this one's inliers only.
  for (int i = 0; i < frame.size(); ++i) {
    if (frame.outlier[static_cast<std::size_t>(i)] != 0) frame.map_points[static_cast<std::size_t>(i)] = nullptr;
  }
  standing_.last_frame = std::move(frame);
}

std::vector<std::uint64_t> Tracker::Withdraw() {
  Provisional provisional = std::move(*provisional_);
  provisional_.reset();
  spdlog::debug("the pose found at {:.3f} is refuted: {} frames withdrawn", provisional.since,
                provisional.frames.size());
  for (std::size_t r = provisional.first_record; r < records_.size(); ++r) {
    records_[r].reference = nullptr;
    records_[r].inliers = {};  // a withdrawn frame is never placed
  }
  standing_ = std::move(provisional.before);
  state_ = TrackingState::kLost;
  return provisional.frames;
}

std::pair<KeyFrame*, core::Pose> Tracker::FrameRecord::Resolved() const {
  KeyFrame* keyframe = reference;
  core::Pose T_ck = T_cr;
  while (keyframe->bad()) {
    T_ck = T_ck * keyframe->T_cp();
    keyframe = keyframe->parent();
  }
  return {keyframe, T_ck};
}

void Tracker::PlaceFramesInAdjustedMap() {
  std::shared_lock lock(map_.mutex());
  for (FrameRecord& record : records_) {
    if (record.reference == nullptr || record.inliers.empty()) continue;
    const auto [reference, T_cr] = record.Resolved();
    const std::optional<core::Pose> T_cw =
        PlaceByInliers(map_, record.inliers, reference->keypoints().sensor(), T_cr * reference->T_cw());
    if (!T_cw) continue;
    record.reference = reference;
    record.T_cr = *T_cw * reference->T_wc();
  }
}

void Tracker::Follow(Frame& frame, const Placement& placement) {
  frame.T_cw = FollowKeyFrame(frame.T_cw, placement.keyframe_T_cw, placement.keyframe->T_cw());
}

void Tracker::StartInLoadedMap(bool localization) {
  state_ = TrackingState::kLost;
  localization_ = localization;
}

void Tracker::OpenNewMapWhenLostLong(const Frame& frame) {
  if (state_ != TrackingState::kLost || new_map_opened_ || localization_ || options_.new_map_after <= 0.0 ||
      !lost_since_ || frame.timestamp - *lost_since_ < options_.new_map_after) {
    return;
  }
  std::unique_lock lock(map_.mutex());
  const MapId map = map_.StartNewMap();
  new_map_opened_ = true;
  spdlog::debug("frame {}: lost for {:.2f} s, map {} opened", frame.id, frame.timestamp - *lost_since_, map);
}

void Tracker::RefreshLastFrame() {
  // In a loaded map no frame has been tracked at first: the first one is relocalised, as after a long loss.
  if (!standing_.last_frame) return;
  for (MapPoint*& p : standing_.last_frame->map_points) {
    if (p != nullptr) p = p->Current();
  }
  const KeyFrame* reference = standing_.last_record.reference;
  if (reference != nullptr && !reference->bad()) {
    standing_.last_frame->T_cw = standing_.last_record.T_cr * reference->T_cw();
  }
}

bool Tracker::Initialize(Frame& frame) {
  if (frame.keypoints->num_with_depth() < options_.min_initial_points) {
    spdlog::debug("frame {}: {} keypoints with depth, {} needed to start the map", frame.id,
                  frame.keypoints->num_with_depth(), options_.min_initial_points);
    return false;
  }
  frame.T_cw = core::Pose::Identity();
  ClearMatches(frame);
  KeyFrame* keyframe = map_.CreateKeyFrame(frame.id, frame.timestamp, frame.keypoints, frame.T_cw);
  const KeypointSet& keypoints = *frame.keypoints;
  for (int i = 0; i < keypoints.size(); ++i) {
    if (!keypoints.has_depth(i)) continue;
    frame.map_points[static_cast<std::size_t>(i)] = map_.CreateMapPoint(keypoints.Unproject(i), keyframe, i);
  }
  frame.reference_keyframe = keyframe;
  last_keyframe_ = standing_.reference_keyframe = keyframe;
  last_keyframe_timestamp_ = frame.timestamp;
  return true;
}

PoseHypothesis Tracker::TrackFollowing(const Frame& frame, const TrackingContext& context) const {
  PoseHypothesis best;
  if (context.motion->measured()) {
    best = searches_.WithMotionModel(frame, context);
    if (best.accepted() && !best.verdict.doubtful) return best;
  }
  // The prediction may have led to the wrong corners: the reference keyframe, and the pose more points back.
  best = Better(std::move(best), searches_.FromReferenceKeyFrame(frame, context));
  if (best.accepted()) return best;
  // Right after a relocalisation there is no motion yet, and the keyframe it found may see the place from afar:
  // the camera taken to stand still, the last frame's points are searched for where they were.
  if (!context.motion->measured()) {
    best = Better(std::move(best), searches_.WithMotionModel(frame, context));
    if (best.accepted()) return best;
  }
  // Too few matches for either (people fill the view): the map around the last frame, searched strictly.
  return Better(std::move(best), searches_.FromPrediction(frame, context));
}

PoseHypothesis Tracker::Recover(const Frame& frame, const TrackingContext& context, double gap) const {
  // After a short loss a pose found must lie where the camera could have gone since, moving on as it was: within the
  // spread its acceleration allows, ½ a τ² (half the soft prior's, which leaves room to be safe: χ² four times the
  // prior's). A pose in another map's world frame cannot be compared.
  const auto reachable = [&](const Frame& estimate) -> std::optional<double> {
    if (context.prior == nullptr || context.reference_keyframe == nullptr ||
        estimate.reference_keyframe->map_id() != context.reference_keyframe->map_id()) {
      return std::nullopt;
    }
    return 4.0 * PriorChi2(estimate.T_cw, *context.prior);
  };
  const double max_chi2 = options_.acceptance.max_motion_chi2;
  PoseHypothesis found;
  // Lost for a moment (people filled the view): the camera is most likely where it was heading.
  if (context.last != nullptr && gap <= options_.max_motion_gap) {
    found = searches_.FromPrediction(frame, context);
    if (found.accepted() && reachable(*found.frame).value_or(0.0) <= max_chi2) return found;
  }
  // Lost long, the frame may be in any map; else in the one it was tracked in.
  const std::optional<MapId> map = new_map_opened_ ? std::nullopt : std::optional(map_.active_map());
  const bow::ImageWords words = DescribePlace(vocabulary_, *frame.keypoints);
  PoseHypothesis relocalized;
  relocalized.method = TrackingMethod::kRelocalization;
  std::vector<RelocalizedPose> poses = relocalizer_.Relocalize(
      frame, words, relocalizer_.Candidates(words, context.reference_keyframe, map), relocalized.failure);
  // Of the places the frame looks like, the one the motion model allows most after a short loss; otherwise the best
  // backed, unless another place fits it about as well.
  std::optional<std::size_t> chosen;
  double best_chi2 = max_chi2;
  for (std::size_t p = 0; p < poses.size(); ++p) {
    const std::optional<double> chi2 = reachable(poses[p].frame);
    spdlog::debug("frame {}: relocalised by keyframe {} on {} inliers, χ² {:.1f} from the motion model's prediction",
                  frame.id, poses[p].frame.reference_keyframe->id(), poses[p].inliers, chi2.value_or(-1.0));
    if (chi2 && *chi2 <= best_chi2) {
      best_chi2 = *chi2;
      chosen = p;
    }
  }
  const bool comparable = std::any_of(poses.begin(), poses.end(), [&](const RelocalizedPose& p) {
    return reachable(p.frame).has_value();
  });
  if (!comparable && !poses.empty()) {
    if (poses.size() > 1 && relocalizer_.Ambiguous(poses[0], poses[1])) {
      spdlog::debug("frame {}: two places fit it alike ({} and {} inliers): neither is taken", frame.id,
                    poses[0].inliers, poses[1].inliers);
      relocalized.failure = TrackingFailure::kPoseRejected;
      relocalized.verdict.rejection = PoseRejection::kAmbiguous;
      return Better(std::move(found), std::move(relocalized));
    }
    chosen = 0;
  }
  if (!chosen) {
    if (!poses.empty()) {
      relocalized.failure = TrackingFailure::kPoseRejected;
      relocalized.verdict.rejection = PoseRejection::kAgainstMotion;
    }
    return Better(std::move(found), std::move(relocalized));
  }
  return searches_.ConfirmWithLocalMap(std::move(poses[*chosen].frame), TrackingMethod::kRelocalization, context);
}

std::vector<MapPoint*> Tracker::CountOnMapPoints(const PoseHypothesis& hypothesis, const Frame* last,
                                                 double gap) const {
  for (MapPoint* p : hypothesis.visible) p->IncreaseVisible();
  const Frame& frame = *hypothesis.frame;
  for (int i = 0; i < frame.size(); ++i) {
    if (frame.IsInlier(i)) frame.map_points[static_cast<std::size_t>(i)]->IncreaseFound();
  }
  std::vector<MapPoint*> moving;
  if (options_.moving_point_outliers == 0 || localization_) return moving;
  // Only a pose most matches agree with can accuse a point: on a weak frame the misfits may be the pose's fault.
  if (hypothesis.inliers < 2 * options_.acceptance.min_inliers || 2 * hypothesis.inliers < hypothesis.matched) {
    return moving;
  }
  // The share of the image motion since the last frame that falls between the colour and the depth image; a
  // depth taken apart from the colour after a loss (no motion known) accuses nothing.
  double delay_shift_per_pixel = 0.0;
  if (frame.depth_delay != 0.0) {
    if (last == nullptr || !(gap > 0.0) || gap > options_.max_motion_gap) return moving;
    delay_shift_per_pixel = std::abs(frame.depth_delay) / gap;
  }
  const RgbdCamera& camera = frame.keypoints->sensor().camera;
  for (int i = 0; i < frame.size(); ++i) {
    MapPoint* p = frame.map_points[static_cast<std::size_t>(i)];
    if (p == nullptr || p->bad()) continue;
    // A misfit: measured at a depth off by more than moving_point_depth of the predicted one. Where a matched
    // point is seen in the image cannot tell: the search by projection only matches it within a few pixels of
    // its prediction, so a moving point is either found nearly in place (and within the pose optimiser's bound)
    // or not at all; a wrong match to a similar corner nearby misfits again and again on a static point. Depth is
    // measured, not searched.
    if (!frame.keypoints->has_depth(i)) continue;
    const Eigen::Vector3d p_c = frame.T_cw * p->position();
    if (!(p_c.z() > 0.0)) continue;
    if (delay_shift_per_pixel > 0.0) {
      const Eigen::Vector3d p_last = last->T_cw * p->position();
      if (!(p_last.z() > 0.0)) continue;
      const double shift = (camera.Project(p_c) - camera.Project(p_last)).norm() * delay_shift_per_pixel;
      if (shift > options_.moving_point_max_delay_shift) continue;
    }
    const bool misfit = std::abs(frame.keypoints->depth(i) - p_c.z()) > options_.moving_point_depth * p_c.z();
    if (p->RecordOutlier(misfit) >= options_.moving_point_outliers) moving.push_back(p);
  }
  return moving;
}

bool Tracker::NeedNewKeyFrame(const Frame& frame, int inliers) const {
  const KeyFrame* reference = standing_.reference_keyframe;
  if (reference == nullptr) return false;  // the first frame found in a loaded map: nothing to compare
  KeyFrameDecisionInput input;
  input.mapper_paused = local_mapper_.Paused();
  input.mapper_idle = local_mapper_.Idle();
  input.mapper_queued = static_cast<int>(local_mapper_.Queued());
  input.map_keyframes = static_cast<int>(map_.NumKeyFrames(map_.active_map()));
  input.inliers = inliers;
  input.reference_points = reference->NumTrackedPoints(input.map_keyframes <= 2 ? 2 : 3);
  const KeypointSet& keypoints = *frame.keypoints;
  for (int i = 0; i < keypoints.size(); ++i) {
    if (!keypoints.has_depth(i) || keypoints.depth(i) >= keypoints.sensor().close_depth) continue;
    ++(frame.IsInlier(i) ? input.close_tracked : input.close_untracked);
  }
  input.since_keyframe = frame.timestamp - last_keyframe_timestamp_;
  return slam::NeedNewKeyFrame(input, options_.keyframes);
}

void Tracker::CreateKeyFrame(Frame& frame) {
  KeyFrame* keyframe = map_.CreateKeyFrame(frame.id, frame.timestamp, frame.keypoints, frame.T_cw);
  for (int i = 0; i < frame.size(); ++i) {
    MapPoint* p = frame.map_points[static_cast<std::size_t>(i)];
    if (p != nullptr && !p->bad() && frame.outlier[static_cast<std::size_t>(i)] == 0 && p->IndexIn(keyframe) < 0) {
      map_.AddObservation(p, keyframe, i);
    }
  }
  // New points from depth, nearest first: every close keypoint, and far ones until keyframe_min_new_points.
  const KeypointSet& keypoints = *frame.keypoints;
  std::vector<int> with_depth;
  for (int i = 0; i < keypoints.size(); ++i) {
    if (keypoints.has_depth(i)) with_depth.push_back(i);
  }
  std::stable_sort(with_depth.begin(), with_depth.end(),
                   [&](int a, int b) { return keypoints.depth(a) < keypoints.depth(b); });
  const core::Pose T_wc = frame.T_cw.inverse();
  int points = 0;
  for (const int i : with_depth) {
    const auto k = static_cast<std::size_t>(i);
    if (keyframe->map_point(i) == nullptr) {
      frame.map_points[k] = map_.CreateMapPoint(T_wc * keypoints.Unproject(i), keyframe, i);
      frame.outlier[k] = 0;
    }
    ++points;
    if (keypoints.depth(i) > keypoints.sensor().close_depth && points > options_.keyframe_min_new_points) break;
  }
  frame.reference_keyframe = keyframe;
  last_keyframe_ = keyframe;
  last_keyframe_timestamp_ = frame.timestamp;
}

}  // namespace hoidslam::slam
