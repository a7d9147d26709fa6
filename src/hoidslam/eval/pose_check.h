#pragma once
// Whether chosen poses of an estimate agree with the ground truth once the whole trajectory is aligned to it: the
// bench's check of relocalisation, where one wrong pose (a place taken for another) bends everything after it,
// however small the ATE of the frames around it.

#include <span>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "hoidslam/core/pose.h"
#include "hoidslam/eval/alignment.h"
#include "hoidslam/eval/association.h"

namespace hoidslam::eval {

struct PoseCheckOptions {
  double max_position_error = 0.10;     // metres: a checked pose farther from the ground truth is wrong
  double max_rotation_error_deg = 5.0;  // degrees: so is one turned more than this
};

struct CheckedPose {
  double timestamp = 0.0;           // of the estimated pose
  double position_error = 0.0;      // metres, after the alignment
  double rotation_error_deg = 0.0;  // angle of the rotation between the aligned and the true orientation
  bool wrong = false;               // beyond either limit
};

struct PoseCheck {
  std::vector<CheckedPose> poses;  // in the order of the stamps asked for
  std::size_t unmatched = 0;       // stamps with no estimated pose, or no ground-truth pose near enough
  std::size_t Wrong() const;
};

// Checks the estimated poses at `stamps` (each the stamp of a pose in `estimate`, as written: within 0.1 ms)
// against the ground-truth pose nearest in time (within association.max_difference), the estimate taken into the
// ground truth's frame by `alignment` (an ATE alignment; its scale is applied to positions only).
PoseCheck CheckPoses(const core::Trajectory& groundtruth, const core::Trajectory& estimate,
                     const Alignment& alignment, std::span<const double> stamps,
                     const AssociationOptions& association, const PoseCheckOptions& options);

// A relative pose an estimate measured between two of its frames: the bench's check of loop closing, where the
// loop's two ends are joined by the pose the verification found between them.
struct RelativePose {
  double timestamp = 0.0;       // of the frame whose pose is given ...
  double base_timestamp = 0.0;  // ... relative to this one's
  core::Pose T_base_frame;      // the frame's camera into the base's camera
};

// Checks each relative pose against the ground truth's between the two stamps (each matched to the nearest
// ground-truth pose within association.max_difference): no alignment is needed, a relative pose is the same in
// every world frame. CheckedPose::timestamp is the frame's.
PoseCheck CheckRelativePoses(const core::Trajectory& groundtruth, std::span<const RelativePose> relative,
                             const AssociationOptions& association, const PoseCheckOptions& options);

// {"count", "false", "unmatched", "max_position_error_m", "max_rotation_error_deg", "poses": [...]}: the limits
// and every checked pose.
nlohmann::json PoseCheckToJson(const PoseCheck& check, const PoseCheckOptions& options);

}  // namespace hoidslam::eval
