#pragma once
// Scenarios: what a synthetic sequence shows, as a JSON file a user can copy and change (format:
// docs/synthetic-benchmark.md). A scenario names the camera path, the office layout, the people and what
// they do, and the detector and sensor noise. The scenarios shipped in scenarios/*.json are compiled into the
// library so `--scenario walking_xyz` works from any folder.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hoidslam/synth/camera_path.h"
#include "hoidslam/synth/detector_noise.h"
#include "hoidslam/synth/office.h"
#include "hoidslam/synth/people.h"
#include "hoidslam/synth/sensor_noise.h"
#include "hoidslam/synth/textures.h"

namespace hoidslam::synth {

enum class ActionType {
  kWalkTo,   // walk to `to`
  kStop,     // stand still for `duration`
  kPickUp,   // walk to `object`, reach for it, lift it (one hand or both, by its kind)
  kCarryTo,  // walk to `to` with the object in hand (an error when the hands are empty)
  kPutDown,  // walk next to `to`, put the carried object there (on a desk when a desk is there, else the floor)
  kSitOn,    // walk to chair `object`, sit on it for `duration`, stand up; the chair does not move
  kPush,     // walk behind chair `object`, grip its back, push it until it stands at `to`, let go
  kStandAt,  // stand in front of `object` (`distance` out along its front, or at `position`), facing it, for
             // `duration`, without touching it
  kGesture,  // talk with the hands and turn the head for `duration` (also while seated: see `sit_on`)
  kFace,     // turn on the spot to face the point `to` (say, the camera, to talk to whoever holds it)
  kLeave,    // walk to `to` and vanish (a door, or out of the room's view)
};

std::string_view ToString(ActionType type);

struct Action {
  ActionType type = ActionType::kStop;
  std::string key;                          // where it is in the scenario, e.g. "people[1].actions[3]", for messages
  std::optional<double> at;                 // seconds from the first frame: do not start before this time
  Eigen::Vector2d to = {0.0, 0.0};          // walk_to, carry_to, put_down, push, face, leave
  std::string object;                       // pick_up, sit_on, push, stand_at
  double duration = 0.0;                    // stop, sit_on, stand_at, gesture; seconds
  double distance = 0.8;                    // stand_at: metres in front of the object where the person stands
  std::optional<Eigen::Vector2d> position;  // stand_at: where to stand instead (facing the object)
  bool gesture = false;                     // sit_on: gesture while seated (the person counts as moving)
};

struct PersonSpec {
  std::string name;
  BodyShape shape;
  Eigen::Vector2d start = {0.0, 0.0};  // where the person stands at `enter_at`
  double facing_deg = 0.0;             // initial heading
  double enter_at = 0.0;               // seconds from the first frame; absent before
  double speed = 1.1;                  // walking speed, m/s
  std::vector<Action> actions;
};

struct CameraSpec {
  std::string tum;                               // TUM path name, e.g. "fr3_walking_xyz"; empty = procedural
  ProceduralPathOptions procedural;              // used when `tum` is empty (T_anchor set from the anchor)
  core::Pose T_anchor = core::Pose::Identity();  // the first camera pose in the room
};

// A stretch of time in which the lens is covered (a hand, a cap) while the camera moves on: the colour image is
// dark but for sensor noise, and there is no depth.
struct CoveredStretch {
  double from = 0.0;      // seconds from the first frame
  double duration = 0.0;  // seconds, > 0

  double end() const { return from + duration; }
  bool Covers(double time) const { return time >= from && time < end(); }
};

// A stretch of time in which the lights are dimmed: the colour image is scaled to `level` of its brightness before
// the sensor noise (which stays); depth, boxes and masks are as ever.
struct DarkStretch {
  double from = 0.0;      // seconds from the first frame
  double duration = 0.0;  // seconds, > 0
  double level = 0.1;     // share of the brightness left, in (0, 1]

  double end() const { return from + duration; }
  bool Covers(double time) const { return time >= from && time < end(); }
};

struct Scenario {
  std::string source;  // where it came from, for messages: a file path or "builtin:<name>"
  std::string name;
  std::string description;
  std::uint64_t seed = 1;
  std::size_t max_frames = 0;  // 0 = every frame of the camera path
  CameraSpec camera;
  std::vector<CoveredStretch> covered;  // in time order, none overlapping
  std::vector<DarkStretch> dark;        // in time order, none overlapping (a covered lens is dark anyway)
  OfficeLayout office;
  std::vector<PersonSpec> people;
  DetectorNoiseOptions detector_noise;
  SensorNoiseOptions sensor_noise;
  TextureOptions textures;  // photo_folder stays empty (a command-line choice)
  nlohmann::json document;  // the parsed file, to copy next to the output

  // True when `time` (seconds from the first frame) lies in a covered stretch.
  bool LensCoveredAt(double time) const;
  // The share of the brightness the lights give at `time`: the level of the dark stretch there, else 1.
  double LightLevelAt(double time) const;
};

// Parses a scenario. `source` names it in messages. Throws InputError "<source>: <key>: <what>" naming the
// offending key (e.g. "people[1].actions[3].object: unknown object 'mug7'"), or "<source>:<line>: ..." when
// the text is not JSON.
Scenario ParseScenario(std::string_view text, const std::string& source);

// The shipped scenario of that name, else the scenario file at that path. Throws InputError naming the file
// (and listing the shipped names) when there is neither, and as ParseScenario does for a bad file.
Scenario LoadScenario(const std::string& name_or_path);

// Shipped scenarios, sorted by name, and the text of one (nullopt for an unknown name).
std::vector<std::string> BuiltinScenarioNames();
std::optional<std::string_view> BuiltinScenarioText(std::string_view name);

}  // namespace hoidslam::synth
