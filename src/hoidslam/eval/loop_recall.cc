#include "hoidslam/eval/loop_recall.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {
namespace {

// A keyframe with its estimated pose and the true one at its stamp.
struct Keyframe {
  double timestamp = 0.0;
  core::Pose T_true;
  core::Pose T_estimate;
};

// Where a true pose returned to: the keyframe it is nearest, and how near.
struct Place {
  std::size_t keyframe = 0;
  double score = 0.0;     // distance / max_return_distance + angle / max_return_angle_deg: 0 where they coincide
  double distance = 0.0;  // metres
};

// The keyframe (of `keyframes`, sorted by time) at least min_separation older than `timestamp` whose true pose is
// within both limits of `T_true` and nearest it, if any.
std::optional<Place> NearestPlace(const core::Pose& T_true, double timestamp, const std::vector<Keyframe>& keyframes,
                                  const LoopRecallOptions& options) {
  std::optional<Place> nearest;
  for (std::size_t j = 0; j < keyframes.size() && keyframes[j].timestamp < timestamp &&
                          timestamp - keyframes[j].timestamp >= options.min_separation;
       ++j) {
    const core::Pose T = keyframes[j].T_true.inverse() * T_true;
    const double distance = T.translation().norm();
    const double angle = core::RotationAngleDegrees(T.linear());
    if (distance > options.max_return_distance || angle > options.max_return_angle_deg) continue;
    const double score = distance / options.max_return_distance + angle / options.max_return_angle_deg;
    if (!nearest || score < nearest->score) nearest = Place{j, score, distance};
  }
  return nearest;
}

// Whether the camera's true path between two returning keyframes (stamps on the estimate's clock) kept returning,
// never longer than event_gap away from every keyframe it could return to. Judged on the path, not on keyframes
// alone: on a return a system that finds its map makes few keyframes, seconds apart.
bool KeptReturning(const core::Trajectory& gt, const std::vector<double>& gt_stamps, double from, double to,
                   const std::vector<Keyframe>& keyframes, const AssociationOptions& association,
                   const LoopRecallOptions& options) {
  if (to - from <= options.event_gap) return true;
  double last = from;  // the latest moment known to be a return
  for (auto it = std::upper_bound(gt_stamps.begin(), gt_stamps.end(), from + association.offset);
       it != gt_stamps.end() && *it - association.offset < to; ++it) {
    const core::StampedPose& pose = gt[static_cast<std::size_t>(it - gt_stamps.begin())];
    const double t = pose.timestamp - association.offset;
    if (!NearestPlace(pose.T_wc, t, keyframes, options)) continue;
    if (t - last > options.event_gap) return false;
    last = t;
  }
  return to - last <= options.event_gap;
}

void RequireAtLeast(double value, double minimum, bool inclusive, const char* name, const char* unit) {
  if (std::isfinite(value) && (inclusive ? value >= minimum : value > minimum)) return;
  throw core::InputError::ForParameter(fmt::format("loop_recall.{}", name),
                                       fmt::format("must be {} {} {}, got {}", inclusive ? ">=" : ">", minimum, unit,
                                                   value));
}

}  // namespace

void LoopRecallOptions::Check() const {
  RequireAtLeast(max_return_distance, 0.0, false, "max_return_distance", "m");
  RequireAtLeast(max_return_angle_deg, 0.0, false, "max_return_angle_deg", "degrees");
  if (max_return_angle_deg > 180.0) {
    throw core::InputError::ForParameter("loop_recall.max_return_angle_deg",
                                         fmt::format("must be <= 180 degrees, got {}", max_return_angle_deg));
  }
  RequireAtLeast(min_separation, 0.0, true, "min_separation", "s");
  RequireAtLeast(event_gap, 0.0, true, "event_gap", "s");
  RequireAtLeast(close_within, 0.0, true, "close_within", "s");
  RequireAtLeast(max_consistent_position_error, 0.0, false, "max_consistent_position_error", "m");
  RequireAtLeast(max_consistent_rotation_error_deg, 0.0, false, "max_consistent_rotation_error_deg", "degrees");
  RequireAtLeast(closure.max_position_error, 0.0, false, "closure.max_position_error", "m");
  RequireAtLeast(closure.max_rotation_error_deg, 0.0, false, "closure.max_rotation_error_deg", "degrees");
}

std::size_t LoopRecall::Closed() const {
  return static_cast<std::size_t>(
      std::count_if(events.begin(), events.end(), [](const ReturnEvent& e) { return e.closed_by.has_value(); }));
}

std::size_t LoopRecall::Consistent() const {
  return static_cast<std::size_t>(
      std::count_if(events.begin(), events.end(), [](const ReturnEvent& e) { return e.consistent; }));
}

std::optional<double> LoopRecall::Recall() const {
  if (events.empty()) return std::nullopt;
  return static_cast<double>(Recalled()) / static_cast<double>(events.size());
}

std::optional<double> LoopRecall::Precision() const {
  if (closures == 0) return std::nullopt;
  return static_cast<double>(confirmed) / static_cast<double>(closures);
}

LoopRecall ComputeLoopRecall(const core::Trajectory& groundtruth, const core::Trajectory& keyframes,
                             std::span<const RelativePose> closures, const AssociationOptions& association,
                             const LoopRecallOptions& options) {
  options.Check();
  LoopRecall result;
  const core::Trajectory gt = SortedUniqueByTime(groundtruth);
  const core::Trajectory estimate = SortedUniqueByTime(keyframes);
  std::vector<Keyframe> matched;
  for (const Match& m : AssociateByTimestamp(gt, estimate, association)) {
    matched.push_back({estimate[m.second].timestamp, gt[m.first].T_wc, estimate[m.second].T_wc});
  }
  std::sort(matched.begin(), matched.end(),
            [](const Keyframe& l, const Keyframe& r) { return l.timestamp < r.timestamp; });
  result.unmatched_keyframes = estimate.size() - matched.size();

  // Each keyframe against every one at least min_separation older: the nearest within both limits is where it
  // returned to. Quadratic, but keyframes are few (a few hundred in a two-minute run).
  const std::vector<double> gt_stamps = Timestamps(gt);
  double best_score = std::numeric_limits<double>::infinity();  // of the current event's nearest return
  for (const Keyframe& current : matched) {
    const std::optional<Place> place = NearestPlace(current.T_true, current.timestamp, matched, options);
    if (!place) continue;
    if (result.events.empty() ||
        !KeptReturning(gt, gt_stamps, result.events.back().end, current.timestamp, matched, association, options)) {
      result.events.emplace_back().start = current.timestamp;
      best_score = std::numeric_limits<double>::infinity();
    }
    ReturnEvent& event = result.events.back();
    event.end = current.timestamp;
    ++event.keyframes;
    // The event is judged at its nearest return, where the two views overlap most.
    if (place->score < best_score) {
      best_score = place->score;
      const Keyframe& earlier = matched[place->keyframe];
      const core::Pose difference = (earlier.T_true.inverse() * current.T_true).inverse() *
                                    (earlier.T_estimate.inverse() * current.T_estimate);
      event.timestamp = current.timestamp;
      event.place_timestamp = earlier.timestamp;
      event.true_distance = place->distance;
      event.position_error = difference.translation().norm();
      event.rotation_error_deg = core::RotationAngleDegrees(difference.linear());
    }
  }

  const PoseCheck check = CheckRelativePoses(groundtruth, closures, association, options.closure);
  result.closures = check.poses.size();
  result.confirmed = check.poses.size() - check.Wrong();
  result.unmatched_closures = check.unmatched;
  for (ReturnEvent& event : result.events) {
    // A false loop recalls nothing: it joined the map at the wrong place.
    for (const CheckedPose& closure : check.poses) {
      if (closure.wrong || closure.timestamp < event.start - kWrittenStampTolerance ||
          closure.timestamp > event.end + options.close_within) {
        continue;
      }
      if (!event.closed_by || closure.timestamp < *event.closed_by) event.closed_by = closure.timestamp;
    }
    event.consistent = !event.closed_by && event.position_error <= options.max_consistent_position_error &&
                       event.rotation_error_deg <= options.max_consistent_rotation_error_deg;
  }
  return result;
}

nlohmann::json LoopRecallToJson(const LoopRecall& recall, const LoopRecallOptions& options) {
  const auto optional = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); };
  nlohmann::json returns = nlohmann::json::array();
  for (const ReturnEvent& e : recall.events) {
    returns.push_back({{"start", e.start},
                       {"end", e.end},
                       {"keyframes", e.keyframes},
                       {"timestamp", e.timestamp},
                       {"place_timestamp", e.place_timestamp},
                       {"true_distance_m", e.true_distance},
                       {"position_error_m", e.position_error},
                       {"rotation_error_deg", e.rotation_error_deg},
                       {"closed_by", optional(e.closed_by)},
                       {"consistent", e.consistent}});
  }
  return {{"events", recall.events.size()},
          {"recalled", recall.Recalled()},
          {"closed", recall.Closed()},
          {"consistent", recall.Consistent()},
          {"recall", optional(recall.Recall())},
          {"closures", recall.closures},
          {"confirmed", recall.confirmed},
          {"precision", optional(recall.Precision())},
          {"unmatched_closures", recall.unmatched_closures},
          {"unmatched_keyframes", recall.unmatched_keyframes},
          {"options",
           {{"max_return_distance_m", options.max_return_distance},
            {"max_return_angle_deg", options.max_return_angle_deg},
            {"min_separation_s", options.min_separation},
            {"event_gap_s", options.event_gap},
            {"close_within_s", options.close_within},
            {"max_consistent_position_error_m", options.max_consistent_position_error},
            {"max_consistent_rotation_error_deg", options.max_consistent_rotation_error_deg},
            {"closure_max_position_error_m", options.closure.max_position_error},
            {"closure_max_rotation_error_deg", options.closure.max_rotation_error_deg}}},
          {"returns", std::move(returns)}};
}

}  // namespace hoidslam::eval
