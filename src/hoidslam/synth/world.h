#pragma once
// The simulation: turns a scenario into the state of the office at any instant (a SceneSnapshot), with the
// log of who picked up, put down, pushed or sat on what, and when.
//
// The people's actions are planned once, at construction, into timed segments (walk, turn, reach, lift,
// place, sit down, ...); objects rest where they were last put and follow the hands while held. Time is in
// seconds from the first frame. Snapshot() is const and thread-safe.

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/synth/people.h"
#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/scene.h"
#include "hoidslam/synth/textures.h"

namespace hoidslam::synth {

// One line of the event log.
struct WorldEvent {
  double time = 0.0;  // seconds from the first frame
  std::string person;
  std::string action;  // "enter", "pick_up", "put_down", "push", "sit_down", "stand_up", "stand_at", "leave"
  std::string object;  // empty when the action involves none
  std::optional<Eigen::Vector3d> from;  // object (or person) position before, when it applies
  std::optional<Eigen::Vector3d> to;    // and after
};

class World {
 public:
  // Plans every person's actions. Throws InputError "<scenario source>: <action key>: <what>" for an action
  // that cannot be done (carrying nothing to put down, picking up what someone else holds, ...).
  World(const Scenario& scenario, const TextureSet& textures);

  // The office at `time` (seconds from the first frame); snapshot.timestamp = time.
  SceneSnapshot Snapshot(double time) const;

  const std::vector<WorldEvent>& events() const { return events_; }  // sorted by time
  double end_time() const { return end_time_; }                      // when the last action of anyone ends

  // Introspection (tests, tools). Instance ids are stable: structure first, then objects, then people.
  std::optional<int> InstanceId(std::string_view object_or_person) const;
  std::optional<core::Pose> ObjectPose(std::string_view object, double time) const;  // nullopt: unknown name
  // The pose of person `index` (scenario order), or nullopt when the person is not in the room at `time`.
  std::optional<BodyPose> PersonPose(std::size_t index, double time) const;
  std::optional<Skeleton> PersonSkeleton(std::size_t index, double time) const;
  // Names of the people and objects moving at `time`.
  std::vector<std::string> MovingAt(double time) const;

 private:
  // A stretch of one person's time line: the body blends from `a` to `b` (eased or linear in time).
  struct Segment {
    double t0 = 0.0, t1 = 0.0;
    BodyPose a, b;
    bool moving = false;
    bool eased = false;
    int held = -1;  // object index held during the segment, or -1
    core::Pose T_bo_a = core::Pose::Identity(), T_bo_b = core::Pose::Identity();  // held object in the body frame
  };
  struct PersonTrack {
    PersonSpec spec;
    int id = 0;
    double exit = 0.0;  // time the person leaves the room (infinity when never)
    std::vector<Segment> segments;
  };
  struct Hold {
    double t0 = 0.0, t1 = 0.0;  // [grasp, release)
    std::size_t person = 0;
  };
  struct ObjectTrack {
    OfficeObject info;
    int id = 0;
    std::vector<Box> parts;                            // in the object frame
    std::vector<std::pair<double, core::Pose>> rests;  // (from time, resting pose), by time
    std::vector<Hold> holds;                           // by time
  };
  class Planner;

  // A person at one instant: the pose, the segment it lies in (nullptr before the first), how far into it.
  struct PersonInstant {
    BodyPose pose;
    const Segment* segment = nullptr;
    double s = 0.0;  // eased progress through the segment
    bool moving = false;
  };

  const Segment* SegmentAt(const PersonTrack& person, double time) const;
  // Nullopt when the person is not in the room at `time`.
  std::optional<PersonInstant> PersonState(std::size_t index, double time) const;
  // Pose and moving flag of object `index`.
  std::pair<core::Pose, bool> ObjectState(std::size_t index, double time) const;

  std::vector<SceneInstance> structure_;
  std::vector<ObjectTrack> objects_;
  std::vector<PersonTrack> people_;
  std::vector<WorldEvent> events_;
  double end_time_ = 0.0;
  TextureSet textures_;  // a cheap copy (images are shared) for the people's clothes
};

}  // namespace hoidslam::synth
