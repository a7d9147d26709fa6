#include "hoidslam/eval/dense_score.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace hoidslam::eval {
namespace {

// Adds a box (centre, half sizes) with outward-facing triangles.
void AddBox(io::TriangleMesh& mesh, const Eigen::Vector3f& centre, const Eigen::Vector3f& half) {
  const int first = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.push_back(centre + Eigen::Vector3f((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                                                     (i & 4) ? half.z() : -half.z()));
  }
  const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) mesh.triangles.emplace_back(first + f[0], first + f[1], first + f[2]);
}

// A square in the plane z = `z`, facing -z (towards a camera at the origin).
void AddSquare(io::TriangleMesh& mesh, float z, float half_x, float half_y) {
  const int first = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(-half_x, -half_y, z);
  mesh.vertices.emplace_back(half_x, -half_y, z);
  mesh.vertices.emplace_back(-half_x, half_y, z);
  mesh.vertices.emplace_back(half_x, half_y, z);
  mesh.triangles.emplace_back(first, first + 2, first + 1);
  mesh.triangles.emplace_back(first + 1, first + 2, first + 3);
}

// A wall 1.95 m in front of a camera that never moves (TUM fr3 camera); someone once stood at 1 m.
DenseTruth WallTruth() {
  DenseTruth truth;
  AddBox(truth.static_geometry, {0.0F, 0.0F, 2.0F}, {3.0F, 2.0F, 0.05F});
  truth.moving_volume.voxel_size = 0.02;
  for (int x = -10; x < 10; ++x) {
    for (int y = -10; y < 10; ++y) {
      for (int z = 45; z < 55; ++z) truth.moving_volume.centres.emplace_back(0.02F * (x + 0.5F), 0.02F * (y + 0.5F), 0.02F * (z + 0.5F));
    }
  }
  // Two views from where the camera stands, each measuring the wall's depth at every pixel.
  for (int i = 0; i < 2; ++i) {
    truth.views.push_back({core::Pose::Identity(), cv::Mat(truth.camera.height, truth.camera.width, CV_32FC1,
                                                           cv::Scalar(1.95F))});
  }
  return truth;
}

TEST(ScoreDenseMap, AnExactWallIsAccurateCompleteWhereItReachesAndHasNoGhost) {
  const DenseTruth truth = WallTruth();
  io::TriangleMesh wall;
  AddSquare(wall, 1.95F, 3.0F, 2.0F);  // the whole wall face
  const DenseScore whole = ScoreDenseMap(wall, nullptr, 0.05, Alignment{}, truth);
  EXPECT_NEAR(whole.accuracy_mean, 0.0, 1e-4);
  EXPECT_NEAR(whole.accuracy_p90, 0.0, 1e-4);
  EXPECT_NEAR(whole.completeness, 1.0, 1e-9);
  EXPECT_NEAR(whole.area, 24.0, 1e-3);
  EXPECT_EQ(whole.ghost_area, 0.0);
  // The camera sees about ±1.17 m × ±0.87 m of the wall (4.1 m²): some 10,000 samples 2 cm apart.
  EXPECT_GT(whole.seen_samples, 8000U);
  EXPECT_LT(whole.seen_samples, 12000U);

  io::TriangleMesh half;
  AddSquare(half, 1.95F, 0.585F, 0.87F);  // half of what the camera saw, in x
  EXPECT_NEAR(ScoreDenseMap(half, nullptr, 0.05, Alignment{}, truth).completeness, 0.5, 0.05);
}

TEST(ScoreDenseMap, SurfaceAPersonHidInEveryViewIsNotCountedAsMissing) {
  DenseTruth truth = WallTruth();
  for (DenseTruth::View& view : truth.views) view.depth.colRange(320, 640).setTo(1.0F);  // someone in front, right
  io::TriangleMesh left;
  AddSquare(left, 1.95F, 3.0F, 2.0F);
  for (Eigen::Vector3f& v : left.vertices) v.x() = std::min(v.x(), 0.0F);  // the wall's left half only
  const DenseScore score = ScoreDenseMap(left, nullptr, 0.05, Alignment{}, truth);
  EXPECT_NEAR(score.completeness, 1.0, 0.01);
  EXPECT_LT(score.seen_samples, 6000U);  // half of the ~10,000 the whole view holds
}

TEST(ScoreDenseMap, APersonFusedIntoTheMapIsAGhostInTheMeshAndInTheOccupancy) {
  const DenseTruth truth = WallTruth();
  io::TriangleMesh map;
  AddSquare(map, 1.95F, 1.0F, 1.0F);  // 4 m² of wall
  AddSquare(map, 1.0F, 0.25F, 0.5F);  // 0.5 m² of the person, a metre from the wall
  const std::vector<Eigen::Vector3d> occupied = {{0.0, 0.0, 1.0}, {0.1, 0.1, 0.95}, {0.0, 0.0, 1.95}, {2.0, 1.0, 1.95}};
  const DenseScore score = ScoreDenseMap(map, &occupied, 0.05, Alignment{}, truth);
  EXPECT_NEAR(score.area, 4.5, 1e-3);
  EXPECT_NEAR(score.ghost_area, 0.5, 1e-3);
  EXPECT_NEAR(score.GhostShare(), 0.5 / 4.5, 1e-3);
  EXPECT_GT(score.accuracy_p90, 0.9);  // half of the vertices are the person's, 0.95 m from the wall
  EXPECT_EQ(score.occupied_cells, 4U);
  EXPECT_EQ(score.ghost_cells, 2U) << "the cells where the person stood, not the wall's";
}

TEST(ScoreDenseMap, TheReconstructionIsScoredAfterTheTrajectorysAlignment) {
  const DenseTruth truth = WallTruth();
  // The estimate's world frame is the truth's turned 30° about y and shifted: the alignment takes it back.
  Alignment alignment;
  alignment.rotation = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitY()).toRotationMatrix();
  alignment.translation = Eigen::Vector3d(0.3, -0.2, 0.1);
  io::TriangleMesh wall;
  AddSquare(wall, 1.95F, 3.0F, 2.0F);
  for (Eigen::Vector3f& v : wall.vertices) {
    v = (alignment.rotation.transpose() * (v.cast<double>() - alignment.translation)).cast<float>();
  }
  const DenseScore score = ScoreDenseMap(wall, nullptr, 0.05, alignment, truth);
  EXPECT_NEAR(score.accuracy_p90, 0.0, 1e-4);
  EXPECT_NEAR(score.completeness, 1.0, 1e-9);
}

}  // namespace
}  // namespace hoidslam::eval
