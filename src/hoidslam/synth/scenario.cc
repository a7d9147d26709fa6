#include "hoidslam/synth/scenario.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <set>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/synth/builtin_scenarios.h"

namespace hoidslam::synth {
namespace {

using nlohmann::json;

constexpr int kMaxCameraFrames = 1000000;
constexpr double kDefaultCircleTurns = 2.0;

constexpr core::EnumNames<ActionType, 11> kActionNames = {{
    {ActionType::kWalkTo, "walk_to"},
    {ActionType::kStop, "stop"},
    {ActionType::kPickUp, "pick_up"},
    {ActionType::kCarryTo, "carry_to"},
    {ActionType::kPutDown, "put_down"},
    {ActionType::kSitOn, "sit_on"},
    {ActionType::kPush, "push"},
    {ActionType::kStandAt, "stand_at"},
    {ActionType::kGesture, "gesture"},
    {ActionType::kFace, "face"},
    {ActionType::kLeave, "leave"},
}};

// A JSON value and its key path ("people[1].actions[3]"), for messages that name the key.
class Node {
 public:
  Node(const json& value, std::string key, const std::string& source)
      : value_(value), key_(std::move(key)), source_(source) {}

  const std::string& key() const { return key_; }
  const json& value() const { return value_; }

  [[noreturn]] void Fail(const std::string& what) const {
    throw core::InputError::InFile(source_, fmt::format("{}: {}", key_.empty() ? "(top level)" : key_, what));
  }

  bool Has(const std::string& name) const { return value_.is_object() && value_.contains(name); }

  Node Child(const std::string& name) const {
    if (!Has(name)) Fail(fmt::format("missing key '{}'", name));
    return Node(value_.at(name), key_.empty() ? name : key_ + "." + name, source_);
  }

  Node Element(std::size_t i) const { return Node(value_.at(i), fmt::format("{}[{}]", key_, i), source_); }

  // Rejects keys other than `allowed`, so that a misspelt key is an error rather than silently ignored.
  void AllowOnly(std::initializer_list<std::string_view> allowed) const {
    RequireObject();
    for (const auto& item : value_.items()) {
      if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
      std::string names;
      for (const std::string_view name : allowed) names += (names.empty() ? "" : ", ") + std::string(name);
      Node(item.value(), key_.empty() ? item.key() : key_ + "." + item.key(), source_)
          .Fail(fmt::format("unknown key (allowed here: {})", names));
    }
  }

  void RequireObject() const {
    if (!value_.is_object()) Fail(fmt::format("must be an object, not {}", value_.type_name()));
  }

  std::size_t ArraySize() const {
    if (!value_.is_array()) Fail(fmt::format("must be an array, not {}", value_.type_name()));
    return value_.size();
  }

  double Number() const {
    if (!value_.is_number()) Fail(fmt::format("must be a number, not {}", value_.type_name()));
    return value_.get<double>();
  }
  double Number(double lo, double hi) const {
    const double v = Number();
    if (!(v >= lo && v <= hi)) Fail(fmt::format("{} is outside [{}, {}]", v, lo, hi));
    return v;
  }
  std::uint64_t Unsigned() const {
    if (!value_.is_number_unsigned()) Fail("must be a whole number >= 0");
    return value_.get<std::uint64_t>();
  }
  int Int(int lo, int hi) const {
    if (!value_.is_number_integer()) Fail("must be a whole number");
    // Above int64's range, get<std::int64_t> would wrap (2^64 - 1 reads as -1).
    const bool above = value_.is_number_unsigned() && value_.get<std::uint64_t>() > static_cast<std::uint64_t>(hi);
    const auto v = value_.get<std::int64_t>();
    if (above || v < lo || v > hi) Fail(fmt::format("{} is outside [{}, {}]", value_.dump(), lo, hi));
    return static_cast<int>(v);
  }
  bool Bool() const {
    if (!value_.is_boolean()) Fail(fmt::format("must be true or false, not {}", value_.type_name()));
    return value_.get<bool>();
  }
  std::string String() const {
    if (!value_.is_string()) Fail(fmt::format("must be a string, not {}", value_.type_name()));
    return value_.get<std::string>();
  }
  template <int N>
  Eigen::Matrix<double, N, 1> Vector() const {
    if (!value_.is_array() || value_.size() != N) Fail(fmt::format("must be an array of {} numbers", N));
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = Element(static_cast<std::size_t>(i)).Number();
    return v;
  }

  // The value a parser such as ParseObjectKind(text, parameter) reads from this string. Those parsers name the
  // key as a parameter ("parameter <key>: unknown ..."); the message is given here as every scenario error is,
  // "<source>: <key>: unknown ...".
  template <typename Parse>
  auto Parsed(Parse parse) const {
    const std::string text = String();
    try {
      return parse(text, key_);
    } catch (const core::InputError& e) {
      const std::string prefix = core::InputError::ForParameter(key_, "").what();
      std::string_view what = e.what();
      if (what.starts_with(prefix)) what.remove_prefix(prefix.size());
      Fail(std::string(what));
    }
  }

  // Optional members: the default when absent.
  double NumberOr(const std::string& name, double fallback, double lo, double hi) const {
    return Has(name) ? Child(name).Number(lo, hi) : fallback;
  }

 private:
  const json& value_;
  std::string key_;
  const std::string& source_;
};

ActionType ParseActionType(std::string_view text, const std::string& parameter) {
  return core::ParseEnumName(kActionNames, text, parameter, "action");
}

core::Pose ParseAnchor(const Node& camera) {
  const Eigen::Vector3d position = camera.Child("position").Vector<3>();
  if (camera.Has("look_at")) {
    const Node look_at = camera.Child("look_at");
    try {
      return CameraPoseLookingAt(position, look_at.Vector<3>());
    } catch (const core::InputError& e) {
      look_at.Fail(e.what());
    }
  }
  return CameraPoseFromYawPitch(position, camera.NumberOr("yaw_deg", 90.0, -360.0, 360.0),
                                camera.NumberOr("pitch_deg", 0.0, -89.0, 89.0));
}

std::vector<CameraWaypoint> ParseWaypoints(const Node& list) {
  std::vector<CameraWaypoint> waypoints;
  const std::size_t n = list.ArraySize();
  if (n < 2) list.Fail(fmt::format("needs at least two waypoints, got {}", n));
  for (std::size_t i = 0; i < n; ++i) {
    const Node node = list.Element(i);
    node.AllowOnly({"time", "position", "yaw_deg", "pitch_deg", "roll_deg"});
    CameraWaypoint w;
    w.time = node.Child("time").Number(0.0, 1e6);
    if (i == 0 && w.time != 0.0) node.Child("time").Fail("must be 0: the path starts at its first waypoint");
    if (i > 0 && !(w.time > waypoints.back().time)) {
      node.Child("time").Fail(
          fmt::format("must be after waypoints[{}].time ({} s), got {}", i - 1, waypoints.back().time, w.time));
    }
    w.position = node.Child("position").Vector<3>();
    w.yaw_deg = node.NumberOr("yaw_deg", w.yaw_deg, -360.0, 360.0);
    w.pitch_deg = node.NumberOr("pitch_deg", w.pitch_deg, -89.0, 89.0);
    w.roll_deg = node.NumberOr("roll_deg", w.roll_deg, -360.0, 360.0);
    waypoints.push_back(w);
  }
  return waypoints;
}

CameraSpec ParseCamera(const Node& camera) {
  static constexpr std::array kProceduralKeys = {"fps", "frames", "amplitude", "angle_amplitude_deg", "period",
                                                 "start_time"};
  static constexpr std::array kCircleKeys = {"radius", "turns"};
  static constexpr std::array kShakeKeys = {"wobble", "wobble_angle_deg", "wobble_seed"};
  static constexpr std::array kAnchorKeys = {"position", "look_at", "yaw_deg", "pitch_deg"};
  camera.AllowOnly({"tum", "procedural", "fps", "frames", "amplitude", "angle_amplitude_deg", "period", "start_time",
                    "radius", "turns", "wobble", "wobble_angle_deg", "wobble_seed", "waypoints", "position", "look_at",
                    "yaw_deg", "pitch_deg"});
  CameraSpec spec;
  if (camera.Has("tum") == camera.Has("procedural")) camera.Fail("give exactly one of 'tum' and 'procedural'");
  const auto only = [&camera](const auto& keys, const char* what) {
    for (const char* key : keys) {
      if (camera.Has(key)) camera.Child(key).Fail(what);
    }
  };
  if (camera.Has("tum")) {
    spec.T_anchor = ParseAnchor(camera);
    spec.tum = camera.Child("tum").String();
    if (spec.tum.empty() || spec.tum.find('/') != std::string::npos || spec.tum.find("..") != std::string::npos) {
      camera.Child("tum").Fail("must be a TUM path name such as 'fr3_walking_xyz'");
    }
    only(kProceduralKeys, "only for a procedural camera");
    only(kCircleKeys, "only for a procedural circle camera");
    only(kShakeKeys, "only for a procedural circle or waypoints camera");
    only(std::array{"waypoints"}, "only for a procedural waypoints camera");
    return spec;
  }
  ProceduralPathOptions& p = spec.procedural;
  p.motion = camera.Child("procedural").Parsed(ParseProceduralMotion);
  p.fps = camera.NumberOr("fps", p.fps, 1.0, 1000.0);
  p.start_time = camera.NumberOr("start_time", p.start_time, 0.0, 1e10);
  const bool circle = p.motion == ProceduralMotion::kCircle;
  const bool waypoints = p.motion == ProceduralMotion::kWaypoints;
  if (!circle) only(kCircleKeys, "only for the circle camera (\"procedural\": \"circle\")");
  if (!circle && !waypoints) {
    only(kShakeKeys, "only for the circle and waypoints cameras (\"procedural\": \"circle\" or \"waypoints\")");
  }
  if (!waypoints) only(std::array{"waypoints"}, "only for the waypoints camera (\"procedural\": \"waypoints\")");
  if (circle || waypoints) {
    p.wobble = camera.NumberOr("wobble", p.wobble, 0.0, 0.5);
    p.wobble_angle_deg = camera.NumberOr("wobble_angle_deg", p.wobble_angle_deg, 0.0, 10.0);
    if (camera.Has("wobble_seed")) p.wobble_seed = camera.Child("wobble_seed").Unsigned();
  }
  if (waypoints) {
    // The waypoints place the path in the room and set its length.
    only(kAnchorKeys, "not for the waypoints camera: it starts at its first waypoint");
    only(std::array{"frames", "amplitude", "angle_amplitude_deg", "period"}, "not for the waypoints camera");
    const Node list = camera.Child("waypoints");
    p.waypoints = ParseWaypoints(list);
    const std::size_t frames = WaypointFrameCount(p.waypoints, p.fps);
    if (frames > static_cast<std::size_t>(kMaxCameraFrames)) {
      list.Element(p.waypoints.size() - 1)
          .Child("time")
          .Fail(fmt::format("{} s at {} fps are {} frames, more than {}", p.waypoints.back().time, p.fps, frames,
                            kMaxCameraFrames));
    }
    p.frames = frames;
    const CameraWaypoint& first = p.waypoints.front();
    spec.T_anchor = CameraPoseFromYawPitchRoll(first.position, first.yaw_deg, first.pitch_deg, first.roll_deg);
    p.T_anchor = spec.T_anchor;
    return spec;
  }
  spec.T_anchor = ParseAnchor(camera);
  if (camera.Has("frames")) p.frames = static_cast<std::size_t>(camera.Child("frames").Int(1, kMaxCameraFrames));
  p.amplitude = camera.NumberOr("amplitude", p.amplitude, 0.0, 3.0);
  p.angle_amplitude_deg = camera.NumberOr("angle_amplitude_deg", p.angle_amplitude_deg, 0.0, 90.0);
  p.period = camera.NumberOr("period", p.period, 0.1, 1e6);
  p.T_anchor = spec.T_anchor;
  if (!circle) return spec;
  p.radius = camera.NumberOr("radius", p.radius, 0.05, 10.0);
  // The circle's length: `frames`, else `turns` turns of `period` seconds each.
  if (camera.Has("turns") && camera.Has("frames")) camera.Child("turns").Fail("give either 'turns' or 'frames'");
  if (!camera.Has("frames")) {
    const double turns = camera.NumberOr("turns", kDefaultCircleTurns, 0.01, 1000.0);
    const double frames = std::max(1.0, std::round(turns * p.period * p.fps));
    if (frames > kMaxCameraFrames) {
      camera.Child(camera.Has("turns") ? "turns" : "period")
          .Fail(fmt::format("{} turns of {} s at {} fps are {} frames, more than {}", turns, p.period, p.fps, frames,
                            kMaxCameraFrames));
    }
    p.frames = static_cast<std::size_t>(frames);
  }
  return spec;
}

std::string ObjectName(const Node& node, const OfficeLayout& office) {
  const std::string name = node.String();
  if (office.FindObject(name) == nullptr) node.Fail(fmt::format("unknown object '{}'", name));
  return name;
}

Eigen::Vector2d PointInRoom(const Node& node, const OfficeLayout& office) {
  const Eigen::Vector2d xy = node.Vector<2>();
  if (xy.x() < 0.0 || xy.y() < 0.0 || xy.x() > office.room.x() || xy.y() > office.room.y()) {
    node.Fail(
        fmt::format("({}, {}) is outside the room (0..{}, 0..{})", xy.x(), xy.y(), office.room.x(), office.room.y()));
  }
  return xy;
}

Action ParseAction(const Node& node, const OfficeLayout& office) {
  node.RequireObject();
  Action action;
  action.key = node.key();
  action.type = node.Child("action").Parsed(ParseActionType);
  auto require_chair = [&](const Node& object) {
    if (office.FindObject(action.object)->kind != ObjectKind::kChair) {
      object.Fail(fmt::format("'{}' is not a chair", action.object));
    }
  };
  auto duration = [&] { action.duration = node.Child("duration").Number(0.01, 1e5); };
  switch (action.type) {
    case ActionType::kWalkTo:
    case ActionType::kCarryTo:
    case ActionType::kPutDown:
    case ActionType::kFace:
    case ActionType::kLeave:
      node.AllowOnly({"action", "at", "to"});
      action.to = PointInRoom(node.Child("to"), office);
      break;
    case ActionType::kStop:
    case ActionType::kGesture:
      node.AllowOnly({"action", "at", "duration"});
      duration();
      break;
    case ActionType::kPickUp:
      node.AllowOnly({"action", "at", "object"});
      action.object = ObjectName(node.Child("object"), office);
      break;
    case ActionType::kSitOn:
      node.AllowOnly({"action", "at", "object", "duration", "gesture"});
      action.object = ObjectName(node.Child("object"), office);
      require_chair(node.Child("object"));
      duration();
      if (node.Has("gesture")) action.gesture = node.Child("gesture").Bool();
      break;
    case ActionType::kPush:
      node.AllowOnly({"action", "at", "object", "to"});
      action.object = ObjectName(node.Child("object"), office);
      require_chair(node.Child("object"));
      action.to = PointInRoom(node.Child("to"), office);
      break;
    case ActionType::kStandAt:
      node.AllowOnly({"action", "at", "object", "duration", "distance", "position"});
      action.object = ObjectName(node.Child("object"), office);
      duration();
      action.distance = node.NumberOr("distance", action.distance, 0.3, 5.0);
      if (node.Has("position")) action.position = PointInRoom(node.Child("position"), office);
      break;
  }
  if (node.Has("at")) action.at = node.Child("at").Number(0.0, 1e6);
  return action;
}

cv::Vec3f Tint(const Node& node) {
  const Eigen::Vector3d v = node.Vector<3>();
  if ((v.array() < 0.0).any() || (v.array() > 2.0).any()) node.Fail("every channel must be in [0, 2]");
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

PersonSpec ParsePerson(const Node& node, const OfficeLayout& office) {
  node.AllowOnly(
      {"name", "height", "shirt", "trousers", "skin", "hair", "start", "facing_deg", "enter_at", "speed", "actions"});
  PersonSpec person;
  person.name = node.Child("name").String();
  if (person.name.empty()) node.Child("name").Fail("must not be empty");
  person.shape.height = node.NumberOr("height", person.shape.height, 1.2, 2.2);
  if (node.Has("shirt")) person.shape.shirt = node.Child("shirt").Int(0, 1000);
  if (node.Has("trousers")) person.shape.trousers = node.Child("trousers").Int(0, 1000);
  if (node.Has("skin")) person.shape.skin_tint = Tint(node.Child("skin"));
  if (node.Has("hair")) person.shape.hair_tint = Tint(node.Child("hair"));
  person.start = PointInRoom(node.Child("start"), office);
  person.facing_deg = node.NumberOr("facing_deg", 0.0, -360.0, 360.0);
  person.enter_at = node.NumberOr("enter_at", 0.0, 0.0, 1e6);
  person.speed = node.NumberOr("speed", person.speed, 0.2, 3.0);
  if (node.Has("actions")) {
    const Node actions = node.Child("actions");
    for (std::size_t i = 0, n = actions.ArraySize(); i < n; ++i) {
      person.actions.push_back(ParseAction(actions.Element(i), office));
      if (person.actions.back().type == ActionType::kLeave && i + 1 != n) {
        actions.Element(i + 1).Fail("no action can follow 'leave'");
      }
    }
  }
  return person;
}

OfficeObject ParseObject(const Node& node) {
  node.AllowOnly({"name", "type", "position", "z", "yaw_deg", "variant"});
  OfficeObject object;
  object.name = node.Child("name").String();
  object.kind = node.Child("type").Parsed(ParseObjectKind);
  object.position = node.Child("position").Vector<2>();
  if (node.Has("z")) object.z = node.Child("z").Number(0.0, 10.0);
  object.yaw_deg = node.NumberOr("yaw_deg", 0.0, -360.0, 360.0);
  if (node.Has("variant")) object.variant = node.Child("variant").Int(0, 1000);
  return object;
}

// Nullopt for "default": the default office's decoration.
std::optional<std::vector<WallPanel>> ParseWalls(const Node& node) {
  if (node.value().is_string()) {
    if (node.String() != "default") node.Fail("must be \"default\" or an array of wall panels");
    return std::nullopt;
  }
  std::vector<WallPanel> panels;
  for (std::size_t i = 0, n = node.ArraySize(); i < n; ++i) {
    const Node p = node.Element(i);
    p.AllowOnly({"type", "wall", "at", "z", "size", "variant"});
    WallPanel panel;
    panel.kind = p.Child("type").Parsed(ParsePanelKind);
    panel.wall = p.Child("wall").Parsed(ParseWall);
    panel.at = p.Child("at").Number(0.0, 100.0);
    panel.size = p.Has("size") ? Eigen::Vector2d(p.Child("size").Vector<2>()) : DefaultPanelSize(panel.kind);
    // A door stands on the floor.
    if (panel.kind == PanelKind::kDoor) {
      if (p.Has("z")) p.Child("z").Fail("not for a door: it stands on the floor");
      panel.z = panel.size.y() / 2.0;
    } else {
      panel.z = p.NumberOr("z", panel.z, 0.0, 100.0);
    }
    if (p.Has("variant")) {
      if (panel.kind != PanelKind::kPoster) p.Child("variant").Fail("only for a poster");
      panel.variant = p.Child("variant").Int(0, 1000);
    }
    panels.push_back(panel);
  }
  return panels;
}

OfficeLayout ParseOffice(const Node& node, const std::string& source) {
  if (node.value().is_string()) {
    if (node.String() != "default") node.Fail("must be \"default\" or an object describing the layout");
    return DefaultOfficeLayout();
  }
  node.AllowOnly({"base", "room", "desks", "shelves", "objects", "walls", "patchwork_walls_seed"});
  OfficeLayout base;
  if (node.Has("base")) {
    const Node base_node = node.Child("base");
    if (base_node.String() == "default") {
      base = DefaultOfficeLayout();
    } else if (base_node.String() != "empty") {
      base_node.Fail("must be \"default\" or \"empty\"");
    }
  }
  OfficeLayout office = base;
  if (node.Has("room")) office.room = node.Child("room").Vector<3>();
  if (node.Has("patchwork_walls_seed")) office.patchwork_walls_seed = node.Child("patchwork_walls_seed").Unsigned();
  if (node.Has("desks")) {
    const Node desks = node.Child("desks");
    for (std::size_t i = 0, n = desks.ArraySize(); i < n; ++i) {
      const Node d = desks.Element(i);
      d.AllowOnly({"name", "position", "yaw_deg", "size", "height"});
      Desk desk;
      desk.name = d.Child("name").String();
      desk.position = d.Child("position").Vector<2>();
      desk.yaw_deg = d.NumberOr("yaw_deg", 0.0, -360.0, 360.0);
      if (d.Has("size")) desk.size = d.Child("size").Vector<2>();
      desk.height = d.NumberOr("height", desk.height, 0.0, 10.0);
      office.desks.push_back(desk);
    }
  }
  if (node.Has("shelves")) {
    const Node shelves = node.Child("shelves");
    for (std::size_t i = 0, n = shelves.ArraySize(); i < n; ++i) {
      const Node s = shelves.Element(i);
      s.AllowOnly({"name", "position", "yaw_deg", "size", "boards"});
      Shelf shelf;
      shelf.name = s.Child("name").String();
      shelf.position = s.Child("position").Vector<2>();
      shelf.yaw_deg = s.NumberOr("yaw_deg", 0.0, -360.0, 360.0);
      if (s.Has("size")) shelf.size = s.Child("size").Vector<3>();
      if (s.Has("boards")) shelf.boards = s.Child("boards").Int(2, 50);
      office.shelves.push_back(shelf);
    }
  }
  if (node.Has("objects")) {
    const Node objects = node.Child("objects");
    for (std::size_t i = 0, n = objects.ArraySize(); i < n; ++i) {
      office.objects.push_back(ParseObject(objects.Element(i)));
    }
  }
  if (node.Has("walls")) office.walls = ParseWalls(node.Child("walls"));
  office.Check(source, node.key(), base);
  return office;
}

DetectorNoiseOptions ParseDetectorNoise(const Node& node) {
  node.AllowOnly({"miss_rate", "box_jitter", "false_positive_rate", "class_confusion_rate", "seed"});
  DetectorNoiseOptions o;
  o.miss_rate = node.NumberOr("miss_rate", o.miss_rate, 0.0, 1.0);
  o.box_jitter = node.NumberOr("box_jitter", o.box_jitter, 0.0, 1.0);
  o.false_positive_rate = node.NumberOr("false_positive_rate", o.false_positive_rate, 0.0, 100.0);
  o.class_confusion_rate = node.NumberOr("class_confusion_rate", o.class_confusion_rate, 0.0, 1.0);
  if (node.Has("seed")) o.seed = node.Child("seed").Unsigned();
  return o;
}

SensorNoiseOptions ParseSensorNoise(const Node& node) {
  node.AllowOnly({"rgb_noise_sigma", "rgb_blur_sigma", "depth_noise_scale", "disparity_step", "min_range", "max_range",
                  "edge_jump_ratio", "edge_erosion_probability", "dropout_probability"});
  SensorNoiseOptions o;
  o.rgb_noise_sigma = node.NumberOr("rgb_noise_sigma", o.rgb_noise_sigma, 0.0, 100.0);
  o.rgb_blur_sigma = node.NumberOr("rgb_blur_sigma", o.rgb_blur_sigma, 0.0, 10.0);
  o.depth_noise_scale = node.NumberOr("depth_noise_scale", o.depth_noise_scale, 0.0, 100.0);
  o.disparity_step = node.NumberOr("disparity_step", o.disparity_step, 0.0, 1.0);
  o.min_range = node.NumberOr("min_range", o.min_range, 0.0, 100.0);
  o.max_range = node.NumberOr("max_range", o.max_range, 0.0, 100.0);
  o.edge_jump_ratio = node.NumberOr("edge_jump_ratio", o.edge_jump_ratio, 1e-6, 100.0);
  o.edge_erosion_probability = node.NumberOr("edge_erosion_probability", o.edge_erosion_probability, 0.0, 1.0);
  o.dropout_probability = node.NumberOr("dropout_probability", o.dropout_probability, 0.0, 1.0);
  if (o.max_range <= o.min_range) node.Child("max_range").Fail("must be greater than min_range");
  return o;
}

std::vector<CoveredStretch> ParseCovered(const Node& node) {
  std::vector<CoveredStretch> stretches;
  for (std::size_t i = 0, n = node.ArraySize(); i < n; ++i) {
    const Node item = node.Element(i);
    item.AllowOnly({"from", "for"});
    const CoveredStretch stretch{item.Child("from").Number(0.0, 1e6), item.Child("for").Number(0.001, 1e5)};
    if (!stretches.empty() && stretch.from < stretches.back().end()) {
      item.Child("from").Fail(fmt::format("must not be before the end of covered[{}] at {} s", i - 1,
                                          stretches.back().end()));
    }
    stretches.push_back(stretch);
  }
  return stretches;
}

std::vector<DarkStretch> ParseDark(const Node& node) {
  std::vector<DarkStretch> stretches;
  for (std::size_t i = 0, n = node.ArraySize(); i < n; ++i) {
    const Node item = node.Element(i);
    item.AllowOnly({"from", "for", "level"});
    DarkStretch stretch{item.Child("from").Number(0.0, 1e6), item.Child("for").Number(0.001, 1e5)};
    if (item.Has("level")) {
      stretch.level = item.Child("level").Number();
      if (!(stretch.level > 0.0 && stretch.level <= 1.0)) {
        item.Child("level").Fail(fmt::format("{} is outside (0, 1]", stretch.level));
      }
    }
    if (!stretches.empty() && stretch.from < stretches.back().end()) {
      item.Child("from").Fail(fmt::format("must not be before the end of dark[{}] at {} s", i - 1,
                                          stretches.back().end()));
    }
    stretches.push_back(stretch);
  }
  return stretches;
}

TextureOptions ParseTextures(const Node& node) {
  node.AllowOnly({"seed", "size", "variants"});
  TextureOptions o;
  if (node.Has("seed")) o.seed = node.Child("seed").Unsigned();
  if (node.Has("size")) {
    o.size = node.Child("size").Int(16, 2048);
    if ((o.size & (o.size - 1)) != 0) node.Child("size").Fail("must be a power of two");
  }
  if (node.Has("variants")) o.variants = node.Child("variants").Int(1, 64);
  return o;
}

// Where nlohmann::json stops reading invalid JSON: its count of bytes read, from 1. Only parse_error carries it;
// a number out of double's range (1e400) throws out_of_range without one, so the text is read again by a SAX
// reader that builds nothing and keeps the position of the error.
std::size_t JsonErrorByte(std::string_view text) {
  struct ErrorPosition {
    std::size_t byte = 1;
    bool null() { return true; }
    bool boolean(bool) { return true; }
    bool number_integer(json::number_integer_t) { return true; }
    bool number_unsigned(json::number_unsigned_t) { return true; }
    bool number_float(json::number_float_t, const json::string_t&) { return true; }
    bool string(json::string_t&) { return true; }
    bool binary(json::binary_t&) { return true; }
    bool start_object(std::size_t) { return true; }
    bool key(json::string_t&) { return true; }
    bool end_object() { return true; }
    bool start_array(std::size_t) { return true; }
    bool end_array() { return true; }
    bool parse_error(std::size_t position, const std::string&, const json::exception&) {
      byte = std::max<std::size_t>(position, 1);
      return false;
    }
  } reader;
  json::sax_parse(text.begin(), text.end(), &reader);
  return reader.byte;
}

}  // namespace

std::string_view ToString(ActionType type) { return core::EnumName(kActionNames, type); }

Scenario ParseScenario(std::string_view text, const std::string& source) {
  Scenario scenario;
  scenario.source = source;
  try {
    scenario.document = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number such as 1e400
    const std::size_t end = std::min<std::size_t>(JsonErrorByte(text) - 1, text.size());
    const std::size_t line =
        1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
    throw core::InputError::AtLine(source, line, "not valid JSON: " + std::string(e.what()));
  }
  const Node root(scenario.document, "", scenario.source);
  root.AllowOnly({"name", "description", "seed", "frames", "camera", "covered", "dark", "office", "people",
                  "detector_noise", "sensor_noise", "textures"});
  scenario.name = root.Child("name").String();
  if (scenario.name.empty()) root.Child("name").Fail("must not be empty");
  if (root.Has("description")) scenario.description = root.Child("description").String();
  if (root.Has("seed")) scenario.seed = root.Child("seed").Unsigned();
  if (root.Has("frames")) scenario.max_frames = static_cast<std::size_t>(root.Child("frames").Int(0, 10000000));
  scenario.camera = ParseCamera(root.Child("camera"));
  if (root.Has("covered")) scenario.covered = ParseCovered(root.Child("covered"));
  if (root.Has("dark")) scenario.dark = ParseDark(root.Child("dark"));
  scenario.office = root.Has("office") ? ParseOffice(root.Child("office"), scenario.source) : DefaultOfficeLayout();
  if (root.Has("people")) {
    const Node people = root.Child("people");
    std::set<std::string> names;
    for (std::size_t i = 0, n = people.ArraySize(); i < n; ++i) {
      scenario.people.push_back(ParsePerson(people.Element(i), scenario.office));
      if (!names.insert(scenario.people.back().name).second) {
        people.Element(i).Child("name").Fail(fmt::format("duplicate name '{}'", scenario.people.back().name));
      }
    }
  }
  if (root.Has("detector_noise")) scenario.detector_noise = ParseDetectorNoise(root.Child("detector_noise"));
  if (root.Has("sensor_noise")) scenario.sensor_noise = ParseSensorNoise(root.Child("sensor_noise"));
  if (root.Has("textures")) scenario.textures = ParseTextures(root.Child("textures"));
  return scenario;
}

bool Scenario::LensCoveredAt(double time) const {
  return std::any_of(covered.begin(), covered.end(), [time](const CoveredStretch& s) { return s.Covers(time); });
}

double Scenario::LightLevelAt(double time) const {
  for (const DarkStretch& stretch : dark) {
    if (stretch.Covers(time)) return stretch.level;
  }
  return 1.0;
}

std::vector<std::string> BuiltinScenarioNames() {
  std::vector<std::string> names;
  for (const EmbeddedFile& file : BuiltinScenarioFiles()) names.emplace_back(file.name);
  std::sort(names.begin(), names.end());
  return names;
}

std::optional<std::string_view> BuiltinScenarioText(std::string_view name) {
  for (const EmbeddedFile& file : BuiltinScenarioFiles()) {
    if (file.name == name) return file.text;
  }
  return std::nullopt;
}

Scenario LoadScenario(const std::string& name_or_path) {
  if (const auto text = BuiltinScenarioText(name_or_path)) {
    return ParseScenario(*text, fmt::format("scenarios/{}.json", name_or_path));
  }
  const std::filesystem::path path(name_or_path);
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found) {
    throw core::InputError::InFile(path, fmt::format("no such scenario file, and no shipped scenario of that name "
                                                     "(shipped: {})",
                                                     fmt::join(BuiltinScenarioNames(), ", ")));
  }
  // Without these checks a folder or an unreadable file reads as empty text, reported as bad JSON on line 1.
  if (status.type() == fs::file_type::none) {
    throw core::InputError::InFile(path, "cannot look at the scenario file: " + error.message());
  }
  if (!fs::is_regular_file(status)) {
    throw core::InputError::InFile(path, "is a folder or a special file, not a scenario file");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    throw core::InputError::InFile(path, fmt::format("cannot open the scenario file: {}", std::strerror(errno)));
  }
  const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (file.bad()) {
    throw core::InputError::InFile(path, fmt::format("cannot read the scenario file: {}", std::strerror(errno)));
  }
  return ParseScenario(text, path.string());
}

}  // namespace hoidslam::synth
