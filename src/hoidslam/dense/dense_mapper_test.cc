#include "hoidslam/dense/dense_mapper.h"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/dense/test_views.h"
#include "support/temp_dir.h"

namespace hoidslam::dense {
namespace {

// An 80×60 camera in front of a wall 1.5 m away (its depth constant along the optical axis), a "person" 0.8 m away
// in the middle of the image, marked as left out.
struct WallScene {
  core::CameraIntrinsics camera = test_views::SmallCamera();
  core::RgbdFrame Frame(double timestamp) const {
    core::RgbdFrame frame;
    frame.timestamp = timestamp;
    frame.rgb = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar(200, 150, 100));
    frame.depth = cv::Mat(camera.height, camera.width, CV_32FC1, cv::Scalar(1.5F));
    frame.depth(Person()).setTo(0.8F);
    return frame;
  }
  cv::Rect Person() const { return {30, 10, 20, 50}; }
  cv::Mat LeftOut() const {
    cv::Mat mask(camera.height, camera.width, CV_8UC1, cv::Scalar(0));
    mask(Person()).setTo(255);
    return mask;
  }
};

using test_views::CoarseOptions;
using test_views::ReadCloud;

TEST(DenseMapper, FusesTheFinalKeyFramesAtTheirFinalPosesWithoutWhatWasLeftOut) {
  const WallScene scene;
  DenseMapper mapper(CoarseOptions(), scene.camera);
  for (const double t : {1.0, 2.0, 3.0}) mapper.AddKeyFrame(scene.Frame(t), scene.LeftOut());
  // The map kept keyframes 1 and 3 (2 was culled), and moved both 10 cm to the left; one more comes from a loaded map.
  core::Pose moved = core::Pose::Identity();
  moved.translation() = Eigen::Vector3d(-0.1, 0.0, 0.0);
  const testing::TempDir dir;
  const DenseSummary summary = mapper.Build({{1.0, moved}, {3.0, moved}, {4.0, moved}}, dir.path());
  EXPECT_TRUE(summary.written);
  EXPECT_EQ(summary.keyframes, 2U);
  EXPECT_EQ(summary.keyframes_without_images, 1U);
  EXPECT_EQ(summary.fuse_ms.size(), 2U);
  EXPECT_GT(summary.mesh.triangles, 0U);
  EXPECT_GT(summary.occupied_cells, 0U);
  for (const char* file : kDenseOutputs) EXPECT_TRUE(std::filesystem::is_regular_file(dir / file)) << file;

  const open3d::geometry::PointCloud cloud = ReadCloud(dir / "cloud.ply");
  ASSERT_FALSE(cloud.points_.empty());
  for (const Eigen::Vector3d& p : cloud.points_) {
    ASSERT_NEAR(p.z(), 1.5, 0.02) << "only the wall, never the person 0.8 m away";
  }
  // The wall behind the person is a hole (no other view saw it); around it the wall is there, shifted with the pose.
  const double fx = scene.camera.fx;
  const double person_left = (scene.Person().x - scene.camera.cx) * 1.5 / fx - 0.1;
  const double person_right = (scene.Person().br().x - scene.camera.cx) * 1.5 / fx - 0.1;
  std::size_t behind_person = 0, beside = 0;
  for (const Eigen::Vector3d& p : cloud.points_) {
    if (p.y() < -0.3) continue;  // the rows the person covers (10 to 59: from y = -0.43 m down)
    if (p.x() > person_left + 0.08 && p.x() < person_right - 0.08) ++behind_person;
    if (p.x() < person_left - 0.08) ++beside;
  }
  EXPECT_EQ(behind_person, 0U);
  EXPECT_GT(beside, 10U);
}

TEST(DenseMapper, ChecksThePersonBoxesForPeopleTheMapKept) {
  // The detector's box is wider than the person and runs out of the image. Left out, the person is not in the map:
  // none of their pixels has surface at the depth measured there; fused (nothing left out), they are.
  const WallScene scene;
  const cv::Rect box(25, 5, 30, 80);
  const auto people_kept = [&](const cv::Mat& left_out) {
    DenseMapper mapper(CoarseOptions(), scene.camera);
    for (const double t : {1.0, 2.0}) mapper.AddKeyFrame(scene.Frame(t), left_out, std::nullopt, {box});
    const testing::TempDir dir;
    const DenseSummary summary = mapper.Build({{1.0, core::Pose::Identity()}, {2.0, core::Pose::Identity()}}, dir.path());
    EXPECT_TRUE(summary.people.has_value());
    return summary.people.value_or(eval::PersonSurface{});
  };
  const eval::PersonSurface left_out = people_kept(scene.LeftOut());
  EXPECT_EQ(left_out.boxes, 2U);
  EXPECT_GE(left_out.person_pixels, 2U * static_cast<std::size_t>(scene.Person().area()));
  EXPECT_LT(left_out.Share(), 0.02);
  EXPECT_GT(people_kept(cv::Mat()).Share(), 0.9);

  DenseMapper without_boxes(CoarseOptions(), scene.camera);
  without_boxes.AddKeyFrame(scene.Frame(1.0), scene.LeftOut());
  const testing::TempDir dir;
  EXPECT_FALSE(without_boxes.Build({{1.0, core::Pose::Identity()}}, dir.path()).people.has_value());
}

TEST(DenseMapper, UndistortsTheKeyFramesOfACameraWithDistortion) {
  // A wall 1.5 m away seen through a lens with strong barrel distortion, a gap in it at world x in [0.5, 0.7] m: each
  // distorted pixel shows the wall point its undistorted ray meets.
  WallScene scene;
  scene.camera.k1 = -0.5;
  const cv::Matx33d K(scene.camera.fx, 0, scene.camera.cx, 0, scene.camera.fy, scene.camera.cy, 0, 0, 1);
  std::vector<cv::Point2f> distorted, normalized;
  for (int v = 0; v < scene.camera.height; ++v) {
    for (int u = 0; u < scene.camera.width; ++u) distorted.emplace_back(u, v);
  }
  cv::undistortPoints(distorted, normalized, K, cv::Vec<double, 5>(scene.camera.k1, 0, 0, 0, 0));
  core::RgbdFrame frame = scene.Frame(1.0);
  frame.depth.setTo(1.5F);
  for (std::size_t i = 0; i < distorted.size(); ++i) {
    const double x = 1.5 * normalized[i].x;
    if (x > 0.5 && x < 0.7) frame.depth.at<float>(static_cast<int>(distorted[i].y), static_cast<int>(distorted[i].x)) = 0.0F;
  }
  DenseOptions options = CoarseOptions();
  options.mask_margin = 0;
  DenseMapper mapper(options, scene.camera);
  mapper.AddKeyFrame(frame, cv::Mat());
  const testing::TempDir dir;
  ASSERT_TRUE(mapper.Build({{1.0, core::Pose::Identity()}}, dir.path()).written);
  std::size_t in_gap = 0, beside = 0;
  for (const Eigen::Vector3d& p : ReadCloud(dir / "cloud.ply").points_) {
    if (p.x() > 0.53 && p.x() < 0.67) ++in_gap;
    if (p.x() > 0.25 && p.x() < 0.45) ++beside;
  }
  EXPECT_EQ(in_gap, 0U) << "the gap where the world has it";
  EXPECT_GT(beside, 20U);
}

TEST(DenseMapper, WritesNoEmptyFilesWhenThereIsNothingToFuse) {
  const WallScene scene;
  DenseMapper mapper(CoarseOptions(), scene.camera);
  core::RgbdFrame blank = scene.Frame(1.0);
  blank.depth.setTo(0.0F);
  mapper.AddKeyFrame(blank, cv::Mat());
  const testing::TempDir dir;
  const DenseSummary summary = mapper.Build({{1.0, core::Pose::Identity()}}, dir.path());
  EXPECT_EQ(summary.keyframes, 1U);
  EXPECT_FALSE(summary.written);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(DenseMapper, TakesNoKeyFrameAfterTheBuild) {
  const WallScene scene;
  DenseMapper mapper(CoarseOptions(), scene.camera);
  const testing::TempDir dir;
  EXPECT_FALSE(mapper.Build({}, dir.path()).written);
  EXPECT_THROW(mapper.AddKeyFrame(scene.Frame(1.0), cv::Mat()), std::logic_error);
}

TEST(DenseMapper, APreviewGrowsFromTheKeyFramesAtThePosesTrackingGaveThemUntilTheBuild) {
  const WallScene scene;
  DenseMapper mapper(CoarseOptions(), scene.camera);
  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<io::TriangleMesh> meshes;
  PreviewOptions preview;
  preview.interval_s = 0.02;
  mapper.FollowPreview(preview, [&](io::TriangleMesh mesh) {
    {
      const std::lock_guard lock(mutex);
      meshes.push_back(std::move(mesh));
    }
    arrived.notify_all();
  });
  EXPECT_THROW(mapper.FollowPreview(preview, [](io::TriangleMesh) {}), std::logic_error);
  // A keyframe without a pose stays out of the preview (at the origin it would put a wall at z = 1.5 m); one
  // tracked 0.3 m forward puts the wall at 1.8 m, and never the person, left out.
  core::Pose forward = core::Pose::Identity();
  forward.translation() = Eigen::Vector3d(0.0, 0.0, 0.3);
  mapper.AddKeyFrame(scene.Frame(1.0), scene.LeftOut());
  mapper.AddKeyFrame(scene.Frame(2.0), scene.LeftOut(), forward);
  {
    std::unique_lock lock(mutex);
    ASSERT_TRUE(arrived.wait_for(lock, std::chrono::seconds(30), [&] { return !meshes.empty(); }));
    ASSERT_FALSE(meshes.back().triangles.empty());
    for (const Eigen::Vector3f& v : meshes.back().vertices) ASSERT_NEAR(v.z(), 1.8F, preview.voxel_size);
  }

  const testing::TempDir dir;
  EXPECT_EQ(mapper.Build({{1.0, core::Pose::Identity()}, {2.0, forward}}, dir.path()).keyframes, 2U);
  std::size_t shown = 0;
  {
    const std::lock_guard lock(mutex);
    shown = meshes.size();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  {
    const std::lock_guard lock(mutex);
    EXPECT_EQ(meshes.size(), shown) << "no preview after the build";
  }
  EXPECT_THROW(mapper.FollowPreview(preview, [](io::TriangleMesh) {}), std::logic_error);
}

TEST(DenseMapper, RefusesBadOptionsBeforeAnyKeyFrame) {
  DenseOptions options;
  options.voxel_size = 0.0;
  EXPECT_THROW(DenseMapper mapper(options, WallScene().camera), core::InputError);
}

}  // namespace
}  // namespace hoidslam::dense
