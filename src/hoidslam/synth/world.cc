#include "hoidslam/synth/world.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/camera_path.h"
#include "hoidslam/synth/plane_geometry.h"

namespace hoidslam::synth {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Durations of the body motions, seconds.
constexpr double kReachTime = 0.7;
constexpr double kLiftTime = 0.7;
constexpr double kPlaceTime = 0.8;
constexpr double kRetractTime = 0.6;
constexpr double kSitTime = 1.2;
constexpr double kGripTime = 0.5;
constexpr double kTurnRate = 2.5;         // rad/s
constexpr double kPushSpeedFactor = 0.6;  // pushing a chair is slower than walking
constexpr double kBodyRadius = 0.25;      // metres kept free between a standing person and furniture
constexpr double kWalkClearance = 0.3;    // metres kept free between a walking person's centre and furniture
constexpr double kChairClearance = 0.5;   // metres between a standing person and a chair's centre
constexpr double kSitApproach = 0.3;      // metres in front of the seat centre where a person sits down from

core::Pose YawPose(const Vector3d& t, double yaw) {
  core::Pose pose = core::Pose::Identity();
  pose.translate(t);
  pose.rotate(Eigen::AngleAxisd(yaw, Vector3d::UnitZ()));
  return pose;
}

double YawOf(const core::Pose& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); }

double Heading(const Vector2d& d) { return std::atan2(d.y(), d.x()); }

}  // namespace

// Plans every person's time line, one action at a time, always advancing the person whose clock is earliest,
// so that an object put down by one person is where the next person looks for it.
class World::Planner {
 public:
  Planner(World& world, const Scenario& scenario) : world_(world), scenario_(scenario) {}

  void Run() {
    const std::size_t count = world_.people_.size();
    cursors_.resize(count);
    for (std::size_t p = 0; p < count; ++p) {
      const PersonSpec& spec = world_.people_[p].spec;
      Cursor& c = cursors_[p];
      c.time = spec.enter_at;
      c.pose.position = spec.start;
      c.pose.yaw = spec.facing_deg * std::numbers::pi / 180.0;
      world_.events_.push_back(
          {spec.enter_at, spec.name, "enter", "", std::nullopt, Vector3d(spec.start.x(), spec.start.y(), 0.0)});
    }
    for (;;) {
      // The person whose next action starts first (an action's `at` can hold it back).
      std::size_t next = count;
      double next_start = kInfinity;
      for (std::size_t p = 0; p < count; ++p) {
        const auto& actions = world_.people_[p].spec.actions;
        if (cursors_[p].next_action >= actions.size()) continue;
        const double start = std::max(cursors_[p].time, actions[cursors_[p].next_action].at.value_or(0.0));
        if (start < next_start) {
          next = p;
          next_start = start;
        }
      }
      if (next == count) break;
      const Action& action = world_.people_[next].spec.actions[cursors_[next].next_action++];
      Do(next, action);
    }
    for (std::size_t p = 0; p < count; ++p) {
      world_.end_time_ = std::max(world_.end_time_, cursors_[p].time);
      world_.people_[p].exit = cursors_[p].gone ? cursors_[p].time : kInfinity;
    }
    std::stable_sort(world_.events_.begin(), world_.events_.end(),
                     [](const WorldEvent& a, const WorldEvent& b) { return a.time < b.time; });
  }

 private:
  struct Cursor {
    double time = 0.0;
    BodyPose pose;
    std::size_t next_action = 0;
    int held = -1;                                 // object index in hand, or -1
    core::Pose T_bo = core::Pose::Identity();      // held object in the body frame
    std::array<std::optional<Vector3d>, 2> grasp;  // where each holding hand grips, object frame
    Vector3d picked_from = Vector3d::Zero();
    bool gone = false;
  };

  [[noreturn]] void Fail(const Action& action, const std::string& what) const {
    throw core::InputError::InFile(scenario_.source, fmt::format("{}: {}", action.key, what));
  }

  const BodyShape& Shape(std::size_t p) const { return world_.people_[p].spec.shape; }

  // The hand targets and blends of a pose that holds the current object at T_bo.
  BodyPose Holding(BodyPose pose, const Cursor& c, const core::Pose& T_bo) const {
    for (std::size_t i = 0; i < 2; ++i) {
      if (!c.grasp[i]) continue;
      pose.hand_target[i] = T_bo * *c.grasp[i];
      pose.hand_blend[i] = 1.0;
    }
    return pose;
  }

  // Appends a segment from the cursor's pose to `b` lasting `duration`; the held object goes to T_bo_b.
  void Move(std::size_t p, double duration, const BodyPose& b, bool moving, bool eased,
            const std::optional<core::Pose>& T_bo_b = std::nullopt) {
    Cursor& c = cursors_[p];
    if (duration <= 0.0) return;
    Segment segment;
    segment.t0 = c.time;
    segment.t1 = c.time + duration;
    segment.a = c.pose;
    segment.b = b;
    segment.moving = moving;
    segment.eased = eased;
    segment.held = c.held;
    segment.T_bo_a = c.T_bo;
    segment.T_bo_b = T_bo_b.value_or(c.T_bo);
    world_.people_[p].segments.push_back(segment);
    c.time = segment.t1;
    c.pose = b;
    c.T_bo = segment.T_bo_b;
  }

  void Idle(std::size_t p, double duration) { Move(p, duration, cursors_[p].pose, false, false); }

  void TurnTo(std::size_t p, double yaw) {
    const BodyPose& pose = cursors_[p].pose;
    const double delta = std::abs(std::remainder(yaw - pose.yaw, 2.0 * std::numbers::pi));
    if (delta < 0.05) return;
    BodyPose b = pose;
    b.yaw = yaw;
    b.gait_phase += std::numbers::pi;  // one step on the spot; legs meet again at the end
    b.gait_amount = 0.4;
    Move(p, std::max(0.3, delta / kTurnRate), b, true, true);
  }

  // Walks to `target` round desks and shelves, for `action`; an error naming it when there is no way round.
  void WalkTo(std::size_t p, const Vector2d& target, double speed, const Action& action) {
    const Vector2d& from = cursors_[p].pose.position;
    const auto route = scenario_.office.Route(from, target, kWalkClearance);
    if (!route) {
      Fail(action, fmt::format("{} finds no way from ({:.2f}, {:.2f}) to ({:.2f}, {:.2f}) round the desks and "
                               "shelves",
                               world_.people_[p].spec.name, from.x(), from.y(), target.x(), target.y()));
    }
    for (const Vector2d& waypoint : *route) WalkStraight(p, waypoint, speed);
  }

  void WalkStraight(std::size_t p, const Vector2d& target, double speed) {
    const Cursor& c = cursors_[p];
    const Vector2d d = target - c.pose.position;
    const double distance = d.norm();
    if (distance < 0.02) return;
    TurnTo(p, Heading(d));
    BodyPose b = cursors_[p].pose;
    b.position = target;
    b.yaw = Heading(d);
    // Whole half strides, so that the legs are together when the walk ends.
    const double half_stride = 0.38 * Shape(p).height;
    b.gait_phase += std::numbers::pi * std::max(1.0, std::round(distance / half_stride));
    b.gait_amount = 1.0;
    cursors_[p].pose.gait_amount = 1.0;  // invisible while the legs are together, as at every segment boundary
    Move(p, distance / speed, b, true, false);
  }

  double Speed(std::size_t p) const { return world_.people_[p].spec.speed; }

  // A free spot `distance` from `xy`, towards `from`, moved outwards until no furniture is in the way.
  Vector2d Approach(const Vector2d& xy, const Vector2d& from, double distance, const Vector2d& fallback_dir) const {
    Vector2d dir = from - xy;
    dir = dir.norm() > 1e-6 ? Vector2d(dir.normalized()) : fallback_dir;
    return FreeSpot(xy + dir * distance, dir);
  }

  // True when a person standing at `spot` would overlap furniture or a chair where it stands now.
  bool Blocked(const Vector2d& spot) const {
    if (scenario_.office.IsBlocked(spot, kBodyRadius)) return true;
    for (const ObjectTrack& object : world_.objects_) {
      if (object.info.kind != ObjectKind::kChair) continue;
      if ((object.rests.back().second.translation().head<2>() - spot).norm() < kChairClearance) return true;
    }
    return false;
  }

  Vector2d FreeSpot(Vector2d spot, const Vector2d& dir) const {
    for (int i = 0; i < 60 && Blocked(spot); ++i) spot += dir * 0.05;
    const Eigen::Vector3d& room = scenario_.office.room;
    spot.x() = std::clamp(spot.x(), 0.3, room.x() - 0.3);
    spot.y() = std::clamp(spot.y(), 0.3, room.y() - 0.3);
    return spot;
  }

  std::size_t ObjectIndex(const Action& action) const {
    for (std::size_t i = 0; i < world_.objects_.size(); ++i) {
      if (world_.objects_[i].info.name == action.object) return i;
    }
    Fail(action, fmt::format("unknown object '{}'", action.object));
  }

  // Where object `index` rests now; an error when someone holds it (or will, by the plan so far).
  core::Pose FreeObjectPose(std::size_t p, std::size_t index, const Action& action) const {
    const ObjectTrack& object = world_.objects_[index];
    for (const Hold& hold : object.holds) {
      if (hold.t1 > cursors_[p].time) {
        Fail(action, fmt::format("'{}' is held by {} at {:.2f} s", object.info.name,
                                 world_.people_[hold.person].spec.name, hold.t0));
      }
    }
    return object.rests.back().second;
  }

  void RequireEmptyHands(std::size_t p, const Action& action) const {
    const int held = cursors_[p].held;
    if (held >= 0) {
      Fail(action, fmt::format("{} cannot {} while carrying '{}'; put it down first", world_.people_[p].spec.name,
                               ToString(action.type), world_.objects_[static_cast<std::size_t>(held)].info.name));
    }
  }

  // The lean needed so that every holding hand reaches its target in `pose`.
  double BendFor(std::size_t p, const BodyPose& pose) const {
    double bend = 0.0;
    for (int i = 0; i < 2; ++i) {
      if (pose.hand_blend[static_cast<std::size_t>(i)] > 0.0) {
        bend = std::max(
            bend, BendToReach(Shape(p), pose, static_cast<Side>(i), pose.hand_target[static_cast<std::size_t>(i)]));
      }
    }
    return bend;
  }

  void Event(std::size_t p, const std::string& action, const std::string& object,
             std::optional<Vector3d> from = std::nullopt, std::optional<Vector3d> to = std::nullopt) {
    world_.events_.push_back({cursors_[p].time, world_.people_[p].spec.name, action, object, from, to});
  }

  void StartHold(std::size_t p, std::size_t index, const core::Pose& T_bo) {
    Cursor& c = cursors_[p];
    c.held = static_cast<int>(index);
    c.T_bo = T_bo;
    world_.objects_[index].holds.push_back({c.time, kInfinity, p});
  }

  // Ends the hold: the object rests at `T_w_rest` from now on.
  void EndHold(std::size_t p, const core::Pose& T_w_rest) {
    Cursor& c = cursors_[p];
    ObjectTrack& object = world_.objects_[static_cast<std::size_t>(c.held)];
    object.holds.back().t1 = c.time;
    object.rests.emplace_back(c.time, T_w_rest);
    c.held = -1;
    c.grasp = {};
  }

  // Lets go: the hands return to hanging and the body straightens.
  void Retract(std::size_t p, double duration) {
    BodyPose b = cursors_[p].pose;
    b.hand_blend = {0.0, 0.0};
    b.bend = 0.0;
    Move(p, duration, b, true, true);
  }

  void PickUp(std::size_t p, const Action& action) {
    RequireEmptyHands(p, action);
    const std::size_t index = ObjectIndex(action);
    const ObjectTrack& object = world_.objects_[index];
    const core::Pose T_w_rest = FreeObjectPose(p, index, action);
    const Vector3d ext = ObjectHalfExtents(object.info.kind);
    const Vector2d xy = T_w_rest.translation().head<2>();
    WalkTo(p, Approach(xy, cursors_[p].pose.position, std::max(ext.x(), ext.y()) + 0.3, {0.0, -1.0}), Speed(p),
           action);
    TurnTo(p, Heading(xy - cursors_[p].pose.position));

    Cursor& c = cursors_[p];
    const core::Pose T_bo_rest = BodyToWorld(c.pose).inverse() * T_w_rest;
    // Grip points: both sides of big things (a chair by its seat), the near side of small ones.
    const double grip_z = object.info.kind == ObjectKind::kChair ? 0.46 : ext.z();
    const Vector3d centre_body = T_bo_rest * Vector3d(0.0, 0.0, grip_z);
    const double rel = YawOf(T_bo_rest);
    if (IsTwoHanded(object.info.kind)) {
      const double w = std::abs(std::sin(rel)) * ext.x() + std::abs(std::cos(rel)) * ext.y() + 0.02;
      c.grasp[kLeft] = T_bo_rest.inverse() * (centre_body + Vector3d(0.0, w, 0.0));
      c.grasp[kRight] = T_bo_rest.inverse() * (centre_body - Vector3d(0.0, w, 0.0));
    } else {
      c.grasp[kRight] = T_bo_rest.inverse() * (centre_body - Vector3d(0.04, 0.0, 0.0));
    }
    BodyPose reach = Holding(c.pose, c, T_bo_rest);
    reach.bend = BendFor(p, reach);
    Move(p, kReachTime, reach, true, true);

    Event(p, "pick_up", object.info.name, T_w_rest.translation());
    cursors_[p].picked_from = T_w_rest.translation();
    StartHold(p, index, T_bo_rest);
    const core::Pose T_bo_carry = CarryPose(p, index, T_bo_rest);
    BodyPose lift = Holding(cursors_[p].pose, cursors_[p], T_bo_carry);
    lift.bend = 0.0;
    Move(p, kLiftTime, lift, true, true, T_bo_carry);
  }

  // The held object in the body frame while carrying: in front, at about elbow height, same turn as gripped.
  core::Pose CarryPose(std::size_t p, std::size_t index, const core::Pose& T_bo_grip) const {
    const Cursor& c = cursors_[p];
    BodyPose upright = c.pose;
    upright.bend = 0.0;
    const double shoulder = ShoulderHeight(Shape(p), upright);
    const Eigen::Matrix3d R = T_bo_grip.linear();
    Vector3d hands;
    Vector3d grip;
    if (c.grasp[kLeft]) {
      const bool chair = world_.objects_[index].info.kind == ObjectKind::kChair;
      hands = Vector3d(0.36, 0.0, shoulder - (chair ? 0.45 : 0.38));
      grip = (*c.grasp[kLeft] + *c.grasp[kRight]) / 2.0;
    } else {
      hands = Vector3d(0.3, -0.18, shoulder - 0.42);
      grip = *c.grasp[kRight];
    }
    core::Pose T_bo = core::Pose::Identity();
    T_bo.linear() = R;
    T_bo.translation() = hands - R * grip;
    return T_bo;
  }

  void PutDown(std::size_t p, const Action& action) {
    if (cursors_[p].held < 0) Fail(action, fmt::format("{} carries nothing to put down", world_.people_[p].spec.name));
    const ObjectTrack& object = world_.objects_[static_cast<std::size_t>(cursors_[p].held)];
    const Vector3d ext = ObjectHalfExtents(object.info.kind);
    const Vector2d& to = action.to;
    WalkTo(p, Approach(to, cursors_[p].pose.position, std::max(ext.x(), ext.y()) + 0.35, {0.0, -1.0}), Speed(p),
           action);
    TurnTo(p, Heading(to - cursors_[p].pose.position));

    Cursor& c = cursors_[p];
    const core::Pose T_wb = BodyToWorld(c.pose);
    const double z = scenario_.office.SupportHeightAt(to);
    const core::Pose T_w_place = YawPose(Vector3d(to.x(), to.y(), z), YawOf(T_wb * c.T_bo));
    const core::Pose T_bo_place = T_wb.inverse() * T_w_place;
    BodyPose place = Holding(c.pose, c, T_bo_place);
    place.bend = BendFor(p, place);
    Move(p, kPlaceTime, place, true, true, T_bo_place);
    Event(p, "put_down", object.info.name, cursors_[p].picked_from, T_w_place.translation());
    EndHold(p, T_w_place);
    Retract(p, kRetractTime);
  }

  void SitOn(std::size_t p, const Action& action) {
    RequireEmptyHands(p, action);
    const std::size_t index = ObjectIndex(action);
    const core::Pose T_w_chair = FreeObjectPose(p, index, action);
    const double yaw = YawOf(T_w_chair);
    const Vector2d seat = T_w_chair.translation().head<2>();
    const Vector2d stand = seat + Direction(yaw) * kSitApproach;
    WalkTo(p, stand, Speed(p), action);
    TurnTo(p, yaw);
    BodyPose sit = cursors_[p].pose;
    sit.position = seat + Direction(yaw) * 0.04;
    sit.sit = 1.0;
    sit.seat_height = T_w_chair.translation().z() + 0.49;
    Event(p, "sit_down", action.object);
    Move(p, kSitTime, sit, true, true);
    if (action.gesture) {
      Gesture(p, action.duration);
    } else {
      Idle(p, action.duration);
    }
    BodyPose stand_up = cursors_[p].pose;
    stand_up.position = stand;
    stand_up.sit = 0.0;
    Move(p, kSitTime, stand_up, true, true);
    Event(p, "stand_up", action.object);
  }

  // Talking with the hands: the hands move in front of the chest, the head turns, in 0.6 s strokes.
  void Gesture(std::size_t p, double duration) {
    const int strokes = std::max(2, static_cast<int>(std::lround(duration / 0.6)));
    const double shoulder = ShoulderHeight(Shape(p), cursors_[p].pose);
    for (int k = 0; k < strokes; ++k) {
      BodyPose b = cursors_[p].pose;
      if (k + 1 < strokes) {
        const bool left_turn = k % 2 == 0;
        b.hand_blend = {left_turn ? 0.9 : 0.4, left_turn ? 0.4 : 0.9};
        b.hand_target[kLeft] = Vector3d(0.3, 0.1 + 0.04 * (k % 3), shoulder - 0.3 + 0.08 * (k % 2));
        b.hand_target[kRight] = Vector3d(0.32, -0.1 - 0.03 * (k % 3), shoulder - 0.25 - 0.05 * (k % 3));
        b.head_turn = left_turn ? 0.35 : -0.3;
      } else {
        b.hand_blend = {0.0, 0.0};
        b.head_turn = 0.0;
      }
      Move(p, duration / strokes, b, true, true);
    }
  }

  void Push(std::size_t p, const Action& action) {
    RequireEmptyHands(p, action);
    const std::size_t index = ObjectIndex(action);
    const core::Pose T_w_chair = FreeObjectPose(p, index, action);
    const double yaw = YawOf(T_w_chair);
    const Vector2d from = T_w_chair.translation().head<2>();
    constexpr double kBehind = 0.62;  // body origin to chair centre while pushing
    WalkTo(p, FreeSpot(from - Direction(yaw) * kBehind, -Direction(yaw)), Speed(p), action);
    TurnTo(p, yaw);

    Cursor& c = cursors_[p];
    const core::Pose T_bo = BodyToWorld(c.pose).inverse() * T_w_chair;
    c.grasp[kLeft] = Vector3d(-0.21, 0.17, 0.93);
    c.grasp[kRight] = Vector3d(-0.21, -0.17, 0.93);
    BodyPose grip = Holding(c.pose, c, T_bo);
    grip.bend = BendFor(p, grip);
    Move(p, kGripTime, grip, true, true);
    StartHold(p, index, T_bo);

    if ((action.to - from).norm() > 0.02) {
      // Walk straight from here (C) to a spot P where the chair, held at offset o = (a, b) in the body frame,
      // ends at `to`: to - C = (a + s) u + b u_perp for the heading u and walked distance s, so the heading is
      // the direction of to - C turned back by atan2(b, a + s), with a + s = sqrt(|to - C|^2 - b^2).
      const Vector2d here = cursors_[p].pose.position;
      const Vector2d offset = cursors_[p].T_bo.translation().head<2>();
      const Vector2d to_here = action.to - here;
      const double along = std::sqrt(std::max(0.0, to_here.squaredNorm() - offset.y() * offset.y()));
      if (along < offset.x()) {
        Fail(action, fmt::format("'{}' cannot be pushed backwards: ({:.2f}, {:.2f}) is behind {}", action.object,
                                 action.to.x(), action.to.y(), world_.people_[p].spec.name));
      }
      const double heading = Heading(to_here) - std::atan2(offset.y(), along);
      TurnTo(p, heading);
      WalkStraight(p, here + (along - offset.x()) * Direction(heading), Speed(p) * kPushSpeedFactor);
    }
    const core::Pose T_w_end = BodyToWorld(cursors_[p].pose) * cursors_[p].T_bo;
    Event(p, "push", action.object, T_w_chair.translation(), T_w_end.translation());
    EndHold(p, T_w_end);
    Retract(p, kGripTime);
  }

  void StandAt(std::size_t p, const Action& action) {
    const std::size_t index = ObjectIndex(action);
    const core::Pose T_w_object = FreeObjectPose(p, index, action);
    const Vector2d xy = T_w_object.translation().head<2>();
    const Vector2d front = Direction(YawOf(T_w_object));
    WalkTo(p, action.position ? *action.position : FreeSpot(xy + front * action.distance, front), Speed(p),
           action);
    TurnTo(p, Heading(xy - cursors_[p].pose.position));
    Event(p, "stand_at", action.object);
    Idle(p, action.duration);
  }

  void Face(std::size_t p, const Action& action) {
    const Vector2d d = action.to - cursors_[p].pose.position;
    // So close, the direction is meaningless: most likely a mistyped point.
    if (d.norm() < 0.05) {
      Fail(action, fmt::format("{} stands at ({:.2f}, {:.2f}): no direction to face", world_.people_[p].spec.name,
                               action.to.x(), action.to.y()));
    }
    TurnTo(p, Heading(d));
  }

  void Do(std::size_t p, const Action& action) {
    Cursor& c = cursors_[p];
    if (c.gone) Fail(action, fmt::format("{} has left", world_.people_[p].spec.name));
    if (action.at && *action.at > c.time) Idle(p, *action.at - c.time);
    switch (action.type) {
      case ActionType::kWalkTo:
        WalkTo(p, action.to, Speed(p), action);
        break;
      case ActionType::kStop:
        Idle(p, action.duration);
        break;
      case ActionType::kPickUp:
        PickUp(p, action);
        break;
      case ActionType::kCarryTo:
        if (c.held < 0) Fail(action, fmt::format("{} carries nothing", world_.people_[p].spec.name));
        WalkTo(p, action.to, Speed(p), action);
        break;
      case ActionType::kPutDown:
        PutDown(p, action);
        break;
      case ActionType::kSitOn:
        SitOn(p, action);
        break;
      case ActionType::kPush:
        Push(p, action);
        break;
      case ActionType::kStandAt:
        StandAt(p, action);
        break;
      case ActionType::kGesture:
        RequireEmptyHands(p, action);
        Gesture(p, action.duration);
        break;
      case ActionType::kFace:
        Face(p, action);
        break;
      case ActionType::kLeave:
        RequireEmptyHands(p, action);
        WalkTo(p, action.to, Speed(p), action);
        Event(p, "leave", "", std::nullopt, Vector3d(action.to.x(), action.to.y(), 0.0));
        cursors_[p].gone = true;
        break;
    }
  }

  World& world_;
  const Scenario& scenario_;
  std::vector<Cursor> cursors_;
};

World::World(const Scenario& scenario, const TextureSet& textures) : textures_(textures) {
  structure_ = BuildStructure(scenario.office, textures, 1);
  int next_id = static_cast<int>(structure_.size()) + 1;
  for (const OfficeObject& info : scenario.office.objects) {
    ObjectTrack track;
    track.info = info;
    track.id = next_id++;
    track.parts = ObjectParts(info.kind, info.variant, textures);
    track.rests.emplace_back(-kInfinity, scenario.office.RestPose(info));
    objects_.push_back(std::move(track));
  }
  for (const PersonSpec& spec : scenario.people) {
    PersonTrack track;
    track.spec = spec;
    track.id = next_id++;
    people_.push_back(std::move(track));
  }
  Planner(*this, scenario).Run();
}

const World::Segment* World::SegmentAt(const PersonTrack& person, double time) const {
  const auto& segments = person.segments;
  // The last segment starting at or before `time`.
  auto it =
      std::upper_bound(segments.begin(), segments.end(), time, [](double t, const Segment& s) { return t < s.t0; });
  if (it == segments.begin()) return nullptr;
  return &*std::prev(it);
}

std::optional<World::PersonInstant> World::PersonState(std::size_t index, double time) const {
  const PersonTrack& person = people_.at(index);
  if (time < person.spec.enter_at || time >= person.exit) return std::nullopt;
  const Segment* segment = SegmentAt(person, time);
  if (segment == nullptr) {
    BodyPose pose;
    pose.position = person.spec.start;
    pose.yaw = person.spec.facing_deg * std::numbers::pi / 180.0;
    return PersonInstant{pose, nullptr, 0.0, false};
  }
  if (time >= segment->t1) return PersonInstant{segment->b, segment, 1.0, false};  // done: at rest
  double s = (time - segment->t0) / (segment->t1 - segment->t0);
  if (segment->eased) s = Smoothstep(s);
  return PersonInstant{Blend(segment->a, segment->b, s), segment, s, segment->moving};
}

std::pair<core::Pose, bool> World::ObjectState(std::size_t index, double time) const {
  const ObjectTrack& object = objects_[index];
  for (const Hold& hold : object.holds) {
    if (time < hold.t0 || time >= hold.t1) continue;
    const auto state = PersonState(hold.person, time);
    if (state && state->segment != nullptr && state->segment->held == static_cast<int>(index)) {
      const Segment& segment = *state->segment;
      return {BodyToWorld(state->pose) * LerpPose(segment.T_bo_a, segment.T_bo_b, state->s), state->moving};
    }
  }
  // The last rest that began at or before `time`.
  auto it = std::upper_bound(object.rests.begin(), object.rests.end(), time,
                             [](double t, const auto& rest) { return t < rest.first; });
  return {std::prev(it)->second, false};
}

SceneSnapshot World::Snapshot(double time) const {
  SceneSnapshot snapshot;
  snapshot.timestamp = time;
  snapshot.instances.reserve(structure_.size() + objects_.size() + people_.size());
  snapshot.instances = structure_;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    const auto [T_wo, moving] = ObjectState(i, time);
    SceneInstance instance{objects_[i].id, std::string(CocoLabel(objects_[i].info.kind)), moving, objects_[i].parts};
    for (Box& box : instance.parts) box.T_wb = T_wo * box.T_wb;
    snapshot.instances.push_back(std::move(instance));
  }
  for (std::size_t p = 0; p < people_.size(); ++p) {
    const auto state = PersonState(p, time);
    if (!state) continue;
    const Skeleton skeleton = PoseSkeleton(people_[p].spec.shape, state->pose);
    snapshot.instances.push_back(
        SceneInstance{people_[p].id, "person", state->moving, PersonParts(people_[p].spec.shape, skeleton, textures_)});
  }
  return snapshot;
}

std::optional<int> World::InstanceId(std::string_view name) const {
  for (const ObjectTrack& object : objects_) {
    if (object.info.name == name) return object.id;
  }
  for (const PersonTrack& person : people_) {
    if (person.spec.name == name) return person.id;
  }
  return std::nullopt;
}

std::optional<core::Pose> World::ObjectPose(std::string_view name, double time) const {
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (objects_[i].info.name == name) return ObjectState(i, time).first;
  }
  return std::nullopt;
}

std::optional<BodyPose> World::PersonPose(std::size_t index, double time) const {
  const auto state = PersonState(index, time);
  if (!state) return std::nullopt;
  return state->pose;
}

std::optional<Skeleton> World::PersonSkeleton(std::size_t index, double time) const {
  const auto pose = PersonPose(index, time);
  if (!pose) return std::nullopt;
  return PoseSkeleton(people_.at(index).spec.shape, *pose);
}

std::vector<std::string> World::MovingAt(double time) const {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (ObjectState(i, time).second) names.push_back(objects_[i].info.name);
  }
  for (std::size_t p = 0; p < people_.size(); ++p) {
    const auto state = PersonState(p, time);
    if (state && state->moving) names.push_back(people_[p].spec.name);
  }
  return names;
}

}  // namespace hoidslam::synth
