#include "hoidslam/slam/tracker.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace hoidslam::slam::tracker_test {
namespace {

core::Pose MakePose(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& translation) {
  core::Pose pose = core::Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

// A keyframe and a frame tracked 12 cm beside it, slightly turned (world to camera).
const core::Pose kKeyFrame = MakePose(0.3, {0.0, 1.0, 0.0}, {0.5, -0.2, 1.1});
const core::Pose kFrame = MakePose(0.05, {0.2, 1.0, 0.1}, {0.0, 0.0, 0.12}) * kKeyFrame;

TEST(FollowKeyFrameTest, AFrameWhoseKeyFrameStayedKeepsItsPoseBitForBit) {
  const core::Pose followed = FollowKeyFrame(kFrame, kKeyFrame, kKeyFrame);
  EXPECT_TRUE(followed.matrix() == kFrame.matrix());
}

// A merge carries the keyframe's whole map into another map's world frame (here 1.2 m and 40° away): a frame tracked
// in the old world frame just before must land beside the keyframe where it now stands, not 1.2 m away.
TEST(FollowKeyFrameTest, AFrameMovesWithItsKeyFrameIntoAnotherWorldFrame) {
  const core::Pose T_old_new = MakePose(0.7, {0.1, 1.0, -0.2}, {1.2, 0.1, -0.3});  // new world into old world
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
  const core::Pose correction = MakePose(0.02, {0.0, 0.0, 1.0}, {0.03, 0.0, -0.01});  // in the keyframe's camera
  const core::Pose keyframe_now = correction * kKeyFrame;
  const core::Pose followed = FollowKeyFrame(kFrame, kKeyFrame, keyframe_now);
  EXPECT_TRUE((followed * keyframe_now.inverse()).matrix().isApprox((kFrame * kKeyFrame.inverse()).matrix(), 1e-12));
}

}  // namespace
}  // namespace hoidslam::slam::tracker_test
