#include "hoidslam/synth/people.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hoidslam::synth {
namespace {

constexpr double kPi = std::numbers::pi;

double LowestAnkle(const Skeleton& sk) { return std::min(sk.ankle[kLeft].z(), sk.ankle[kRight].z()); }

TEST(People, StandingPersonHasFeetOnTheFloorAndItsHeight) {
  const BodyShape shape;
  BodyPose pose;
  pose.position = {2.0, 3.0};
  pose.yaw = 0.7;
  const Skeleton sk = PoseSkeleton(shape, pose);
  EXPECT_NEAR(LowestAnkle(sk), shape.FootHeight(), 1e-9);
  // The top of the head (head centre plus the head's half height, scaled) is the person's height.
  EXPECT_NEAR(sk.head.z() + 0.115 * shape.height / 1.75, shape.height, 0.05 * shape.height);
  EXPECT_NEAR(sk.pelvis.x(), 2.0, 1e-9);
  EXPECT_NEAR(sk.pelvis.y(), 3.0, 1e-9);
}

TEST(People, WalkingKeepsOneFootOnTheFloorAndSegmentLengths) {
  const BodyShape shape{1.6};
  BodyPose pose;
  pose.gait_amount = 1.0;
  for (double phase = 0.0; phase < 2 * kPi; phase += 0.1) {
    pose.gait_phase = phase;
    const Skeleton sk = PoseSkeleton(shape, pose);
    EXPECT_NEAR(LowestAnkle(sk), shape.FootHeight(), 1e-9);
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR((sk.knee[i] - sk.hip[i]).norm(), shape.Thigh(), 1e-9);
      EXPECT_NEAR((sk.ankle[i] - sk.knee[i]).norm(), shape.Shin(), 1e-9);
      EXPECT_NEAR((sk.elbow[i] - sk.shoulder[i]).norm(), shape.UpperArm(), 1e-9);
      EXPECT_NEAR((sk.hand[i] - sk.elbow[i]).norm(), shape.Forearm(), 1e-9);
    }
  }
  // Mid-stride the feet are apart; where the legs pass each other they are together.
  pose.gait_phase = kPi / 2;
  const Skeleton stride = PoseSkeleton(shape, pose);
  EXPECT_GT(std::abs(stride.ankle[kLeft].x() - stride.ankle[kRight].x()), 0.3);
  pose.gait_phase = kPi;
  const Skeleton together = PoseSkeleton(shape, pose);
  EXPECT_NEAR(together.ankle[kLeft].x(), together.ankle[kRight].x(), 1e-9);
}

TEST(People, ArmsReachTargetsWithinReach) {
  const BodyShape shape;
  BodyPose pose;
  pose.yaw = kPi / 2;
  pose.position = {1.0, 1.0};
  pose.hand_blend = {1.0, 1.0};
  pose.hand_target[kLeft] = {0.35, 0.25, 1.0};
  pose.hand_target[kRight] = {0.4, -0.1, 1.2};
  const Skeleton sk = PoseSkeleton(shape, pose);
  const core::Pose T_wb = BodyToWorld(pose);
  EXPECT_LT((sk.hand[kLeft] - T_wb * pose.hand_target[kLeft]).norm(), 1e-9);
  EXPECT_LT((sk.hand[kRight] - T_wb * pose.hand_target[kRight]).norm(), 1e-9);
  // The elbow bends down, not up.
  EXPECT_LT(sk.elbow[kLeft].z(), (sk.shoulder[kLeft].z() + sk.hand[kLeft].z()) / 2);
}

TEST(People, LeaningReachesTheDesk) {
  const BodyShape shape;
  const BodyPose pose;
  const Eigen::Vector3d on_desk(0.55, -0.15, 0.78);
  const double bend = BendToReach(shape, pose, kRight, on_desk);
  EXPECT_GT(bend, 0.0);
  BodyPose reaching = pose;
  reaching.bend = bend;
  reaching.hand_blend[kRight] = 1.0;
  reaching.hand_target[kRight] = on_desk;
  EXPECT_LT((PoseSkeleton(shape, reaching).hand[kRight] - on_desk).norm(), 1e-9);
}

TEST(People, SittingPutsThePelvisOnTheSeat) {
  const BodyShape shape;
  BodyPose pose;
  pose.sit = 1.0;
  pose.seat_height = 0.49;
  const Skeleton sk = PoseSkeleton(shape, pose);
  EXPECT_NEAR(sk.pelvis.z(), 0.49 + 0.03 * shape.height, 1e-9);
  EXPECT_NEAR(sk.knee[kLeft].z(), sk.hip[kLeft].z(), 1e-9);    // thighs level
  EXPECT_NEAR(sk.ankle[kLeft].x(), sk.knee[kLeft].x(), 1e-9);  // shins upright
  EXPECT_GT(LowestAnkle(sk), 0.0);
  EXPECT_LT(ShoulderHeight(shape, pose), ShoulderHeight(shape, BodyPose{}));
}

TEST(People, BlendInterpolatesAndTurnsTheShortWay) {
  BodyPose a;
  a.yaw = 3.0;
  BodyPose b;
  b.yaw = -3.0;
  b.position = {2.0, 0.0};
  const BodyPose mid = Blend(a, b, 0.5);
  EXPECT_NEAR(std::remainder(mid.yaw - kPi, 2 * kPi), 0.0, 1e-9);
  EXPECT_NEAR(mid.position.x(), 1.0, 1e-12);
}

TEST(People, PartsAreTexturedWithTheClothes) {
  const TextureSet textures;
  const BodyShape shape{1.75, 2, 1};
  const std::vector<Box> parts = PersonParts(shape, PoseSkeleton(shape, BodyPose{}), textures);
  EXPECT_EQ(parts.size(), 18U);
  const int shirt = textures.Index(TextureRole::kShirt, 2);
  EXPECT_TRUE(std::any_of(parts.begin(), parts.end(), [&](const Box& b) { return b.texture == shirt; }));
  for (const Box& box : parts) EXPECT_TRUE((box.half_size.array() > 0.0).all());
}

}  // namespace
}  // namespace hoidslam::synth
