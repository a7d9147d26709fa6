#include "hoidslam/dense/floor.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hoidslam::dense {
namespace {

// A horizontal patch of `n` × `n` points 2 cm apart at height `y_down` (world y points down, as the first camera's
// does), centred on (x, z), normals up.
void AddPatch(OrientedPoints& surface, double y_down, double x, double z, int n) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      surface.points.emplace_back(x + 0.02 * (i - n / 2), y_down, z + 0.02 * (j - n / 2));
      surface.normals.emplace_back(0.0, -1.0, 0.0);
    }
  }
}

TEST(EstimateFloor, TakesTheLowestWellSupportedSurfaceNotTheBiggestDesk) {
  OrientedPoints surface;
  AddPatch(surface, 1.4, 0.0, 2.5, 30);   // the floor, 1.4 m below the camera: 900 points
  AddPatch(surface, 0.7, 0.0, 1.5, 60);   // a desk top 0.7 m below it: 3,600 points
  AddPatch(surface, 1.9, 3.0, 3.0, 3);    // a few stray points below the floor
  const FloorFrame floor = EstimateFloor(surface, core::Pose::Identity());
  ASSERT_TRUE(floor.found);
  // The floor at z = 0, the desk 0.7 m above it, the camera 1.4 m, x along the camera's view.
  EXPECT_NEAR((floor.T_fw * Eigen::Vector3d(0.3, 1.4, 2.0)).z(), 0.0, 1e-6);
  EXPECT_NEAR((floor.T_fw * Eigen::Vector3d(0.0, 0.7, 1.5)).z(), 0.7, 1e-6);
  EXPECT_NEAR((floor.T_fw * Eigen::Vector3d::Zero()).z(), 1.4, 1e-6);
  EXPECT_NEAR((floor.T_fw * Eigen::Vector3d::Zero()).head<2>().norm(), 0.0, 1e-6) << "origin under the camera";
  EXPECT_NEAR((floor.T_fw.linear() * Eigen::Vector3d::UnitZ()).x(), 1.0, 1e-6);
}

TEST(EstimateFloor, FollowsTheFloorWhenTheCameraIsTilted) {
  OrientedPoints surface;
  AddPatch(surface, 1.2, 0.0, 2.0, 40);
  core::Pose tilted = core::Pose::Identity();
  tilted.linear() = Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const FloorFrame floor = EstimateFloor(surface, tilted);
  ASSERT_TRUE(floor.found);
  const Eigen::Vector3d up = floor.T_fw.linear().row(2).transpose();
  EXPECT_NEAR(up.dot(-Eigen::Vector3d::UnitY()), 1.0, 1e-6) << "up is the floor's normal, not the camera's";
}

TEST(EstimateFloor, WithoutAFloorInViewUsesTheCameraAndTheLowestSurface) {
  OrientedPoints surface;
  for (int i = 0; i < 500; ++i) {  // a wall in front, its normals towards the camera
    surface.points.emplace_back(0.01 * (i % 50) - 0.25, 0.01 * (i / 50) - 0.5 + 0.9, 2.0);
    surface.normals.emplace_back(0.0, 0.0, -1.0);
  }
  const FloorFrame floor = EstimateFloor(surface, core::Pose::Identity());
  EXPECT_FALSE(floor.found);
  EXPECT_NEAR((floor.T_fw.linear() * -Eigen::Vector3d::UnitY()).z(), 1.0, 1e-9);
  EXPECT_NEAR((floor.T_fw * Eigen::Vector3d(0.0, 0.49, 2.0)).z(), 0.0, 0.02) << "the wall's lowest point";
}

}  // namespace
}  // namespace hoidslam::dense
