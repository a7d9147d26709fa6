#pragma once
// What the final dense build fills one keyframe at a time — the volume (surface and colour) and the occupancy map
// (free and occupied space) — and the surface written from them: the volume's mesh and cloud without what the
// occupancy map's rays saw through (DenseOptions::keep_seen_through).

#include <cstddef>
#include <filesystem>

#include <opencv2/core/mat.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/dense/dense_options.h"
#include "hoidslam/dense/occupancy.h"
#include "hoidslam/dense/tsdf_volume.h"

namespace hoidslam::dense {

class StaticWorld {
 public:
  // `camera` without distortion. Throws InputError when the occupancy options fail Check().
  StaticWorld(const DenseOptions& options, const core::CameraIntrinsics& camera);

  // One keyframe: colour CV_8UC3 (BGR), depth CV_32FC1 with 0 where nothing is to be fused (FusibleDepth), the
  // camera at T_wc. The occupancy map's rays are cast in a second thread while the volume integrates: the two
  // share nothing but the images, and a build after the run has the machine's cores to itself.
  void Fuse(const cv::Mat& bgr, const cv::Mat& depth, const core::Pose& T_wc);

  const TsdfVolume& volume() const { return volume_; }
  const OccupancyMap& occupancy() const { return occupancy_; }

  // Does the occupancy map call the cell holding p_w free? A surface there was seen through by later views.
  bool SeenThrough(const Eigen::Vector3d& p_w) const;
  // The volume's mesh and cloud (TsdfVolume::WriteMesh, WriteCloud), without what was seen through unless the
  // options keep it.
  MeshCounts WriteMesh(const std::filesystem::path& path) const;
  std::size_t WriteCloud(const std::filesystem::path& path) const;

 private:
  PointFilter LeaveOut() const;

  DenseOptions options_;
  core::CameraIntrinsics camera_;
  TsdfVolume volume_;
  OccupancyMap occupancy_;
};

}  // namespace hoidslam::dense
