#pragma once
// Free and occupied space of the static world: an OctoMap (3D, written as occupancy.bt) filled with the keyframes'
// depth rays — the dynamic pixels already taken out, as for the volume — and a 2D grid of it over a height band,
// written as occupancy.pgm + occupancy.yaml in the format ROS map_server and Nav2 read.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/dense/dense_options.h"

namespace hoidslam::dense {

// A 2D occupancy grid in the floor's frame (grid.T_fw: world → floor frame, z up, the floor at z = 0).
struct OccupancyGrid {
  static constexpr std::int8_t kUnknown = -1, kFree = 0, kOccupied = 100;

  double resolution = 0.05;                    // m a cell
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // floor-frame x, y of the lower-left corner of cell (0, 0)
  int width = 0, height = 0;                   // cells; row 0 is the lowest y
  // Per cell (row-major, row 0 lowest y): kUnknown, kFree or kOccupied (ROS nav_msgs/OccupancyGrid values).
  std::vector<std::int8_t> cells;
  core::Pose T_fw = core::Pose::Identity();
};

// What the 3D map knows of a cell.
enum class CellState { kUnknown, kFree, kOccupied };

class OccupancyMap {
 public:
  explicit OccupancyMap(const OccupancyOptions& options);
  ~OccupancyMap();
  OccupancyMap(const OccupancyMap&) = delete;
  OccupancyMap& operator=(const OccupancyMap&) = delete;

  // Casts the rays of one depth image (CV_32FC1, metres; 0 = no ray: invalid or excluded) from the camera at
  // T_wc: cells along a ray are free, the cell at its end occupied. A ray deeper than `max_depth` (beyond the
  // range the caller trusts for surfaces) is cut there and only frees the cells it crosses: the space before a far
  // wall is free even where the wall itself is too far to map. Those rays are cast at twice the pixel step.
  void InsertDepth(const cv::Mat& depth, const core::CameraIntrinsics& camera, const core::Pose& T_wc,
                   double max_depth = std::numeric_limits<double>::infinity());

  // The centres of the occupied leaves (world), at the finest resolution.
  std::vector<Eigen::Vector3d> OccupiedCentres() const;
  std::size_t OccupiedLeaves() const;
  // The state of the leaf holding p_w (world).
  CellState At(const Eigen::Vector3d& p_w) const;
  // Writes the map as OctoMap's binary tree file (.bt: free and occupied, maximum likelihood), atomically.
  void WriteBinary(const std::filesystem::path& path) const;

  // The 2D grid over the band [options.band_low, band_high] above the floor: a column is occupied when a leaf
  // in the band is, free when one is free and none occupied, unknown otherwise.
  OccupancyGrid Project(const core::Pose& T_fw) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The occupied cells of an occupancy.bt: their size and centres (the finest leaves). Throws InputError naming the
// file when it is not an OctoMap binary tree.
struct OccupiedCells {
  double resolution = 0.0;
  std::vector<Eigen::Vector3d> centres;
};
OccupiedCells ReadOccupiedCells(const std::filesystem::path& path);

// Writes `grid` as <stem>.pgm (occupied 0, free 254, unknown 205; the top image row is the highest y) and
// <stem>.yaml (image, resolution, origin [x, y, yaw], negate, occupied_thresh, free_thresh, mode trinary), both
// atomically; the YAML also records grid.T_fw so that a user can place the grid in the SLAM world frame. Throws
// InputError naming the file that cannot be written, or `pgm` for an empty grid (no depth in the height band).
void WriteOccupancyGrid(const OccupancyGrid& grid, const std::filesystem::path& pgm, const std::filesystem::path& yaml);

}  // namespace hoidslam::dense
