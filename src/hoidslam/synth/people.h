#pragma once
// Articulated people built from boxes: a skeleton (pelvis, torso, head, arms, legs) posed from a few
// parameters, a walking gait driven by the distance walked, sitting, bending, and arms that reach for points
// by two-bone inverse kinematics.
//
// Body frame: origin on the floor below the pelvis, x forward, y to the person's left, z up.

#include <Eigen/Core>
#include <array>
#include <opencv2/core/matx.hpp>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/synth/scene.h"
#include "hoidslam/synth/textures.h"

namespace hoidslam::synth {

// Which side; the index into the per-side arrays below.
enum Side : int { kLeft = 0, kRight = 1 };

// The fixed look and proportions of one person.
struct BodyShape {
  double height = 1.75;                        // metres, in [1.2, 2.2]
  int shirt = 0;                               // texture variant of the shirt (TextureRole::kShirt)
  int trousers = 0;                            // texture variant of the trousers (TextureRole::kTrousers)
  cv::Vec3f skin_tint = {0.75F, 0.85F, 1.0F};  // B, G, R multiplier on the skin texture
  cv::Vec3f hair_tint = {0.4F, 0.45F, 0.5F};

  // Segment lengths, metres, in proportion to height.
  double UpperArm() const { return 0.186 * height; }
  double Forearm() const { return 0.146 * height + 0.04 * height; }  // elbow to the middle of the hand
  double Thigh() const { return 0.245 * height; }
  double Shin() const { return 0.246 * height; }
  double FootHeight() const { return 0.039 * height; }
  double TorsoLength() const { return 0.29 * height; }  // hip joint height to shoulder height
  double ShoulderHalfWidth() const { return 0.115 * height; }
  double HipHalfWidth() const { return 0.055 * height; }
};

// Everything that changes from frame to frame. Interpolating two poses field by field gives a valid pose.
struct BodyPose {
  Eigen::Vector2d position = {0.0, 0.0};  // world x, y of the body frame origin
  double yaw = 0.0;                       // heading of body +x, radians from world +x
  double gait_phase = 0.0;                // radians; legs pass each other at multiples of pi
  double gait_amount = 0.0;               // 0 = legs straight, 1 = full stride
  double sit = 0.0;                       // 0 = standing, 1 = seated at seat_height
  double seat_height = 0.46;              // metres
  double bend = 0.0;                      // forward lean of the torso, radians
  double head_turn = 0.0;                 // head yaw relative to the torso, radians
  // Per arm: where the hand should be (body frame) and how much the arm follows that target rather than
  // hanging and swinging with the gait (0 = hang/swing, 1 = reach the target).
  std::array<Eigen::Vector3d, 2> hand_target = {Eigen::Vector3d{0.3, 0.2, 1.0}, Eigen::Vector3d{0.3, -0.2, 1.0}};
  std::array<double, 2> hand_blend = {0.0, 0.0};
};

// Linear blend of two poses (yaw along the shorter way round); s in [0, 1].
BodyPose Blend(const BodyPose& a, const BodyPose& b, double s);

// Body frame to world.
core::Pose BodyToWorld(const BodyPose& pose);

// Joint positions in the world.
struct Skeleton {
  Eigen::Vector3d pelvis, neck, head;
  std::array<Eigen::Vector3d, 2> shoulder, elbow, hand, hip, knee, ankle;
  core::Pose T_w_torso = core::Pose::Identity();  // torso frame at the pelvis: x forward, z up the spine
  core::Pose T_w_head = core::Pose::Identity();   // head frame at the head centre: x the way the face looks
};

Skeleton PoseSkeleton(const BodyShape& shape, const BodyPose& pose);

// The body's boxes, textured with the person's clothes.
std::vector<Box> PersonParts(const BodyShape& shape, const Skeleton& skeleton, const TextureSet& textures);

// Height of the shoulders above the floor (body frame z) in `pose`.
double ShoulderHeight(const BodyShape& shape, const BodyPose& pose);

// The smallest forward lean (radians, up to about 80 degrees) at which the hand of `side` can reach
// `target_body` (body frame) with a slightly bent arm; the largest lean when nothing reaches it.
double BendToReach(const BodyShape& shape, const BodyPose& pose, Side side, const Eigen::Vector3d& target_body);

}  // namespace hoidslam::synth
