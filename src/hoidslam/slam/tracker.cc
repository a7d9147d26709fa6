#include "hoidslam/slam/tracker.h"

#include <algorithm>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <shared_mutex>
#include <unordered_set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/features2d.hpp>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/slam/match/matcher.h"

namespace hoidslam::slam {
namespace {

constexpr core::EnumNames<TrackingState, 3> kStateNames = {{
    {TrackingState::kNotInitialized, "not_initialized"},
    {TrackingState::kOk, "ok"},
    {TrackingState::kLost, "lost"},
}};
constexpr core::EnumNames<TrackingMethod, 5> kMethodNames = {{
    {TrackingMethod::kNone, "none"},
    {TrackingMethod::kInitialization, "initialization"},
    {TrackingMethod::kMotionModel, "motion_model"},
    {TrackingMethod::kReferenceKeyFrame, "reference_keyframe"},
    {TrackingMethod::kRelocalization, "relocalization"},
}};
constexpr core::EnumNames<TrackingFailure, 4> kFailureNames = {{
    {TrackingFailure::kNone, "none"},
    {TrackingFailure::kTooFewKeypoints, "too_few_keypoints"},
    {TrackingFailure::kTooFewMatches, "too_few_matches"},
    {TrackingFailure::kPoseRejected, "pose_rejected"},
}};

// Matches needed before a pose optimisation is worth trying, and inliers after it for the first estimate.
constexpr int kMinProjectionMatches = 20;
constexpr int kMinDescriptorMatches = 15;
constexpr int kMinFirstEstimateInliers = 10;

int CountMatches(const Frame& frame) {
  return static_cast<int>(std::count_if(frame.map_points.begin(), frame.map_points.end(),
                                        [](const MapPoint* p) { return p != nullptr; }));
}

// The motion `T` that took `seconds`, continued at the same rate for `elapsed` seconds (rotation about the same
// axis, translation in proportion). Up to 4 times the measured interval: beyond that constant velocity means little.
core::Pose ScaleMotion(const core::Pose& T, double seconds, double elapsed) {
  if (!(seconds > 0.0) || !(elapsed > 0.0)) return T;
  const double ratio = std::min(elapsed / seconds, 4.0);
  const Eigen::AngleAxisd rotation(T.linear());
  core::Pose scaled = core::Pose::Identity();
  scaled.linear() = Eigen::AngleAxisd(rotation.angle() * ratio, rotation.axis()).toRotationMatrix();
  scaled.translation() = T.translation() * ratio;
  return scaled;
}

void ClearMatches(Frame& frame) {
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  std::fill(frame.outlier.begin(), frame.outlier.end(), 0);
}

// The points of `keyframes` that the frame has not matched yet and that project into it at frame.T_cw, within
// their scale range and viewing angle: each once, in the keyframes' order.
std::vector<ProjectedPoint> PointsInView(const std::vector<KeyFrame*>& keyframes, const Frame& frame) {
  std::unordered_set<const MapPoint*> considered(frame.map_points.begin(), frame.map_points.end());
  std::vector<ProjectedPoint> projected;
  const Sensor& sensor = frame.keypoints->sensor();
  for (const KeyFrame* keyframe : keyframes) {
    for (MapPoint* p : keyframe->map_points()) {
      if (p == nullptr || p->bad() || !considered.insert(p).second) continue;
      ProjectedPoint candidate;
      if (ProjectIntoFrame(*p, frame.T_cw, sensor, 0.5, candidate)) projected.push_back(candidate);
    }
  }
  return projected;
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
  const auto positive = [](double value, const char* name) {
    if (!(value > 0.0)) throw core::InputError::ForParameter(name, fmt::format("must be > 0, got {}", value));
  };
  positive(min_initial_points, "Tracking.minInitialPoints");
  positive(motion_search_radius, "Tracking.motionSearchRadius");
  positive(local_search_radius, "Tracking.localSearchRadius");
  positive(min_inliers, "Tracking.minInliers");
  positive(min_inliers_after_relocalization, "Tracking.minInliersAfterRelocalization");
  positive(max_local_keyframes, "Tracking.maxLocalKeyFrames");
  positive(keyframe_max_interval, "Tracking.keyFrameMaxInterval");
  positive(relocalization_candidates, "Tracking.relocalizationCandidates");
  positive(keyframe_min_new_points, "Tracking.keyFrameMinNewPoints");
  positive(moving_point_depth, "Tracking.movingPointDepth");
  positive(min_inliers_floor, "Tracking.minInliersFloor");
  positive(max_motion_gap, "Tracking.maxMotionGap");
  positive(reach_distance, "Tracking.reachDistance");
  positive(max_camera_speed, "Tracking.maxCameraSpeed");
  positive(reach_angle_deg, "Tracking.reachAngle");
  positive(max_camera_turn_rate_deg, "Tracking.maxCameraTurnRate");
  const auto not_negative = [](double value, const char* name) {
    if (!(value >= 0.0)) {
      throw core::InputError::ForParameter(name, fmt::format("must be >= 0 (0: off), got {}", value));
    }
  };
  not_negative(motion_prior_acceleration, "Tracking.motionPriorAcceleration");
  not_negative(motion_prior_angular_acceleration_deg, "Tracking.motionPriorAngularAcceleration");
  if (!(new_map_after >= 0.0)) {
    throw core::InputError::ForParameter("Tracking.newMapAfter",
                                         fmt::format("must be >= 0 seconds (0: never), got {}", new_map_after));
  }
  const auto in_unit = [](double value, const char* name) {
    if (!(value > 0.0 && value <= 1.0)) {
      throw core::InputError::ForParameter(name, fmt::format("must be in (0, 1], got {}", value));
    }
  };
  in_unit(min_inlier_share, "Tracking.minInlierShare");
  in_unit(min_inlier_ratio, "Tracking.minInlierRatio");
  in_unit(doubtful_inlier_ratio, "Tracking.doubtfulInlierRatio");
  in_unit(supported_inlier_ratio, "Tracking.supportedInlierRatio");
  if (!(close_inlier_weight >= 1.0 && close_inlier_weight <= 3.0)) {
    throw core::InputError::ForParameter("Tracking.closeInlierWeight",
                                         fmt::format("must be in [1, 3], got {}", close_inlier_weight));
  }
  if (moving_point_outliers < 0) {
    throw core::InputError::ForParameter("Tracking.movingPointOutliers",
                                         fmt::format("must be >= 0 (0: off), got {}", moving_point_outliers));
  }
}

Tracker::Tracker(Map& map, const bow::Vocabulary& vocabulary, LocalMapper& local_mapper,
                 const TrackerOptions& options)
    : map_(map), vocabulary_(vocabulary), local_mapper_(local_mapper), options_(options) {
  options_.Check();
}

TrackResult Tracker::Track(Frame frame) {
  TrackResult result;
  result.keypoints = frame.size();
  TrackingFailure failure = TrackingFailure::kNone;
  bool make_keyframe = false;
  Placement placement;
  OpenNewMapWhenLostLong(frame);
  // Tries a first estimate, then confirms it against the local map.
  const auto attempt = [&](TrackingMethod method, TrackingFailure first_estimate) {
    failure = first_estimate;
    if (failure != TrackingFailure::kNone) return false;
    result.method = method;
    failure = TrackLocalMap(frame, result);
    return failure == TrackingFailure::kNone;
  };
  bool ok = false;
  {
    std::shared_lock lock(map_.mutex());
    if (state_ == TrackingState::kNotInitialized) {
      // Initialisation writes the map: done below under the exclusive lock.
    } else {
      // Local mapping may have fused points the last tracked frame matched, or moved its reference keyframe. (In a
      // loaded map no frame has been tracked at first: the first one is relocalised, as after a long loss.)
      if (last_frame_) {
        for (MapPoint*& p : last_frame_->map_points) {
          if (p != nullptr) p = p->Current();
        }
        if (last_record_.reference != nullptr && !last_record_.reference->bad()) {
          last_frame_->T_cw = last_record_.T_cr * last_record_.reference->T_cw();
        }
      }
      const double gap = last_frame_ ? frame.timestamp - last_frame_->timestamp
                                     : std::numeric_limits<double>::infinity();
      motion_prior_ = gap <= options_.max_motion_gap ? MotionPrior(frame) : std::nullopt;
      if (state_ == TrackingState::kOk) {
        const bool just_relocalized =
            last_relocalization_frame_id_ && frame.id <= *last_relocalization_frame_id_ + 2;
        if (velocity_ && !just_relocalized) ok = attempt(TrackingMethod::kMotionModel, TrackWithMotionModel(frame));
        // A pose most of the local map contradicts may be the prediction's mistake: the reference keyframe is tried
        // as well, and the pose more points agree with is kept.
        if (ok && result.inliers < options_.doubtful_inlier_ratio * result.matched) {
          const Frame predicted = frame;
          const TrackResult predicted_result = result;
          const std::vector<MapPoint*> predicted_moving = moving_points_;
          if (!attempt(TrackingMethod::kReferenceKeyFrame, TrackReferenceKeyFrame(frame)) ||
              result.inliers <= predicted_result.inliers) {
            frame = predicted;
            result = predicted_result;
            moving_points_ = predicted_moving;
            failure = TrackingFailure::kNone;
          }
        }
        // The prediction may have led to a wrong pose that the local map does not confirm: start again from the
        // reference keyframe before giving the frame up.
        if (!ok) ok = attempt(TrackingMethod::kReferenceKeyFrame, TrackReferenceKeyFrame(frame));
        // Right after a relocalisation there is no motion yet, and the keyframe it found may see the place from
        // afar: the camera taken to stand still, the last frame's points are searched for where they were.
        if (!ok && !velocity_) ok = attempt(TrackingMethod::kMotionModel, TrackWithMotionModel(frame));
        // Too few matches for either (people fill the view): the map around the last frame, searched strictly.
        if (!ok) ok = attempt(TrackingMethod::kMotionModel, TrackFromPrediction(frame));
      } else {
        // Lost for a moment (people filled the view): the camera is most likely where it was heading.
        if (gap <= options_.max_motion_gap) ok = attempt(TrackingMethod::kMotionModel, TrackFromPrediction(frame));
        if (!ok) {
          const TrackingFailure found = Relocalize(frame);
          if (found == TrackingFailure::kNone) last_relocalization_frame_id_ = frame.id;
          ok = attempt(TrackingMethod::kRelocalization, found);
        }
      }
      if (ok) {
        // The motion since the last tracked frame; over a long loss it says nothing of the next frame.
        if (gap <= options_.max_motion_gap && result.method != TrackingMethod::kRelocalization) {
          velocity_ = frame.T_cw * last_frame_->T_cw.inverse();
          velocity_seconds_ = gap;
        } else {
          velocity_.reset();
        }
        make_keyframe = !localization_ && NeedNewKeyFrame(frame, result.inliers);
        placement = PlaceAgainst(frame.reference_keyframe != nullptr ? frame.reference_keyframe : reference_keyframe_);
      }
    }
  }
  if (!moving_points_.empty()) {
    std::unique_lock lock(map_.mutex());
    for (MapPoint* p : moving_points_) map_.ErasePoint(p);
    for (MapPoint*& p : frame.map_points) {
      if (p != nullptr && p->bad()) p = nullptr;
    }
    result.moving_points = static_cast<int>(moving_points_.size());
    moving_points_.clear();
  }
  if (state_ == TrackingState::kNotInitialized || (!ok && new_map_opened_)) {
    // The first map, or a new one: the frame was not found in any map.
    std::unique_lock lock(map_.mutex());
    ok = Initialize(frame);
    if (ok) {
      placement = PlaceAgainst(frame.reference_keyframe);
      result.method = TrackingMethod::kInitialization;
      result.keyframe = true;
      result.matched = result.inliers = frame.keypoints->num_with_depth();
      local_mapper_.Insert(last_keyframe_);
      velocity_.reset();
      new_map_opened_ = false;
    }
  } else if (ok && new_map_opened_) {
    // Found again in a map: tracking goes on there, and the new map, still empty, is forgotten.
    std::unique_lock lock(map_.mutex());
    map_.ActivateMap((frame.reference_keyframe != nullptr ? frame.reference_keyframe : reference_keyframe_)->map_id());
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

  if (ok) {
    state_ = TrackingState::kOk;
    if (frame.reference_keyframe == nullptr) frame.reference_keyframe = reference_keyframe_;
    reference_keyframe_ = frame.reference_keyframe;
    {
      // Local mapping's bundle adjustment may be moving the reference keyframe right now, and loop closing may have
      // moved it since the frame was tracked.
      std::shared_lock lock(map_.mutex());
      Follow(frame, placement);
      records_.push_back({frame.timestamp, reference_keyframe_, frame.T_cw * reference_keyframe_->T_wc()});
      result.map = reference_keyframe_->map_id();
    }
    result.T_cw = frame.T_cw;
    lost_since_.reset();
    last_record_ = records_.back();
    // The next frame searches from this one's inliers only.
    for (int i = 0; i < frame.size(); ++i) {
      if (frame.outlier[static_cast<std::size_t>(i)] != 0) frame.map_points[static_cast<std::size_t>(i)] = nullptr;
    }
    last_frame_ = std::move(frame);
  } else {
    if (state_ == TrackingState::kOk) state_ = TrackingState::kLost;
    if (state_ == TrackingState::kLost && !lost_since_) lost_since_ = frame.timestamp;
    records_.push_back({frame.timestamp, nullptr, core::Pose::Identity()});
    if (state_ == TrackingState::kLost) {
      result.failure = frame.size() < options_.min_inliers_floor ? TrackingFailure::kTooFewKeypoints : failure;
    }
  }
  result.state = state_;
  return result;
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

bool Tracker::Initialize(Frame& frame) {
  if (frame.keypoints->num_with_depth() < options_.min_initial_points) {
    spdlog::debug("frame {}: {} keypoints with depth, {} needed to start the map", frame.id,
                  frame.keypoints->num_with_depth(), options_.min_initial_points);
    return false;
  }
  frame.T_cw = core::Pose::Identity();
  KeyFrame* keyframe = map_.CreateKeyFrame(frame.id, frame.timestamp, frame.keypoints, frame.T_cw);
  const KeypointSet& keypoints = *frame.keypoints;
  for (int i = 0; i < keypoints.size(); ++i) {
    if (!keypoints.has_depth(i)) continue;
    frame.map_points[static_cast<std::size_t>(i)] = map_.CreateMapPoint(keypoints.Unproject(i), keyframe, i);
  }
  frame.reference_keyframe = keyframe;
  last_keyframe_ = reference_keyframe_ = keyframe;
  last_keyframe_frame_id_ = frame.id;
  return true;
}

double Tracker::PredictPose(Frame& frame) const {
  const Frame& last = *last_frame_;
  const double elapsed = frame.timestamp - last.timestamp;
  if (!velocity_) {
    frame.T_cw = last.T_cw;
    return 0.0;
  }
  frame.T_cw = Predicted(elapsed);
  return velocity_seconds_ > 0.0 ? std::clamp(elapsed / velocity_seconds_, 1.0, 4.0) : 1.0;
}

core::Pose Tracker::Predicted(double elapsed) const {
  return ScaleMotion(*velocity_, velocity_seconds_, elapsed) * last_frame_->T_cw;
}

std::optional<PosePrior> Tracker::MotionPrior(const Frame& frame) const {
  const double elapsed = frame.timestamp - last_frame_->timestamp;
  if (!velocity_ || !(elapsed > 0.0) || options_.motion_prior_acceleration <= 0.0 ||
      options_.motion_prior_angular_acceleration_deg <= 0.0) {
    return std::nullopt;
  }
  PosePrior prior;
  prior.T_cw = Predicted(elapsed);
  const double sigma_turn =
      options_.motion_prior_angular_acceleration_deg * std::numbers::pi / 180.0 * elapsed * elapsed;
  const double sigma_step = options_.motion_prior_acceleration * elapsed * elapsed;
  prior.information.diagonal() << Eigen::Vector3d::Constant(1.0 / (sigma_turn * sigma_turn)),
      Eigen::Vector3d::Constant(1.0 / (sigma_step * sigma_step));
  return prior;
}

TrackingFailure Tracker::TrackWithMotionModel(Frame& frame) {
  const Frame& last = *last_frame_;
  // After frames were lost the prediction is rougher: the window grows with them, as far as the motion is scaled.
  const double radius = options_.motion_search_radius * std::max(1.0, PredictPose(frame));
  ClearMatches(frame);
  int matches = SearchByProjection(frame, last, radius);
  if (matches < kMinProjectionMatches) {
    ClearMatches(frame);
    matches = SearchByProjection(frame, last, 2.0 * radius);
  }
  if (matches < kMinProjectionMatches) return TrackingFailure::kTooFewMatches;
  const int inliers = OptimizeFramePose(frame, options_.pose_optimizer, true, MotionPriorOrNull());
  spdlog::debug("frame {}: motion model: {} matches, {} inliers", frame.id, matches, inliers);
  return inliers >= kMinFirstEstimateInliers ? TrackingFailure::kNone : TrackingFailure::kPoseRejected;
}

TrackingFailure Tracker::TrackFromPrediction(Frame& frame) {
  const Frame& last = *last_frame_;
  const double elapsed = frame.timestamp - last.timestamp;
  // Without a measured motion the camera may have gone anywhere near: the widest window.
  const double predicted = PredictPose(frame);
  const double frames = predicted > 0.0 ? predicted : 4.0;
  // The last tracked frame kept few points (the crowd had already come), so the map around it is searched: the
  // points of the keyframes that see its points, and of their neighbours (its local map), where the prediction
  // puts them. Its reference keyframe, made amid the crowd, may hold few. Most of them are hidden by the people:
  // only close descriptors are taken, and RANSAC keeps those that agree on a pose.
  KeyFrame* most_shared = nullptr;
  ClearMatches(frame);
  const std::vector<ProjectedPoint> projected = PointsInView(LocalKeyFrames(last, most_shared), frame);
  const int matches =
      SearchByProjection(frame, projected, options_.motion_search_radius * frames, kDescriptorDistanceLow);
  if (matches < kMinFirstEstimateInliers) return TrackingFailure::kTooFewMatches;
  const int consistent = EstimatePoseRansac(frame);
  const int inliers = consistent < kMinFirstEstimateInliers
                           ? 0
                           : OptimizeFramePose(frame, options_.pose_optimizer, true, MotionPriorOrNull());
  spdlog::debug("frame {}: prediction after {:.2f} s: {} matches, {} consistent, {} inliers", frame.id, elapsed,
                matches, consistent, inliers);
  // RANSAC may settle anywhere the matches agree: only a pose the camera could have reached is taken.
  return inliers >= kMinFirstEstimateInliers && WithinReach(frame) ? TrackingFailure::kNone
                                                                   : TrackingFailure::kPoseRejected;
}

TrackingFailure Tracker::TrackReferenceKeyFrame(Frame& frame) {
  if (reference_keyframe_ == nullptr || reference_keyframe_->bad()) return TrackingFailure::kTooFewMatches;
  ClearMatches(frame);
  const int matches = SearchByDescriptor(*reference_keyframe_, frame, frame.map_points);
  frame.T_cw = last_frame_->T_cw;
  if (matches < kMinDescriptorMatches) return TrackingFailure::kTooFewMatches;
  const int inliers = OptimizeFramePose(frame, options_.pose_optimizer, true, MotionPriorOrNull());
  spdlog::debug("frame {}: reference keyframe {}: {} matches, {} inliers", frame.id, reference_keyframe_->id(),
                matches, inliers);
  return inliers >= kMinFirstEstimateInliers ? TrackingFailure::kNone : TrackingFailure::kPoseRejected;
}

std::vector<KeyFrame*> Tracker::LocalKeyFrames(const Frame& frame, KeyFrame*& most_shared) const {
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

bool Tracker::Accepted(const Frame& frame, int inliers, int matched, int min_inliers) const {
  if (inliers < options_.min_inlier_ratio * matched) return false;
  if (inliers >= min_inliers) return true;
  double support = 0.0;
  const KeypointSet& keypoints = *frame.keypoints;
  for (int i = 0; i < frame.size(); ++i) {
    if (!frame.IsInlier(i)) continue;
    const bool close = keypoints.has_depth(i) && keypoints.depth(i) < keypoints.sensor().close_depth;
    support += close ? options_.close_inlier_weight : 1.0;
  }
  const int needed = std::clamp(static_cast<int>(std::ceil(options_.min_inlier_share * frame.size())),
                                std::min(options_.min_inliers_floor, min_inliers), min_inliers);
  return support >= needed && inliers >= options_.supported_inlier_ratio * matched;
}

TrackingFailure Tracker::TrackLocalMap(Frame& frame, TrackResult& result) {
  const std::vector<KeyFrame*> local_keyframes = LocalKeyFrames(frame, frame.reference_keyframe);
  for (MapPoint* p : frame.map_points) {
    if (p != nullptr && !p->bad()) p->IncreaseVisible();
  }
  const std::vector<ProjectedPoint> projected = PointsInView(local_keyframes, frame);
  for (const ProjectedPoint& candidate : projected) candidate.point->IncreaseVisible();
  const bool recently_relocalized = last_relocalization_frame_id_ && frame.id < *last_relocalization_frame_id_ + 2;
  const int found = SearchByProjection(frame, projected, recently_relocalized ? 5.0 : options_.local_search_radius);
  spdlog::debug("frame {}: local map: {} keyframes, {} points in view, {} found", frame.id, local_keyframes.size(),
                projected.size(), found);

  result.matched = CountMatches(frame);
  // A relocalised pose owes nothing to the last frame; any other is held where the camera was heading.
  const PosePrior* prior = result.method == TrackingMethod::kRelocalization ? nullptr : MotionPriorOrNull();
  result.inliers = OptimizeFramePose(frame, options_.pose_optimizer, false, prior);
  for (int i = 0; i < frame.size(); ++i) {
    if (frame.IsInlier(i)) frame.map_points[static_cast<std::size_t>(i)]->IncreaseFound();
  }
  spdlog::debug("frame {}: local map: {} matched, {} inliers", frame.id, result.matched, result.inliers);
  FindMovingPoints(frame, result);
  const bool relocalized_lately =
      last_relocalization_frame_id_ &&
      frame.id < *last_relocalization_frame_id_ + static_cast<std::uint64_t>(options_.keyframe_max_interval);
  const int min_inliers = relocalized_lately ? options_.min_inliers_after_relocalization : options_.min_inliers;
  if (Accepted(frame, result.inliers, result.matched, min_inliers)) return TrackingFailure::kNone;
  return result.matched < std::min(options_.min_inliers_floor, min_inliers) ? TrackingFailure::kTooFewMatches
                                                                            : TrackingFailure::kPoseRejected;
}

void Tracker::FindMovingPoints(const Frame& frame, const TrackResult& result) {
  moving_points_.clear();
  if (options_.moving_point_outliers == 0 || localization_) return;
  // Only a pose most matches agree with can accuse a point: on a weak frame the misfits may be the pose's fault.
  if (result.inliers < 2 * options_.min_inliers || 2 * result.inliers < result.matched) return;
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
    const bool misfit = std::abs(frame.keypoints->depth(i) - p_c.z()) > options_.moving_point_depth * p_c.z();
    if (p->RecordOutlier(misfit) >= options_.moving_point_outliers) moving_points_.push_back(p);
  }
}

bool Tracker::NeedNewKeyFrame(const Frame& frame, int inliers) const {
  if (local_mapper_.Paused()) return false;  // a loop is being corrected
  if (reference_keyframe_ == nullptr) return false;  // the first frame found in a loaded map: nothing to compare
  const std::size_t keyframes = map_.NumKeyFrames(map_.active_map());
  const auto max_interval = static_cast<std::uint64_t>(options_.keyframe_max_interval);
  // Right after relocalising, wait for the map to be trusted again.
  if (last_relocalization_frame_id_ && frame.id < *last_relocalization_frame_id_ + max_interval &&
      keyframes > max_interval) {
    return false;
  }
  const int min_observations = keyframes <= 2 ? 2 : 3;
  const int reference_points = reference_keyframe_->NumTrackedPoints(min_observations);
  const bool mapper_idle = local_mapper_.Idle();

  // Close keypoints tracked and not tracked: many untracked close ones mean new structure worth mapping.
  const KeypointSet& keypoints = *frame.keypoints;
  int tracked_close = 0, untracked_close = 0;
  for (int i = 0; i < keypoints.size(); ++i) {
    if (!keypoints.has_depth(i) || keypoints.depth(i) >= keypoints.sensor().close_depth) continue;
    if (frame.IsInlier(i)) {
      ++tracked_close;
    } else {
      ++untracked_close;
    }
  }
  const bool need_close = tracked_close < 100 && untracked_close > 70;
  const double reference_ratio = keyframes < 2 ? 0.4 : 0.75;

  const bool interval_passed = frame.id >= last_keyframe_frame_id_ + max_interval;
  const bool weak = inliers < 0.25 * reference_points || need_close;
  const bool fewer_than_reference = (inliers < reference_ratio * reference_points || need_close) && inliers > 15;
  if (!((interval_passed || mapper_idle || weak) && fewer_than_reference)) return false;
  return mapper_idle || local_mapper_.Queued() < 3;
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
  last_keyframe_frame_id_ = frame.id;
}

int Tracker::EstimatePoseRansac(Frame& frame) {
  const KeypointSet& keypoints = *frame.keypoints;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  std::vector<int> index;
  for (int i = 0; i < frame.size(); ++i) {
    const MapPoint* p = frame.map_points[static_cast<std::size_t>(i)];
    if (p == nullptr) continue;
    object.emplace_back(p->position().x(), p->position().y(), p->position().z());
    image.emplace_back(keypoints.undistorted(i).x(), keypoints.undistorted(i).y());
    index.push_back(i);
  }
  if (object.size() < 4) return 0;
  const core::CameraIntrinsics& intrinsics = keypoints.sensor().intrinsics;
  const cv::Matx33d K(intrinsics.fx, 0, intrinsics.cx, 0, intrinsics.fy, intrinsics.cy, 0, 0, 1);
  // OpenCV's RANSAC draws its samples from its own generator, seeded the same on every call: deterministic.
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, 300, 4.0F, 0.99, inliers,
                          cv::SOLVEPNP_EPNP)) {
    return 0;
  }
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  cv::cv2eigen(R, rotation);
  cv::cv2eigen(tvec, translation);
  frame.T_cw.linear() = rotation;
  frame.T_cw.translation() = translation;
  std::vector<MapPoint*> kept(frame.map_points.size(), nullptr);
  for (const int k : inliers) {
    const auto i = static_cast<std::size_t>(index[static_cast<std::size_t>(k)]);
    kept[i] = frame.map_points[i];
  }
  frame.map_points = std::move(kept);
  return static_cast<int>(inliers.size());
}

bool Tracker::WithinReach(const Frame& frame) const {
  if (!last_frame_) return true;  // the first frame in a loaded map may be anywhere in it
  const Frame& last = *last_frame_;
  const double gap = frame.timestamp - last.timestamp;
  if (gap > options_.max_motion_gap) return true;  // time enough to have gone anywhere
  const core::Pose motion = frame.T_cw * last.T_cw.inverse();  // its translation: between the camera centres
  const double turn_deg = core::RotationAngleDegrees(motion.linear());
  return motion.translation().norm() <= options_.reach_distance + options_.max_camera_speed * gap &&
         turn_deg <= options_.reach_angle_deg + options_.max_camera_turn_rate_deg * gap;
}

TrackingFailure Tracker::Relocalize(Frame& frame) {
  const KeypointSet& keypoints = *frame.keypoints;
  if (keypoints.size() < kMinDescriptorMatches) return TrackingFailure::kTooFewMatches;
  // Candidates: the keyframe tracking last relied on and its neighbours (most losses are short), then the keyframes
  // that look most like the frame by their bags of words, from anywhere in the map; tried in order of how many of
  // their points the frame's descriptors match.
  std::vector<KeyFrame*> candidates;
  std::unordered_set<const KeyFrame*> included;
  const auto consider = [&](KeyFrame* keyframe) {
    if (keyframe != nullptr && !keyframe->bad() && included.insert(keyframe).second) candidates.push_back(keyframe);
  };
  if (reference_keyframe_ != nullptr) {
    consider(reference_keyframe_);
    for (KeyFrame* neighbour : reference_keyframe_->BestCovisibles(10)) consider(neighbour);
  }
  const bow::ImageWords words = DescribePlace(vocabulary_, keypoints);
  // Lost long, the frame may be in any map; else in the one it was tracked in.
  const std::optional<MapId> map = new_map_opened_ ? std::nullopt : std::optional(map_.active_map());
  for (KeyFrame* keyframe : map_.database().RelocalizationCandidates(
           words.bow, static_cast<std::size_t>(options_.relocalization_candidates), map)) {
    consider(keyframe);
  }
  if (candidates.empty()) return TrackingFailure::kTooFewMatches;

  std::vector<std::pair<int, std::size_t>> ranked;  // (matches, index into candidates)
  std::vector<std::vector<MapPoint*>> candidate_matches(candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    // Guided by the vocabulary's tree; a keyframe local mapping has not described yet, by every descriptor.
    const KeyFrame& candidate = *candidates[c];
    const int matches = candidate.words().features.empty()
                            ? SearchByDescriptor(candidate, frame, candidate_matches[c], 0.75F)
                            : SearchByBoW(candidate, frame, words.features, candidate_matches[c], 0.75F);
    if (matches >= kMinDescriptorMatches) ranked.emplace_back(matches, c);
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });

  for (const auto& [matches, c] : ranked) {
    KeyFrame* candidate = candidates[c];
    ClearMatches(frame);
    frame.map_points = candidate_matches[c];
    spdlog::debug("frame {}: relocalisation candidate keyframe {}: {} matches", frame.id, candidate->id(), matches);

    const int consistent = EstimatePoseRansac(frame);
    if (consistent < kMinFirstEstimateInliers) continue;
    int good = OptimizeFramePose(frame, options_.pose_optimizer, true);
    if (good < kMinFirstEstimateInliers) continue;
    if (good < options_.min_inliers_after_relocalization) {
      // More matches from the candidate's points projected with the estimate.
      std::vector<ProjectedPoint> projected;
      for (MapPoint* p : candidate->map_points()) {
        ProjectedPoint candidate_point;
        if (p != nullptr && !p->bad() &&
            std::find(frame.map_points.begin(), frame.map_points.end(), p) == frame.map_points.end() &&
            ProjectIntoFrame(*p, frame.T_cw, keypoints.sensor(), 0.0, candidate_point)) {
          projected.push_back(candidate_point);
        }
      }
      SearchByProjection(frame, projected, 4.0);
      good = OptimizeFramePose(frame, options_.pose_optimizer, true);
    }
    spdlog::debug("frame {}: relocalisation candidate keyframe {}: {} PnP inliers, {} after optimisation", frame.id,
                  candidate->id(), consistent, good);
    if (good < options_.min_inliers_after_relocalization) continue;
    // (The reach is measured in the last frame's map: a pose in another map's world frame cannot be compared.)
    const bool same_map = reference_keyframe_ == nullptr || candidate->map_id() == reference_keyframe_->map_id();
    if (same_map && !WithinReach(frame)) {
      spdlog::debug("frame {}: relocalisation candidate keyframe {}: out of the camera's reach", frame.id,
                    candidate->id());
      continue;
    }
    frame.reference_keyframe = candidate;
    return TrackingFailure::kNone;
  }
  ClearMatches(frame);
  return ranked.empty() ? TrackingFailure::kTooFewMatches : TrackingFailure::kPoseRejected;
}

}  // namespace hoidslam::slam
