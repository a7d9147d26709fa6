#pragma once
// Loop recall and precision by the ground truth: of the times the camera came back to a place it had mapped, how
// many ended with the map joined there (a loop closed or a map merged, or the map already consistent), and of the
// loops and merges closed, how many the ground truth confirms. The loop check of eval/pose_check.h judges the loops
// a system closed; this also counts the ones it should have closed and did not (docs/evaluation.md).

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "hoidslam/core/pose.h"
#include "hoidslam/eval/association.h"
#include "hoidslam/eval/pose_check.h"

namespace hoidslam::eval {

struct LoopRecallOptions {
  // A keyframe returns to an earlier keyframe when their true poses are this close: near enough that the two see
  // much of the same scene, so a place recogniser has something to find.
  double max_return_distance = 0.5;    // metres, > 0
  double max_return_angle_deg = 30.0;  // degrees, in (0, 180]
  // ... and the earlier one is at least this much older: the keyframes of one pass past a place are not returns.
  double min_separation = 10.0;  // seconds, >= 0
  // Returning keyframes this close in time form one return event; a longer pause without a return starts another.
  double event_gap = 3.0;  // seconds, >= 0
  // A loop closed (or a map merged) by a keyframe of the event, or up to this long after its last keyframe, recalls
  // it: loop closing confirms a place over a few keyframes before it closes.
  double close_within = 3.0;  // seconds, >= 0
  // An event no loop closed is already consistent when the estimated relative pose between its returning keyframe
  // and the earlier one (final poses) is this close to the true one: tracking found the old map by itself.
  double max_consistent_position_error = 0.02;    // metres, > 0
  double max_consistent_rotation_error_deg = 1.0;  // degrees, > 0
  // A loop or merge is confirmed when its relative pose is within these limits of the truth (the loop check's).
  PoseCheckOptions closure;

  // Throws core::InputError naming the parameter (loop_recall.<member>) of a bad value.
  void Check() const;
};

// One return to an earlier place: consecutive returning keyframes.
struct ReturnEvent {
  double start = 0.0;            // stamp of its first returning keyframe
  double end = 0.0;              // and of its last
  std::size_t keyframes = 0;     // returning keyframes in it
  double timestamp = 0.0;        // its returning keyframe nearest (in truth) to an earlier one ...
  double place_timestamp = 0.0;  // ... and that earlier keyframe
  double true_distance = 0.0;    // metres between the two, in truth
  double position_error = 0.0;      // metres: their estimated relative pose against the true one
  double rotation_error_deg = 0.0;  // degrees
  std::optional<double> closed_by;  // stamp of the current end of the confirmed loop or merge that recalled it
  bool consistent = false;          // not closed, and the relative pose within the consistency limits

  bool Recalled() const { return closed_by.has_value() || consistent; }
};

struct LoopRecall {
  std::vector<ReturnEvent> events;  // in time order
  std::size_t closures = 0;         // loops and merges judged against the ground truth
  std::size_t confirmed = 0;        // of them within the closure limits
  std::size_t unmatched_closures = 0;   // loops and merges with an end the ground truth has no pose for
  std::size_t unmatched_keyframes = 0;  // keyframes the ground truth has no pose for: they take no part

  std::size_t Closed() const;
  std::size_t Consistent() const;
  std::size_t Recalled() const { return Closed() + Consistent(); }
  // Recalled events / events; nullopt without an event (a run that never came back has nothing to recall).
  std::optional<double> Recall() const;
  // Confirmed / judged loops and merges; nullopt when none was closed.
  std::optional<double> Precision() const;
};

// `keyframes`: the estimated keyframe poses at their final places (keyframes.txt); `closures`: every loop and
// merge, each as the relative pose its verification found from the place (base) to the keyframe that closed it.
// Every pose is matched to the ground truth by timestamp (association: max_difference and offset), never by line.
LoopRecall ComputeLoopRecall(const core::Trajectory& groundtruth, const core::Trajectory& keyframes,
                             std::span<const RelativePose> closures, const AssociationOptions& association,
                             const LoopRecallOptions& options);

// {"events", "recalled", "closed", "consistent", "recall" (null without an event), "closures", "confirmed",
//  "precision" (null without a closure), "unmatched_closures", "unmatched_keyframes", "options", "returns": [...]}
nlohmann::json LoopRecallToJson(const LoopRecall& recall, const LoopRecallOptions& options);

}  // namespace hoidslam::eval
