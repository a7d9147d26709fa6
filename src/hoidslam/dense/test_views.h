#pragma once
// What the volume's and the mapper's tests share: a small camera, a coarse volume, and the cloud a file holds as
// Open3D reads it.

#include <filesystem>

#include <gtest/gtest.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/io/PointCloudIO.h>

#include "hoidslam/core/camera.h"
#include "hoidslam/dense/dense_options.h"

namespace hoidslam::dense::test_views {

// An 80×60 camera, so that the tests stay quick.
inline core::CameraIntrinsics SmallCamera() {
  core::CameraIntrinsics camera;
  camera.fx = camera.fy = 70.0;
  camera.cx = 40.0;
  camera.cy = 30.0;
  camera.width = 80;
  camera.height = 60;
  return camera;
}

// 2 cm voxels, 8 cm truncation.
inline DenseOptions CoarseOptions() {
  DenseOptions options;
  options.voxel_size = 0.02;
  options.truncation = 0.08;
  return options;
}

// The cloud a file holds, read by Open3D as a user would.
inline open3d::geometry::PointCloud ReadCloud(const std::filesystem::path& path) {
  open3d::geometry::PointCloud cloud;
  EXPECT_TRUE(open3d::io::ReadPointCloud(path.string(), cloud));
  return cloud;
}

}  // namespace hoidslam::dense::test_views
