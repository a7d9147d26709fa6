#include "hoidslam/dense/tsdf_volume.h"

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>

#include "hoidslam/dense/test_views.h"
#include "support/input_error.h"
#include "support/temp_dir.h"

namespace hoidslam::dense {
namespace {

using test_views::CoarseOptions;
using test_views::ReadCloud;
using test_views::SmallCamera;

// What a camera at T_wc sees of the plane z = `wall` (world): depth per pixel, 0 where the ray misses it.
cv::Mat WallDepth(const core::CameraIntrinsics& camera, const core::Pose& T_wc, double wall) {
  cv::Mat depth(camera.height, camera.width, CV_32FC1, cv::Scalar(0.0F));
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray_c = camera.Unproject(u, v, 1.0);  // depth 1 along the optical axis
      const Eigen::Vector3d ray_w = T_wc.linear() * ray_c;
      const double t = (wall - T_wc.translation().z()) / ray_w.z();
      if (t > 0.0) depth.at<float>(v, u) = static_cast<float>(t);
    }
  }
  return depth;
}

core::Pose CameraAt(double x, double yaw_degrees) {
  core::Pose T_wc = core::Pose::Identity();
  T_wc.linear() = Eigen::AngleAxisd(yaw_degrees * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T_wc.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return T_wc;
}

TEST(TsdfVolume, AWallSeenFromTwoPlacesBecomesAFlatColouredMeshWhereTheWallIs) {
  const core::CameraIntrinsics camera = SmallCamera();
  TsdfVolume volume(CoarseOptions(), camera);
  const cv::Mat red(camera.height, camera.width, CV_8UC3, cv::Scalar(0, 0, 255));  // BGR
  for (const core::Pose& T_wc : {CameraAt(0.0, 0.0), CameraAt(0.3, -10.0)}) {
    volume.Integrate(red, WallDepth(camera, T_wc, 1.5), T_wc);
  }
  EXPECT_GT(volume.Blocks(), 0U);
  EXPECT_EQ(volume.MemoryBytes(), volume.Blocks() * 16 * 16 * 16 * 48);

  const testing::TempDir dir;
  const MeshCounts mesh = volume.WriteMesh(dir / "mesh.ply");
  EXPECT_GT(mesh.triangles, 100U);
  // The wall seen: about 1.7 m × 1.3 m at 1.5 m with a 60° field of view; a mesh that doubled it would be wrong.
  EXPECT_GT(mesh.area, 1.5);
  EXPECT_LT(mesh.area, 4.0);
  const std::size_t points = volume.WriteCloud(dir / "cloud.ply");
  EXPECT_GT(points, 100U);
  const open3d::geometry::PointCloud cloud = ReadCloud(dir / "cloud.ply");
  ASSERT_EQ(cloud.points_.size(), points);
  ASSERT_TRUE(cloud.HasColors());
  for (std::size_t i = 0; i < points; ++i) {
    ASSERT_NEAR(cloud.points_[i].z(), 1.5, 0.01) << "every fused point lies on the wall";
    ASSERT_NEAR(cloud.colors_[i].x(), 1.0, 0.01) << "in the wall's colour, red";
    ASSERT_NEAR(cloud.colors_[i].z(), 0.0, 0.01);
  }
  const OrientedPoints sample = volume.SamplePoints(10);
  ASSERT_FALSE(sample.points.empty());
  EXPECT_LT(sample.normals.front().z(), -0.9) << "normals face the cameras";
}

TEST(TsdfVolume, DepthLeftOutIsNotFused) {
  const core::CameraIntrinsics camera = SmallCamera();
  TsdfVolume volume(CoarseOptions(), camera);
  const cv::Mat grey(camera.height, camera.width, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::Mat depth = WallDepth(camera, core::Pose::Identity(), 1.5);
  depth.colRange(40, 80).setTo(0.0F);  // the right half left out
  volume.Integrate(grey, depth, core::Pose::Identity());
  const testing::TempDir dir;
  volume.WriteCloud(dir / "cloud.ply");
  const open3d::geometry::PointCloud cloud = ReadCloud(dir / "cloud.ply");
  ASSERT_FALSE(cloud.points_.empty());
  for (const Eigen::Vector3d& p : cloud.points_) ASSERT_LT(p.x(), 0.1) << "nothing right of the image centre";
}

TEST(TsdfVolume, WhatTheFilterNamesIsLeftOutOfTheMeshAndTheCloud) {
  const core::CameraIntrinsics camera = SmallCamera();
  TsdfVolume volume(CoarseOptions(), camera);
  const cv::Mat grey(camera.height, camera.width, CV_8UC3, cv::Scalar(128, 128, 128));
  volume.Integrate(grey, WallDepth(camera, core::Pose::Identity(), 1.5), core::Pose::Identity());
  const testing::TempDir dir;
  const MeshCounts whole = volume.WriteMesh(dir / "whole.ply");
  const std::size_t whole_points = volume.WriteCloud(dir / "whole_cloud.ply");
  const PointFilter right_half = [](const Eigen::Vector3d& p_w) { return p_w.x() > 0.0; };

  const MeshCounts left = volume.WriteMesh(dir / "mesh.ply", right_half);
  EXPECT_GT(left.left_out, 0U);
  EXPECT_EQ(left.vertices + left.left_out, whole.vertices);
  EXPECT_LT(left.triangles, whole.triangles);
  EXPECT_NEAR(left.area, whole.area / 2.0, whole.area * 0.1);
  const io::TriangleMesh written = io::ReadPlyMesh(dir / "mesh.ply");
  ASSERT_EQ(written.vertices.size(), left.vertices);
  for (const Eigen::Vector3f& v : written.vertices) ASSERT_LE(v.x(), 0.0F);
  for (const Eigen::Vector3i& triangle : written.triangles) {
    ASSERT_LT(triangle.maxCoeff(), static_cast<int>(written.vertices.size())) << "no triangle keeps a vertex left out";
  }

  const std::size_t points = volume.WriteCloud(dir / "cloud.ply", right_half);
  EXPECT_GT(points, 0U);
  EXPECT_LT(points, whole_points);
  const open3d::geometry::PointCloud cloud = ReadCloud(dir / "cloud.ply");
  ASSERT_EQ(cloud.points_.size(), points);
  ASSERT_TRUE(cloud.HasColors());
  for (const Eigen::Vector3d& p : cloud.points_) ASSERT_LE(p.x(), 0.0);
}

TEST(TsdfVolume, DepthBeyondTheMaxDepthIsNotFused) {
  const core::CameraIntrinsics camera = SmallCamera();
  DenseOptions options = CoarseOptions();
  options.max_depth = 1.4;
  TsdfVolume volume(options, camera);
  const cv::Mat grey(camera.height, camera.width, CV_8UC3, cv::Scalar(128, 128, 128));
  volume.Integrate(grey, WallDepth(camera, core::Pose::Identity(), 1.5), core::Pose::Identity());
  EXPECT_EQ(volume.Blocks(), 0U);
}

TEST(TsdfVolume, RefusesImagesOfAnotherSize) {
  TsdfVolume volume(DenseOptions{}, SmallCamera());
  EXPECT_THROW(volume.Integrate(cv::Mat(10, 10, CV_8UC3), cv::Mat(10, 10, CV_32FC1), core::Pose::Identity()),
               std::invalid_argument);
}

TEST(TsdfVolume, AFileThatCannotBeWrittenIsNamed) {
  const core::CameraIntrinsics camera = SmallCamera();
  TsdfVolume volume(CoarseOptions(), camera);
  const cv::Mat grey(camera.height, camera.width, CV_8UC3, cv::Scalar(128, 128, 128));
  volume.Integrate(grey, WallDepth(camera, core::Pose::Identity(), 1.5), core::Pose::Identity());
  EXPECT_NE(testing::InputErrorOf([&] { volume.WriteMesh("/nonexistent-folder/mesh.ply"); })
                .find("/nonexistent-folder/mesh.ply"),
            std::string::npos);
}

}  // namespace
}  // namespace hoidslam::dense
