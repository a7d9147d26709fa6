#pragma once
// Whether a frame's pose stands, judged on the evidence of its own data: one pure function with its options, so
// that every rule has one home and a table-driven test (pose_acceptance_test.cc).
//
// A right pose keeps most of its local-map matches — or, when it keeps only a minority, its outliers fall anywhere
// in the image: a blurred fast turn of a hand-held camera, a rolling shutter and a noisy sensor give outliers
// everywhere while the inliers agree on the pose. A pose pulled by something moving (people whose points made it
// into the map, or a rival pose that part of the image agrees on) leaves whole regions of the image in
// disagreement, and it often departs from the way the camera was moving. So a minority of inliers is taken when the
// outliers are spread like noise, and refused when they cluster unless the inliers are a large enough share; and a
// pose that most of its matches do not back must also agree with the motion model.

#include <optional>
#include <string_view>

#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/optimize/pose_optimizer.h"

namespace hoidslam::slam {

struct PoseAcceptanceOptions {
  int min_inliers = 30;                       // local-map inliers for a frame to count as tracked
  int min_inliers_after_relocalization = 50;  // the same while a relocalisation is provisional
  // A pose its inliers back by this share of its matches stands on its count alone; below it, the outliers are
  // looked at.
  double majority_ratio = 0.5;
  // Outliers spread like noise (clustering <= max_outlier_clustering): a pose keeping this share is reported. On the
  // real fr1_rpy recording right poses of blurred fast turns keep 10-35 % of their matches.
  double min_noisy_inlier_ratio = 0.08;
  // Outliers clustered in regions of the image: a pose keeping this share is reported. On crowd without a filter
  // poses pulled by people's points kept 15-40 %.
  double min_clustered_inlier_ratio = 0.15;
  // Below this share of its matches, or with clustered outliers, a pose is doubtful: the reference keyframe is tried
  // as well and the pose more inliers back is kept (at 15 Hz on walking_xyz a motion-model pose keeping 40 of 425,
  // its outliers spread, was 57 mm off and, made a keyframe, bent the map: 17 mm ATE where the others had 3). And
  // a pose below it whose outliers cluster extends no map (no keyframe, new points, safety-net verdicts or tracking
  // statistics): on crowd without a filter, keyframes on poses pulled by people's points carry the pull into the
  // map. (Refusing every pose below 30 %, as tracking did before, lost every blurred turn of fr1_rpy; extending no
  // map from any of them left the map behind the camera in a long fast turn, and tracking lost with it.)
  double min_inlier_ratio = 0.3;
  // The dispersion index of the inliers' share over the image cells (PoseEvidence::outlier_clustering) up to which
  // the outliers count as spread like noise. Measured: 1.0-2.9 (5th-95th percentile) for right poses of the real
  // fr1_rpy recording; 2.2-6.0 for poses pulled by people on crowd without a filter.
  double max_outlier_clustering = 2.5;
  // A pose backed by less than min_inlier_ratio of its matches with its outliers clustered, and every provisional
  // pose, must lie within this χ² (6 degrees of freedom) of the motion model's prediction: 22.46 is its 99.9 %
  // quantile. A good share of inliers, or outliers spread like noise, outweigh the prediction: a real jerk of the
  // camera (fr1_rpy: right poses of fast turns at χ² 30-56, keeping 24-44 % of their matches).
  double max_motion_chi2 = 22.46;
  // A frame with few keypoints (people fill the view, the filter dropped most of it) is tracked on what it has,
  // by support rather than count: an inlier nearer than the close depth counts close_inlier_weight times (its
  // depth pins the point: three constraints on the pose where a far one gives two), and the support needed falls
  // to min_inlier_share of the frame's keypoints, never below min_inliers_floor. A pose resting on a few points in
  // one corner of the image is less certain, and a wrong one corrupts the map; so the lower bar also asks that
  // supported_inlier_ratio of the matches be inliers. At half, crowd lost a median of 10 frames in 5 runs whose
  // local maps kept 40-48 % (22 of 50, 29 of 64); at 0.4 none.
  int min_inliers_floor = 15;
  double min_inlier_share = 0.3;
  double close_inlier_weight = 1.5;
  double supported_inlier_ratio = 0.4;
  // The image is divided into this many columns and rows to see where the outliers fall; a cell takes part with at
  // least min_cell_matches matches.
  int clustering_columns = 8;
  int clustering_rows = 6;
  int min_cell_matches = 5;

  void Check() const;
};

// What a pose hypothesis shows, measured by MeasureEvidence.
struct PoseEvidence {
  int keypoints = 0;   // the frame's keypoints (those the exclusion filter kept)
  int matched = 0;     // keypoints matched to map points before the final pose optimisation
  int inliers = 0;     // of those, kept by it
  double support = 0;  // the inliers, each close one counting close_inlier_weight
  // The dispersion index (Pearson's χ² per degree of freedom) of the inliers' share in each image cell with
  // enough matches, against the share over the whole frame: about 1 when the outliers fall anywhere, large when
  // whole regions disagree with the pose. 1 when fewer than two cells take part.
  double outlier_clustering = 1.0;
  std::optional<double> motion_chi2;  // PriorChi2 of the pose against the motion model's prior, when there is one
  // The pose is provisional (a relocalisation not yet confirmed, tracker.h): the motion model is asked even of a
  // clear majority, and the stricter count applies.
  bool provisional = false;

  double inlier_ratio() const { return matched > 0 ? static_cast<double>(inliers) / matched : 0.0; }
};

// Why a pose was refused.
enum class PoseRejection {
  kNone,
  kTooFewInliers,      // fewer than the floor, or a frame with enough keypoints short of the count
  kTooLittleSupport,   // a frame with few keypoints whose inliers support too little of it
  kContradicted,       // too small a share of its matches kept, the outliers spread
  kOutliersClustered,  // too small a share kept, whole regions of the image disagreeing
  kAgainstMotion,      // far from where the camera was heading, without a clear majority to say otherwise
  kAmbiguous,          // relocalisation: two places fit the frame about as well
};
std::string_view ToString(PoseRejection rejection);

struct PoseVerdict {
  bool accepted = false;
  // Accepted, though few matches back it or regions of the image disagree with it: the tracker tries another search
  // and keeps the pose more matches back (the prediction may have led to the wrong corners).
  bool doubtful = false;
  // The map may be extended from the pose (a keyframe, new points, the safety net's verdicts): at least
  // min_inlier_ratio of its matches back it, or its outliers spread like noise. A pose pulled a little by people
  // whose points made it into the map is still reported, but no keyframe made on it carries the pull into the map.
  bool mappable = false;
  PoseRejection rejection = PoseRejection::kNone;
};

// The rules above, in order: the count (or the support of a frame with few keypoints), the motion model for a
// pose without a clear majority, then the share of inliers by how the outliers fall.
PoseVerdict JudgePose(const PoseEvidence& evidence, const PoseAcceptanceOptions& options);

// The evidence of a frame whose pose has just been optimised against its matches (frame.map_points, frame.outlier),
// `matched` of them before the optimisation; `prior` the motion model's, when there is one.
PoseEvidence MeasureEvidence(const Frame& frame, int matched, const PosePrior* prior,
                             const PoseAcceptanceOptions& options);

}  // namespace hoidslam::slam
