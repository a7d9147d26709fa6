#include "hoidslam/synth/people.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "hoidslam/synth/plane_geometry.h"

namespace hoidslam::synth {
namespace {

using Eigen::Vector3d;

constexpr double kHipSwing = 0.45;    // radians, peak thigh swing at full stride
constexpr double kKneeBend = 0.9;     // radians, scales the swing leg's knee bend
constexpr double kArmSwing = 0.6;     // arm swing as a fraction of the opposite thigh swing
constexpr double kMaxBend = 1.4;      // radians, the deepest forward lean
constexpr double kReachSlack = 0.95;  // a reach uses at most this fraction of the arm's length

double WrapAngle(double a) { return std::remainder(a, 2.0 * kPi); }

Vector3d Lerp(const Vector3d& a, const Vector3d& b, double s) { return a + (b - a) * s; }

// The skeleton in the body frame (T_w_torso relative to the body frame).
Skeleton BodySkeleton(const BodyShape& shape, const BodyPose& pose) {
  Skeleton sk;
  const double h = shape.height;
  std::array<double, 2> thigh_angle{};
  std::array<double, 2> knee_angle{};
  double standing_hip_height = 0.0;
  for (int i = 0; i < 2; ++i) {
    const double phase = pose.gait_phase + i * kPi;
    const double swing = kHipSwing * pose.gait_amount * std::sin(phase);
    // Only the leg swinging forward (cos > 0) bends its knee; both legs are straight where they pass.
    const double knee = kKneeBend * pose.gait_amount * std::max(0.0, std::cos(phase)) * std::abs(std::sin(phase));
    standing_hip_height =
        std::max(standing_hip_height, shape.Thigh() * std::cos(swing) + shape.Shin() * std::cos(swing - knee));
    thigh_angle[i] = swing + (kPi / 2 - swing) * pose.sit;
    knee_angle[i] = knee + (kPi / 2 - knee) * pose.sit;
  }
  standing_hip_height += shape.FootHeight();
  const double seated_hip_height = pose.seat_height + 0.03 * h;
  const double hip_height = standing_hip_height + (seated_hip_height - standing_hip_height) * pose.sit;
  sk.pelvis = {0.0, 0.0, hip_height};

  for (int i = 0; i < 2; ++i) {
    const double y = (i == kLeft ? 1.0 : -1.0) * shape.HipHalfWidth();
    const double t = thigh_angle[i];
    const double s = t - knee_angle[i];
    sk.hip[i] = sk.pelvis + Vector3d(0.0, y, 0.0);
    sk.knee[i] = sk.hip[i] + shape.Thigh() * Vector3d(std::sin(t), 0.0, -std::cos(t));
    sk.ankle[i] = sk.knee[i] + shape.Shin() * Vector3d(std::sin(s), 0.0, -std::cos(s));
  }

  const Vector3d up(std::sin(pose.bend), 0.0, std::cos(pose.bend));
  const Vector3d forward(std::cos(pose.bend), 0.0, -std::sin(pose.bend));
  sk.T_w_torso = core::Pose::Identity();
  sk.T_w_torso.translate(sk.pelvis);
  sk.T_w_torso.rotate(Eigen::AngleAxisd(pose.bend, Vector3d::UnitY()));
  const Vector3d shoulder_centre = sk.pelvis + up * shape.TorsoLength();
  sk.neck = shoulder_centre + up * (0.03 * h);
  sk.head = shoulder_centre + up * (0.1 * h);

  for (int i = 0; i < 2; ++i) {
    const double side = i == kLeft ? 1.0 : -1.0;
    sk.shoulder[i] = shoulder_centre + Vector3d(0.0, side * shape.ShoulderHalfWidth(), 0.0);
    // The free arm hangs, swinging against the same-side leg, elbow slightly bent.
    const double swing = -kArmSwing * kHipSwing * pose.gait_amount * std::sin(pose.gait_phase + i * kPi);
    const double elbow_bend = 0.2 + 0.3 * pose.gait_amount;
    const Vector3d free_elbow =
        sk.shoulder[i] + shape.UpperArm() * Vector3d(std::sin(swing), 0.02 * side, -std::cos(swing)).normalized();
    const Vector3d free_hand =
        free_elbow + shape.Forearm() * Vector3d(std::sin(swing + elbow_bend), 0.0, -std::cos(swing + elbow_bend));
    const double blend = pose.hand_blend[static_cast<std::size_t>(i)];
    if (blend <= 0.0) {
      sk.elbow[i] = free_elbow;
      sk.hand[i] = free_hand;
      continue;
    }
    // Two-bone inverse kinematics towards the blended target, elbow pointing down, back and out.
    const Vector3d goal = Lerp(free_hand, pose.hand_target[static_cast<std::size_t>(i)], blend);
    const double upper = shape.UpperArm();
    const double lower = shape.Forearm();
    Vector3d to_goal = goal - sk.shoulder[i];
    const double distance = std::clamp(to_goal.norm(), std::abs(upper - lower) + 1e-3, (upper + lower) * 0.999);
    const Vector3d dir = to_goal.norm() > 1e-9 ? Vector3d(to_goal.normalized()) : Vector3d(0.0, 0.0, -1.0);
    sk.hand[i] = sk.shoulder[i] + dir * distance;
    const double along = (upper * upper + distance * distance - lower * lower) / (2.0 * distance);
    const double out = std::sqrt(std::max(0.0, upper * upper - along * along));
    Vector3d pole = Vector3d(-0.3, 0.4 * side, -1.0);
    pole -= pole.dot(dir) * dir;
    if (pole.norm() < 1e-6) pole = Vector3d(-1.0, 0.0, 0.0) - dir.x() * dir;
    sk.elbow[i] = sk.shoulder[i] + dir * along + pole.normalized() * out;
  }
  return sk;
}

// A box spanning the segment from `a` to `b` (plus `overlap` at each end), turned so that its x axis is as
// close to `forward` as possible.
Box LimbBox(const Vector3d& a, const Vector3d& b, double half_x, double half_y, double overlap, const Vector3d& forward,
            int texture, double scale, const cv::Vec3f& tint) {
  Vector3d z = a - b;
  const double length = z.norm();
  z = length > 1e-9 ? Vector3d(z / length) : Vector3d::UnitZ();
  Vector3d x = forward - forward.dot(z) * z;
  if (x.norm() < 0.1) x = Vector3d::UnitZ() - z.z() * z;
  x.normalize();
  const Vector3d y = z.cross(x);
  Box box;
  box.T_wb.linear() << x, y, z;
  box.T_wb.translation() = (a + b) / 2.0;
  box.half_size = {half_x, half_y, length / 2.0 + overlap};
  box.texture = texture;
  box.texture_scale = scale;
  box.tint = tint;
  return box;
}

Box OrientedBox(const core::Pose& frame, const Vector3d& centre, const Vector3d& half, int texture, double scale,
                const cv::Vec3f& tint) {
  Box box;
  box.T_wb = frame;
  box.T_wb.translation() = centre;
  box.half_size = half;
  box.texture = texture;
  box.texture_scale = scale;
  box.tint = tint;
  return box;
}

}  // namespace

BodyPose Blend(const BodyPose& a, const BodyPose& b, double s) {
  BodyPose p;
  p.position = a.position + (b.position - a.position) * s;
  p.yaw = a.yaw + WrapAngle(b.yaw - a.yaw) * s;
  p.gait_phase = a.gait_phase + (b.gait_phase - a.gait_phase) * s;
  p.gait_amount = a.gait_amount + (b.gait_amount - a.gait_amount) * s;
  p.sit = a.sit + (b.sit - a.sit) * s;
  p.seat_height = a.seat_height + (b.seat_height - a.seat_height) * s;
  p.bend = a.bend + (b.bend - a.bend) * s;
  p.head_turn = a.head_turn + (b.head_turn - a.head_turn) * s;
  for (std::size_t i = 0; i < 2; ++i) {
    p.hand_target[i] = Lerp(a.hand_target[i], b.hand_target[i], s);
    p.hand_blend[i] = a.hand_blend[i] + (b.hand_blend[i] - a.hand_blend[i]) * s;
  }
  return p;
}

core::Pose BodyToWorld(const BodyPose& pose) {
  core::Pose T = core::Pose::Identity();
  T.translate(Vector3d(pose.position.x(), pose.position.y(), 0.0));
  T.rotate(Eigen::AngleAxisd(pose.yaw, Vector3d::UnitZ()));
  return T;
}

Skeleton PoseSkeleton(const BodyShape& shape, const BodyPose& pose) {
  // Hand targets are given in the body frame, as BodySkeleton expects.
  const Skeleton body = BodySkeleton(shape, pose);
  const core::Pose T_wb = BodyToWorld(pose);
  Skeleton sk;
  sk.pelvis = T_wb * body.pelvis;
  sk.neck = T_wb * body.neck;
  sk.head = T_wb * body.head;
  for (std::size_t i = 0; i < 2; ++i) {
    sk.shoulder[i] = T_wb * body.shoulder[i];
    sk.elbow[i] = T_wb * body.elbow[i];
    sk.hand[i] = T_wb * body.hand[i];
    sk.hip[i] = T_wb * body.hip[i];
    sk.knee[i] = T_wb * body.knee[i];
    sk.ankle[i] = T_wb * body.ankle[i];
  }
  sk.T_w_torso = T_wb * body.T_w_torso;
  sk.T_w_head = sk.T_w_torso;
  sk.T_w_head.rotate(Eigen::AngleAxisd(pose.head_turn, Vector3d::UnitZ()));
  sk.T_w_head.translation() = sk.head;
  return sk;
}

std::vector<Box> PersonParts(const BodyShape& shape, const Skeleton& sk, const TextureSet& textures) {
  const double s = shape.height / 1.75;
  const int shirt = textures.Index(TextureRole::kShirt, shape.shirt);
  const int trousers = textures.Index(TextureRole::kTrousers, shape.trousers);
  const int skin = textures.Index(TextureRole::kSkin);
  const int hair = textures.Index(TextureRole::kHair);
  const int shoe = textures.Index(TextureRole::kShoe);
  const cv::Vec3f white = {1.0F, 1.0F, 1.0F};
  const Vector3d torso_x = sk.T_w_torso.linear().col(0);
  const Vector3d torso_z = sk.T_w_torso.linear().col(2);
  // The legs keep the heading of the body, whatever the torso lean.
  Vector3d body_x = torso_x;
  body_x.z() = 0.0;
  if (body_x.norm() < 1e-6) body_x = -torso_z;
  body_x.normalize();

  std::vector<Box> parts;
  parts.reserve(17);
  parts.push_back(
      OrientedBox(sk.T_w_torso, sk.pelvis + torso_z * 0.02 * s, Vector3d(0.1, 0.17, 0.08) * s, trousers, 0.4, white));
  parts.push_back(LimbBox(sk.neck - torso_z * 0.03 * s, sk.pelvis + torso_z * 0.09 * s, 0.11 * s, 0.19 * s, 0.0,
                          torso_x, shirt, 0.45, white));
  parts.push_back(
      LimbBox(sk.head, sk.neck - torso_z * 0.03 * s, 0.04 * s, 0.045 * s, 0.0, torso_x, skin, 0.3, shape.skin_tint));
  const Vector3d head_x = sk.T_w_head.linear().col(0);
  parts.push_back(OrientedBox(sk.T_w_head, sk.head, Vector3d(0.1, 0.08, 0.115) * s, skin, 0.3, shape.skin_tint));
  parts.push_back(OrientedBox(sk.T_w_head, sk.head + torso_z * 0.09 * s - head_x * 0.015 * s,
                              Vector3d(0.105, 0.085, 0.04) * s, hair, 0.2, shape.hair_tint));
  parts.push_back(OrientedBox(sk.T_w_head, sk.head - head_x * 0.07 * s + torso_z * 0.02 * s,
                              Vector3d(0.04, 0.085, 0.08) * s, hair, 0.2, shape.hair_tint));
  for (std::size_t i = 0; i < 2; ++i) {
    parts.push_back(LimbBox(sk.shoulder[i], sk.elbow[i], 0.048 * s, 0.048 * s, 0.03 * s, torso_x, shirt, 0.45, white));
    const Vector3d forearm_dir = (sk.hand[i] - sk.elbow[i]).normalized();
    const Vector3d wrist = sk.hand[i] - forearm_dir * 0.04 * s;
    parts.push_back(LimbBox(sk.elbow[i], wrist, 0.038 * s, 0.038 * s, 0.01 * s, torso_x, skin, 0.3, shape.skin_tint));
    parts.push_back(LimbBox(wrist, sk.hand[i] + forearm_dir * 0.04 * s, 0.02 * s, 0.045 * s, 0.0, torso_x, skin, 0.3,
                            shape.skin_tint));
    parts.push_back(LimbBox(sk.hip[i], sk.knee[i], 0.075 * s, 0.075 * s, 0.03 * s, body_x, trousers, 0.4, white));
    parts.push_back(LimbBox(sk.knee[i], sk.ankle[i], 0.058 * s, 0.058 * s, 0.02 * s, body_x, trousers, 0.4, white));
    core::Pose foot_frame = core::Pose::Identity();
    foot_frame.linear() << body_x, Vector3d::UnitZ().cross(body_x), Vector3d::UnitZ();
    const Vector3d foot_centre = sk.ankle[i] + body_x * 0.06 * s - Vector3d::UnitZ() * (shape.FootHeight() / 2.0);
    parts.push_back(
        OrientedBox(foot_frame, foot_centre, Vector3d(0.13 * s, 0.05 * s, shape.FootHeight() / 2.0), shoe, 0.2, white));
  }
  return parts;
}

double ShoulderHeight(const BodyShape& shape, const BodyPose& pose) {
  return BodySkeleton(shape, pose).shoulder[kLeft].z();
}

double BendToReach(const BodyShape& shape, const BodyPose& pose, Side side, const Vector3d& target_body) {
  const double reach = kReachSlack * (shape.UpperArm() + shape.Forearm());
  BodyPose trial = pose;
  for (double bend = 0.0; bend < kMaxBend; bend += 0.05) {
    trial.bend = bend;
    const Skeleton sk = BodySkeleton(shape, trial);
    if ((target_body - sk.shoulder[static_cast<std::size_t>(side)]).norm() <= reach) return bend;
  }
  return kMaxBend;
}

}  // namespace hoidslam::synth
