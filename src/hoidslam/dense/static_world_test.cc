#include "hoidslam/dense/static_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "hoidslam/dense/test_views.h"
#include "hoidslam/io/ply_file.h"
#include "support/temp_dir.h"

namespace hoidslam::dense {
namespace {

using test_views::CoarseOptions;
using test_views::ReadCloud;
using test_views::SmallCamera;

// Off the occupancy map's 5 cm cell borders, so that each surface lies inside one layer of cells.
constexpr double kWall = 2.025;
constexpr double kPerson = 1.025;

// A camera at the origin looking along +z at a wall, and, when `person`, a person standing in the middle of the
// view (a plate across the middle half of the image) in front of it.
cv::Mat Depth(const core::CameraIntrinsics& camera, bool person) {
  cv::Mat depth(camera.height, camera.width, CV_32FC1, cv::Scalar(static_cast<float>(kWall)));
  if (person) {
    depth(cv::Rect(camera.width / 4, camera.height / 4, camera.width / 2, camera.height / 2))
        .setTo(static_cast<float>(kPerson));
  }
  return depth;
}

core::Pose Sideways(double x) {
  core::Pose T_wc = core::Pose::Identity();
  T_wc.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return T_wc;
}

// The person as the filter missed them in the first keyframe; the four after it see the wall through where they
// stood.
void FuseAMissedPerson(StaticWorld& world) {
  const core::CameraIntrinsics camera = SmallCamera();
  const cv::Mat grey(camera.height, camera.width, CV_8UC3, cv::Scalar(128, 128, 128));
  world.Fuse(grey, Depth(camera, /*person=*/true), core::Pose::Identity());
  for (const double x : {0.0, 0.02, -0.02, 0.04}) world.Fuse(grey, Depth(camera, /*person=*/false), Sideways(x));
}

DenseOptions EveryPixelARay() {
  DenseOptions options = CoarseOptions();
  options.occupancy.pixel_step = 1;
  return options;
}

std::size_t VerticesNear(const io::TriangleMesh& mesh, double z) {
  return static_cast<std::size_t>(std::count_if(mesh.vertices.begin(), mesh.vertices.end(), [z](const auto& v) {
    return std::abs(v.z() - z) < 0.05;
  }));
}

TEST(StaticWorld, SurfaceThatLaterKeyFramesSawThroughIsLeftOutOfTheMeshAndTheCloud) {
  StaticWorld world(EveryPixelARay(), SmallCamera());
  FuseAMissedPerson(world);
  EXPECT_TRUE(world.SeenThrough({0.0, 0.0, kPerson}));
  EXPECT_FALSE(world.SeenThrough({0.0, 0.0, kWall}));
  EXPECT_EQ(world.occupancy().At({0.0, 0.0, kWall}), CellState::kOccupied);

  const testing::TempDir dir;
  const MeshCounts counts = world.WriteMesh(dir / "mesh.ply");
  EXPECT_GT(counts.left_out, 100U);
  const io::TriangleMesh mesh = io::ReadPlyMesh(dir / "mesh.ply");
  EXPECT_EQ(VerticesNear(mesh, kPerson), 0U) << "the person the filter missed is not in the map";
  EXPECT_GT(VerticesNear(mesh, kWall), 500U) << "the wall behind them is";
  world.WriteCloud(dir / "cloud.ply");
  for (const Eigen::Vector3d& p : ReadCloud(dir / "cloud.ply").points_) ASSERT_NEAR(p.z(), kWall, 0.05);
}

TEST(StaticWorld, AWallTooFarToMapStillShowsThatTheSpaceBeforeItIsFree) {
  DenseOptions options = EveryPixelARay();
  options.max_depth = 1.6;  // the person at 1 m is fused, the wall at 2 m is not
  StaticWorld world(options, SmallCamera());
  FuseAMissedPerson(world);
  EXPECT_TRUE(world.SeenThrough({0.0, 0.0, kPerson}));
  EXPECT_EQ(world.occupancy().At({0.0, 0.0, kWall}), CellState::kUnknown) << "a cut ray marks no surface";
  const testing::TempDir dir;
  const MeshCounts counts = world.WriteMesh(dir / "mesh.ply");
  EXPECT_GT(counts.left_out, 100U);
  EXPECT_EQ(counts.vertices, 0U) << "nothing was left: the person seen through, the wall beyond the range";
  EXPECT_EQ(world.WriteCloud(dir / "cloud.ply"), 0U);
  EXPECT_FALSE(std::filesystem::exists(dir / "mesh.ply")) << "no surface, no file";
  EXPECT_FALSE(std::filesystem::exists(dir / "cloud.ply"));
}

TEST(StaticWorld, KeepsWhatWasSeenThroughWhenAsked) {
  DenseOptions options = EveryPixelARay();
  options.keep_seen_through = true;
  StaticWorld world(options, SmallCamera());
  FuseAMissedPerson(world);
  const testing::TempDir dir;
  EXPECT_EQ(world.WriteMesh(dir / "mesh.ply").left_out, 0U);
  EXPECT_GT(VerticesNear(io::ReadPlyMesh(dir / "mesh.ply"), kPerson), 100U)
      << "the volume alone keeps the person: the later views changed only the voxels near the wall";
}

}  // namespace
}  // namespace hoidslam::dense
