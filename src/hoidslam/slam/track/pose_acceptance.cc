#include "hoidslam/slam/track/pose_acceptance.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/option_checks.h"

namespace hoidslam::slam {
namespace {

constexpr core::EnumNames<PoseRejection, 7> kRejectionNames = {{
    {PoseRejection::kNone, "none"},
    {PoseRejection::kTooFewInliers, "too_few_inliers"},
    {PoseRejection::kTooLittleSupport, "too_little_support"},
    {PoseRejection::kContradicted, "contradicted"},
    {PoseRejection::kOutliersClustered, "outliers_clustered"},
    {PoseRejection::kAgainstMotion, "against_motion"},
    {PoseRejection::kAmbiguous, "ambiguous"},
}};

PoseVerdict Refused(PoseRejection why) { return {false, false, false, why}; }

}  // namespace

std::string_view ToString(PoseRejection rejection) { return core::EnumName(kRejectionNames, rejection); }

void PoseAcceptanceOptions::Check() const {
  core::CheckPositive(min_inliers, "Tracking.minInliers");
  core::CheckPositive(min_inliers_after_relocalization, "Tracking.minInliersAfterRelocalization");
  core::CheckShare(majority_ratio, "Tracking.majorityInlierRatio");
  core::CheckShare(min_noisy_inlier_ratio, "Tracking.minNoisyInlierRatio");
  core::CheckShare(min_clustered_inlier_ratio, "Tracking.minClusteredInlierRatio");
  core::CheckShare(min_inlier_ratio, "Tracking.minInlierRatio");
  if (!(min_clustered_inlier_ratio <= min_inlier_ratio && min_inlier_ratio <= majority_ratio)) {
    throw core::InputError::ForParameter(
        "Tracking.minInlierRatio",
        fmt::format("must lie between Tracking.minClusteredInlierRatio ({}) and Tracking.majorityInlierRatio ({}), "
                    "got {}",
                    min_clustered_inlier_ratio, majority_ratio, min_inlier_ratio));
  }
  core::CheckInRange(max_outlier_clustering, 1.0, 1e6, "Tracking.maxOutlierClustering");
  core::CheckPositive(max_motion_chi2, "Tracking.maxMotionChi2");
  core::CheckPositive(min_inliers_floor, "Tracking.minInliersFloor");
  core::CheckShare(min_inlier_share, "Tracking.minInlierShare");
  core::CheckInRange(close_inlier_weight, 1.0, 3.0, "Tracking.closeInlierWeight");
  core::CheckShare(supported_inlier_ratio, "Tracking.supportedInlierRatio");
  core::CheckInRange(clustering_columns, 1, 64, "Tracking.clusteringColumns");
  core::CheckInRange(clustering_rows, 1, 48, "Tracking.clusteringRows");
  core::CheckInRange(min_cell_matches, 2, 1000, "Tracking.minCellMatches");
}

PoseVerdict JudgePose(const PoseEvidence& evidence, const PoseAcceptanceOptions& options) {
  const int min_inliers = evidence.provisional ? options.min_inliers_after_relocalization : options.min_inliers;
  const double ratio = evidence.inlier_ratio();
  if (evidence.inliers < min_inliers) {
    // Few inliers: enough only for a frame that has little, by their support, and then only with a good share of
    // its matches.
    const int floor = std::min(options.min_inliers_floor, min_inliers);
    const int needed = std::clamp(static_cast<int>(std::ceil(options.min_inlier_share * evidence.keypoints)), floor,
                                  min_inliers);
    if (needed == min_inliers) return Refused(PoseRejection::kTooFewInliers);
    if (evidence.support < needed) return Refused(PoseRejection::kTooLittleSupport);
    if (ratio < options.supported_inlier_ratio) return Refused(PoseRejection::kContradicted);
  }
  const bool majority = ratio >= options.majority_ratio;
  const bool clustered = evidence.outlier_clustering > options.max_outlier_clustering;
  const bool good_share = ratio >= options.min_inlier_ratio;
  // The motion model judges a provisional pose always, and otherwise only where the image itself is of two minds
  // (a small share backing the pose, the outliers in regions): outliers spread like noise leave one explanation, and
  // a pose a good share backs stands on it; a pose far from the prediction then means the camera jerked.
  const bool against_motion = evidence.motion_chi2 && *evidence.motion_chi2 > options.max_motion_chi2;
  if (against_motion && (evidence.provisional || (!good_share && clustered))) {
    return Refused(PoseRejection::kAgainstMotion);
  }
  if (majority) return {true, false, true, PoseRejection::kNone};
  if (ratio < (clustered ? options.min_clustered_inlier_ratio : options.min_noisy_inlier_ratio)) {
    return Refused(clustered ? PoseRejection::kOutliersClustered : PoseRejection::kContradicted);
  }
  // Reported; the map extended from it only when a good share backs it, and another search tried when the share is
  // small or regions of the image disagree.
  return {true, clustered || !good_share, good_share || !clustered, PoseRejection::kNone};
}

PoseEvidence MeasureEvidence(const Frame& frame, int matched, const PosePrior* prior,
                             const PoseAcceptanceOptions& options) {
  PoseEvidence evidence;
  evidence.keypoints = frame.size();
  evidence.matched = matched;
  const KeypointSet& keypoints = *frame.keypoints;
  const Sensor& sensor = keypoints.sensor();
  const int columns = options.clustering_columns, rows = options.clustering_rows;
  std::vector<int> cell_matches(static_cast<std::size_t>(columns * rows), 0);
  std::vector<int> cell_inliers(cell_matches.size(), 0);
  const double cell_width = (sensor.max_x - sensor.min_x) / columns;
  const double cell_height = (sensor.max_y - sensor.min_y) / rows;
  for (int i = 0; i < frame.size(); ++i) {
    if (frame.map_points[static_cast<std::size_t>(i)] == nullptr) continue;
    const Eigen::Vector2d& uv = keypoints.undistorted(i);
    const int column = std::clamp(static_cast<int>((uv.x() - sensor.min_x) / cell_width), 0, columns - 1);
    const int row = std::clamp(static_cast<int>((uv.y() - sensor.min_y) / cell_height), 0, rows - 1);
    const auto cell = static_cast<std::size_t>(row * columns + column);
    ++cell_matches[cell];
    if (!frame.IsInlier(i)) continue;
    ++cell_inliers[cell];
    ++evidence.inliers;
    const bool close = keypoints.has_depth(i) && keypoints.depth(i) < sensor.close_depth;
    evidence.support += close ? options.close_inlier_weight : 1.0;
  }
  // Pearson's χ² of the cells' inlier counts against the frame's share, per degree of freedom.
  int cells = 0, cell_total = 0, cell_inlier_total = 0;
  for (std::size_t c = 0; c < cell_matches.size(); ++c) {
    if (cell_matches[c] < options.min_cell_matches) continue;
    ++cells;
    cell_total += cell_matches[c];
    cell_inlier_total += cell_inliers[c];
  }
  const double share = cell_total > 0 ? static_cast<double>(cell_inlier_total) / cell_total : 0.0;
  if (cells >= 2 && share > 0.0 && share < 1.0) {
    double chi2 = 0.0;
    for (std::size_t c = 0; c < cell_matches.size(); ++c) {
      if (cell_matches[c] < options.min_cell_matches) continue;
      const double expected = cell_matches[c] * share;
      const double difference = cell_inliers[c] - expected;
      chi2 += difference * difference / (expected * (1.0 - share));
    }
    evidence.outlier_clustering = chi2 / (cells - 1);
  }
  if (prior != nullptr) evidence.motion_chi2 = PriorChi2(frame.T_cw, *prior);
  return evidence;
}

}  // namespace hoidslam::slam
