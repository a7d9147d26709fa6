#include "hoidslam/slam/track/frame_placement.h"

#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hoidslam/features/orb_extractor.h"
#include "support/geometry.h"

namespace hoidslam::slam::frame_placement_test {
namespace {

using ::hoidslam::testing::PoseFromAxisAngle;

constexpr int kPoints = 60;

// A frame that saw kPoints map points (3 to 5 m away, on a grid) from `T_cw`, every keypoint exactly where the point
// projects, two in three with depth; the map holds the points, made by one keyframe at the origin.
class FramePlacementTest : public ::testing::Test {
 protected:
  FramePlacementTest() {
    std::vector<Eigen::Vector3d> positions;
    for (int i = 0; i < kPoints; ++i) {
      positions.emplace_back(-1.2 + 0.2 * (i % 12), -0.8 + 0.4 * (i / 12), 3.0 + 0.4 * (i % 6));
    }
    const auto keypoints_at = [&](const core::Pose& T_cw) {
      std::vector<cv::KeyPoint> keypoints;
      std::vector<float> depth;
      for (int i = 0; i < kPoints; ++i) {
        const Eigen::Vector3d p_c = T_cw * positions[static_cast<std::size_t>(i)];
        const Eigen::Vector2d uv = sensor_->camera.Project(p_c);
        keypoints.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.0F, 0.0F, 1.0F, i % 3);
        depth.push_back(i % 3 == 2 ? 0.0F : static_cast<float>(p_c.z()));
      }
      const cv::Mat descriptors = cv::Mat::zeros(kPoints, 32, CV_8UC1);
      return std::make_shared<const KeypointSet>(sensor_, std::move(keypoints), descriptors, std::move(depth),
                                                 std::vector<cv::Vec3b>(kPoints));
    };
    KeyFrame* keyframe = map_.CreateKeyFrame(0, 0.0, keypoints_at(core::Pose::Identity()), core::Pose::Identity());
    frame_ = std::make_unique<Frame>(1, 0.1, keypoints_at(kTrue));
    for (int i = 0; i < kPoints; ++i) {
      frame_->map_points[static_cast<std::size_t>(i)] = map_.CreateMapPoint(positions[static_cast<std::size_t>(i)], keyframe, i);
    }
  }

  // Every map point carried by `T` (world to world), as an adjustment might move a whole region.
  void MoveThePoints(const core::Pose& T) {
    for (MapPoint* point : map_.MapPoints()) point->SetPosition(T * point->position());
  }

  std::shared_ptr<const Sensor> sensor_ =
      Sensor::Make(core::CameraIntrinsics{}, 40.0, 3.0, features::ScalePyramid::Make(8, 1.2));
  const core::Pose kTrue = PoseFromAxisAngle({0.02, -0.1, 0.01}, {0.1, -0.05, 0.2});
  Map map_;
  std::unique_ptr<Frame> frame_;
};

TEST_F(FramePlacementTest, RecordsTheInliersOnlyAndTheirMeasurementsToAFraction) {
  frame_->outlier[3] = 1;
  frame_->map_points[7] = nullptr;
  const std::vector<RecordedInlier> inliers = RecordInliers(*frame_);
  ASSERT_EQ(inliers.size(), static_cast<std::size_t>(kPoints - 2));
  for (const RecordedInlier& inlier : inliers) {
    const int i = static_cast<int>(inlier.point());  // the points were made in keypoint order
    EXPECT_NE(i, 3);
    EXPECT_NE(i, 7);
    const Eigen::Vector2d& uv = frame_->keypoints->undistorted(i);
    EXPECT_NEAR(inlier.uv().x(), uv.x(), 0.125);
    EXPECT_NEAR(inlier.uv().y(), uv.y(), 0.125);
    EXPECT_EQ(inlier.level(), frame_->keypoints->level(i));
    ASSERT_EQ(inlier.has_depth(), frame_->keypoints->has_depth(i));
    if (inlier.has_depth()) {
      EXPECT_NEAR(inlier.disparity(), uv.x() - frame_->keypoints->right(i), 0.125);
    }
  }
}

TEST(RecordedInlierTest, WhatItCannotHoldIsNotRecorded) {
  EXPECT_TRUE(RecordedInlier::Make((1 << 24) - 1, {2047.0, 2047.0}, 7, 511.0));
  EXPECT_FALSE(RecordedInlier::Make(1 << 24, {100.0, 100.0}, 0, std::nullopt));
  EXPECT_FALSE(RecordedInlier::Make(0, {-1.0, 100.0}, 0, std::nullopt));
  EXPECT_FALSE(RecordedInlier::Make(0, {100.0, 2048.0}, 0, std::nullopt));
  EXPECT_FALSE(RecordedInlier::Make(0, {100.0, 100.0}, 8, std::nullopt));
  EXPECT_FALSE(RecordedInlier::Make(0, {100.0, 100.0}, 0, 512.0));
  // The smallest disparity still reads as depth.
  const auto far = RecordedInlier::Make(5, {100.0, 100.0}, 2, 0.01);
  ASSERT_TRUE(far);
  EXPECT_TRUE(far->has_depth());
  EXPECT_EQ(far->point(), 5U);
  EXPECT_EQ(far->level(), 2);
}

// The adjustment moved the points the frame saw (and its keyframe, which would carry the frame, by something else):
// placed again, the frame stands where those points now put it.
TEST_F(FramePlacementTest, AFrameIsPlacedWhereItsPointsNowPutIt) {
  const std::vector<RecordedInlier> inliers = RecordInliers(*frame_);
  const core::Pose moved = PoseFromAxisAngle({0.0, 0.03, 0.0}, {0.04, 0.0, -0.02});
  MoveThePoints(moved);
  const core::Pose expected = kTrue * moved.inverse();
  const core::Pose carried = PoseFromAxisAngle({0.01, 0.0, 0.0}, {0.0, 0.03, 0.0}) * kTrue;  // a start off both
  const std::optional<core::Pose> placed = PlaceByInliers(map_, inliers, *sensor_, carried);
  ASSERT_TRUE(placed);
  // Within what the recorded measurements' rounding allows (a millimetre at 3–5 m); it started 3 cm off.
  EXPECT_LT((placed->translation() - expected.translation()).norm(), 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(placed->linear() * expected.linear().transpose()).angle(), 5e-4);  // started at 0.01
}

TEST_F(FramePlacementTest, APointFusedIntoAnotherIsFollowedAndAnErasedOneLeftOut) {
  const std::vector<RecordedInlier> inliers = RecordInliers(*frame_);
  // Point 0 fused into point 1 (a duplicate at another place): the frame's keypoint 0 now measures point 1, an
  // outlier. Points 2–9 erased. The rest still place the frame where it was.
  map_.ReplacePoint(frame_->map_points[0], frame_->map_points[1]);
  for (int i = 2; i < 10; ++i) map_.ErasePoint(frame_->map_points[static_cast<std::size_t>(i)]);
  const std::optional<core::Pose> placed = PlaceByInliers(map_, inliers, *sensor_, kTrue);
  ASSERT_TRUE(placed);
  EXPECT_LT((placed->translation() - kTrue.translation()).norm(), 1e-3);
}

TEST_F(FramePlacementTest, AFrameWhosePointsNoLongerAgreeIsNotPlaced) {
  const std::vector<RecordedInlier> inliers = RecordInliers(*frame_);
  // Two thirds of the points thrown 0.5 m apart at random: the rest are too few to place the frame.
  cv::RNG rng(3);
  for (int i = 0; i < kPoints; ++i) {
    if (i % 3 == 0) continue;
    MapPoint* point = frame_->map_points[static_cast<std::size_t>(i)];
    point->SetPosition(point->position() + 0.5 * Eigen::Vector3d(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), 0.0));
  }
  EXPECT_FALSE(PlaceByInliers(map_, inliers, *sensor_, kTrue));
  // And a frame left with fewer than kMinPlacementInliers points in the map.
  for (int i = kMinPlacementInliers - 1; i < kPoints; ++i) map_.ErasePoint(frame_->map_points[static_cast<std::size_t>(i)]);
  EXPECT_FALSE(PlaceByInliers(map_, RecordInliers(*frame_), *sensor_, kTrue));
}

}  // namespace
}  // namespace hoidslam::slam::frame_placement_test
