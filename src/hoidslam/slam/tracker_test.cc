#include "hoidslam/slam/tracker.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "support/geometry.h"

namespace hoidslam::slam::tracker_test {
namespace {

using ::hoidslam::testing::PoseFromAxisAngle;

// A keyframe and a frame tracked 12 cm beside it, slightly turned (world to camera).
const core::Pose kKeyFrame = PoseFromAxisAngle({0.0, 0.3, 0.0}, {0.5, -0.2, 1.1});
const core::Pose kFrame =
    PoseFromAxisAngle(0.05 * Eigen::Vector3d(0.2, 1.0, 0.1).normalized(), {0.0, 0.0, 0.12}) * kKeyFrame;

TEST(FollowKeyFrameTest, AFrameWhoseKeyFrameStayedKeepsItsPoseBitForBit) {
  const core::Pose followed = FollowKeyFrame(kFrame, kKeyFrame, kKeyFrame);
  EXPECT_TRUE(followed.matrix() == kFrame.matrix());
}

// A merge carries the keyframe's whole map into another map's world frame (here 1.2 m and 40° away): a frame tracked
// in the old world frame just before must land beside the keyframe where it now stands, not 1.2 m away.
TEST(FollowKeyFrameTest, AFrameMovesWithItsKeyFrameIntoAnotherWorldFrame) {
  // The new world frame into the old one.
  const core::Pose T_old_new = PoseFromAxisAngle(0.7 * Eigen::Vector3d(0.1, 1.0, -0.2).normalized(), {1.2, 0.1, -0.3});
  const core::Pose keyframe_now = kKeyFrame * T_old_new;
  const core::Pose followed = FollowKeyFrame(kFrame, kKeyFrame, keyframe_now);

  const core::Pose relative_then = kFrame * kKeyFrame.inverse();
  const core::Pose relative_now = followed * keyframe_now.inverse();
  EXPECT_TRUE(relative_now.matrix().isApprox(relative_then.matrix(), 1e-12));
  EXPECT_TRUE(followed.matrix().isApprox((kFrame * T_old_new).matrix(), 1e-12));
  EXPECT_GT((followed.inverse().translation() - kFrame.inverse().translation()).norm(), 0.5);
}

// A loop correction moves the keyframe by a few centimetres: the frame moves by as much, its offset kept.
TEST(FollowKeyFrameTest, AFrameFollowsALoopCorrectionOfItsKeyFrame) {
  const core::Pose correction = PoseFromAxisAngle({0.0, 0.0, 0.02}, {0.03, 0.0, -0.01});  // in the keyframe's camera
  const core::Pose keyframe_now = correction * kKeyFrame;
  const core::Pose followed = FollowKeyFrame(kFrame, kKeyFrame, keyframe_now);
  EXPECT_TRUE((followed * keyframe_now.inverse()).matrix().isApprox((kFrame * kKeyFrame.inverse()).matrix(), 1e-12));
}

}  // namespace
}  // namespace hoidslam::slam::tracker_test
