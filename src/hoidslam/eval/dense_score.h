#pragma once
// How clean and complete a dense map of the static world is, measured against a synthetic sequence's exact
// geometry (docs/dense.md): the office's static surface (static_geometry.ply) and the space people and moved objects
// ever occupied (moving_volume.ply), both in the ground truth's world frame. The reconstruction is brought into that
// frame by its keyframes' poses (DenseScoreAlignment).

#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <nlohmann/json.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/eval/alignment.h"
#include "hoidslam/eval/association.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/io/rgbd_sequence.h"

namespace hoidslam::eval {

struct DenseScoreOptions {
  double completeness_distance = 0.02;  // m: a true surface point this near the reconstruction counts as mapped
  double ghost_distance = 0.05;         // m: reconstructed surface farther than this from every static one is a ghost
  double surface_spacing = 0.02;        // m between the samples of the true surface completeness is counted on
  std::size_t view_step = 10;           // every n-th frame is a view of where the camera looked
  double min_depth = 0.3, max_depth = 3.0;  // m: what a view sees (the dense map's own range)

  double AlignmentLever() const { return 0.5 * (min_depth + max_depth); }  // m, for DenseScoreAlignment
};

// The frame the map is scored in: the keyframes it was fused from, centres and orientations, aligned to the ground
// truth (AlignPoses, the lever at the middle of the depth range). The ATE's alignment fits centres alone, and on
// carry's short path it left the whole map turned 0.2°: the far floor 4–12 mm off, a map error that was none.
Alignment DenseScoreAlignment(const core::Trajectory& groundtruth, const core::Trajectory& keyframes,
                              const AssociationOptions& association, const DenseScoreOptions& options);

// The truth a synthetic sequence carries.
struct DenseTruth {
  io::TriangleMesh static_geometry;
  io::VoxelCentres moving_volume;
  // Where the camera looked: views of the sequence (every view_step-th frame) with their true pose and the depth
  // image (CV_32FC1, metres) it recorded — people in front of the static surface hide it, as they did.
  struct View {
    core::Pose T_wc;
    cv::Mat depth;
  };
  std::vector<View> views;
  core::CameraIntrinsics camera;

  // Reads static_geometry.ply, moving_volume.ply, and every view_step-th frame's depth with its ground-truth pose;
  // InputError naming a missing or bad file.
  static DenseTruth Load(const io::RgbdSequence& sequence, const core::CameraIntrinsics& camera,
                         std::size_t view_step);
  static bool Exists(const std::filesystem::path& sequence);  // the sequence has the geometry files
};

struct DenseScore {
  // Accuracy: each reconstructed vertex's distance to the true static surface, m.
  double accuracy_mean = 0.0, accuracy_median = 0.0, accuracy_p90 = 0.0;
  // Completeness: the share of the true static surface the views saw (in range, facing the camera, at the depth the
  // view measured there: not hidden by other surface or a person) that lies within completeness_distance of the
  // reconstruction.
  double completeness = 0.0;
  std::size_t seen_samples = 0;
  // Ghosts: reconstructed surface farther than ghost_distance from every static surface.
  double area = 0.0;        // m², the reconstruction's
  double ghost_area = 0.0;  // m²
  double GhostShare() const { return area > 0.0 ? ghost_area / area : 0.0; }
  // The occupancy map's occupied cells, and of them those whose centre lies in space only people and moved objects
  // ever took (a cell of the moving volume, farther than a cell from the static surface).
  std::optional<std::size_t> occupied_cells, ghost_cells;
};

// Scores `reconstruction` (the estimate's world frame) and, when given, the occupied cell centres of its occupancy
// map (same frame, cells of `occupancy_resolution`), after `alignment` (estimate → ground truth).
DenseScore ScoreDenseMap(const io::TriangleMesh& reconstruction, const std::vector<Eigen::Vector3d>* occupied,
                         double occupancy_resolution, const Alignment& alignment, const DenseTruth& truth,
                         const DenseScoreOptions& options = {});

nlohmann::json DenseScoreJson(const DenseScore& score, const DenseScoreOptions& options);

}  // namespace hoidslam::eval
