#include "hoidslam/synth/scenario.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>


#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"

namespace hoidslam::synth {
namespace {

using ::testing::HasSubstr;

// The message of the InputError that parsing `text` throws (fails the test when nothing is thrown).
std::string ParseError(const std::string& text) {
  try {
    ParseScenario(text, "x.json");
  } catch (const core::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for: " << text;
  return "";
}

// A valid scenario with `people` (a JSON array) and `extra` top-level members.
std::string Valid(const std::string& people = "[]", const std::string& extra = "") {
  return R"({"name": "t", "camera": {"procedural": "xyz", "position": [4, 1, 1.4], "look_at": [4, 4, 1]},)" + extra +
         R"( "people": )" + people + "}";
}

TEST(Scenario, ShipsTheTumLikeAndTheLoopScenariosWithTheirControls) {
  const std::vector<std::string> names = BuiltinScenarioNames();
  for (const std::string base : {"walking_static", "walking_xyz", "walking_halfsphere", "walking_rpy", "sitting_static",
                                 "carry", "crowd", "loop", "kidnap", "kidnap_unmapped"}) {
    EXPECT_THAT(names, ::testing::Contains(base));
    EXPECT_THAT(names, ::testing::Contains(base + "_static"));
  }
  EXPECT_THAT(names, ::testing::Contains("revisit_a"));
  EXPECT_THAT(names, ::testing::Contains("revisit_b"));
}

TEST(Scenario, EveryShippedScenarioParsesAndControlsMatchTheirCamera) {
  for (const std::string& name : BuiltinScenarioNames()) {
    SCOPED_TRACE(name);
    const Scenario scenario = LoadScenario(name);
    EXPECT_EQ(scenario.name, name);
    EXPECT_EQ(scenario.source, "scenarios/" + name + ".json");
    if (name.ends_with("_static") && name != "walking_static" && name != "sitting_static") {
      EXPECT_TRUE(scenario.people.empty());
      const Scenario full = LoadScenario(name.substr(0, name.size() - 7));
      EXPECT_FALSE(full.people.empty());
      EXPECT_EQ(full.document.at("camera"), scenario.document.at("camera"));
      EXPECT_EQ(full.document.value("covered", nlohmann::json()), scenario.document.value("covered", nlohmann::json()));
      EXPECT_EQ(full.document.value("office", nlohmann::json()), scenario.document.value("office", nlohmann::json()));
    }
  }
}

TEST(Scenario, ParsesPeopleAndActions) {
  const Scenario s =
      ParseScenario(Valid(R"([{"name": "a", "height": 1.6, "shirt": 2, "start": [1, 2], "facing_deg": 90, "enter_at": 3,
                  "actions": [{"action": "walk_to", "to": [3, 2], "at": 4},
                              {"action": "pick_up", "object": "cup_1"},
                              {"action": "put_down", "to": [2.6, 3.7]},
                              {"action": "sit_on", "object": "chair_1", "duration": 2, "gesture": true},
                              {"action": "stand_at", "object": "tv_1", "duration": 1, "distance": 1.2},
                              {"action": "face", "to": [4, 1]},
                              {"action": "leave", "to": [7.9, 1]}]}])",
                          R"("seed": 42, "frames": 10, "detector_noise": {"miss_rate": 0.1},)"),
                    "x.json");
  EXPECT_EQ(s.seed, 42U);
  EXPECT_EQ(s.max_frames, 10U);
  EXPECT_DOUBLE_EQ(s.detector_noise.miss_rate, 0.1);
  ASSERT_EQ(s.people.size(), 1U);
  const PersonSpec& a = s.people[0];
  EXPECT_DOUBLE_EQ(a.shape.height, 1.6);
  EXPECT_EQ(a.shape.shirt, 2);
  EXPECT_DOUBLE_EQ(a.enter_at, 3.0);
  ASSERT_EQ(a.actions.size(), 7U);
  EXPECT_EQ(a.actions[0].type, ActionType::kWalkTo);
  EXPECT_EQ(a.actions[0].at, 4.0);
  EXPECT_EQ(a.actions[1].object, "cup_1");
  EXPECT_EQ(a.actions[1].key, "people[0].actions[1]");
  EXPECT_TRUE(a.actions[3].gesture);
  EXPECT_DOUBLE_EQ(a.actions[4].distance, 1.2);
  EXPECT_EQ(a.actions[5].type, ActionType::kFace);
  EXPECT_TRUE(a.actions[5].to.isApprox(Eigen::Vector2d(4.0, 1.0)));
  EXPECT_EQ(a.actions[6].type, ActionType::kLeave);
}

TEST(Scenario, AnUnknownObjectIsNamedWithItsKey) {
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [
                  {"action": "walk_to", "to": [3, 2]}, {"action": "pick_up", "object": "mug7"}]}])")),
              HasSubstr("x.json: people[0].actions[1].object: unknown object 'mug7'"));
}

TEST(Scenario, AnUnknownActionIsNamedWithItsKey) {
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [{"action": "dance"}]}])")),
              HasSubstr("x.json: people[0].actions[0].action: unknown action 'dance'"));
}

TEST(Scenario, AMisspeltKeyIsAnError) {
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actoins": []}])")),
              HasSubstr("x.json: people[0].actoins: unknown key"));
  EXPECT_THAT(ParseError(Valid("[]", R"("sed": 3,)")), HasSubstr("x.json: sed: unknown key"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [
                  {"action": "walk_to", "to": [3, 2], "duration": 3}]}])")),
              HasSubstr("people[0].actions[0].duration: unknown key"));
}

TEST(Scenario, AWrongTypeIsNamedWithItsKey) {
  EXPECT_THAT(ParseError(Valid("[]", R"("seed": "one",)")), HasSubstr("x.json: seed: must be a whole number"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1]}])")),
              HasSubstr("people[0].start: must be an array of 2 numbers"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "height": 3.5}])")),
              HasSubstr("people[0].height: 3.5 is outside [1.2, 2.2]"));
  EXPECT_THAT(ParseError(Valid(R"({"name": "a"})")), HasSubstr("people: must be an array"));
}

TEST(Scenario, MissingAndInconsistentValuesAreNamed) {
  EXPECT_THAT(ParseError(R"({"name": "t"})"), HasSubstr("x.json: (top level): missing key 'camera'"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [{"action": "pick_up"}]}])")),
              HasSubstr("people[0].actions[0]: missing key 'object'"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [
                  {"action": "sit_on", "object": "cup_1", "duration": 2}]}])")),
              HasSubstr("people[0].actions[0].object: 'cup_1' is not a chair"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [
                  {"action": "walk_to", "to": [30, 2]}]}])")),
              HasSubstr("people[0].actions[0].to: (30, 2) is outside the room"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2]}, {"name": "a", "start": [1, 3]}])")),
              HasSubstr("people[1].name: duplicate name 'a'"));
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [
                  {"action": "leave", "to": [1, 1]}, {"action": "stop", "duration": 1}]}])")),
              HasSubstr("people[0].actions[1]: no action can follow 'leave'"));
  EXPECT_THAT(ParseError(R"({"name": "t", "camera": {"tum": "fr3_walking_xyz", "procedural": "xyz",
                             "position": [4, 1, 1.4]}})"),
              HasSubstr("camera: give exactly one of 'tum' and 'procedural'"));
  EXPECT_THAT(ParseError(R"({"name": "t", "camera": {"procedural": "zigzag", "position": [4, 1, 1.4]}})"),
              HasSubstr("camera.procedural"));
}

// A valid scenario whose camera has `camera_keys` besides the anchor, and `extra` top-level members.
std::string WithCamera(const std::string& camera_keys, const std::string& extra = "") {
  return R"({"name": "t", "camera": {)" + camera_keys + R"(, "position": [4, 2.5, 1.4], "yaw_deg": 90},)" + extra +
         R"( "people": []})";
}

TEST(Scenario, ParsesTheCircleCameraWithItsDefaults) {
  const Scenario defaults = ParseScenario(WithCamera(R"("procedural": "circle")"), "x.json");
  const ProceduralPathOptions& d = defaults.camera.procedural;
  EXPECT_EQ(d.motion, ProceduralMotion::kCircle);
  EXPECT_DOUBLE_EQ(d.radius, 0.5);
  EXPECT_DOUBLE_EQ(d.wobble, 0.03);
  EXPECT_DOUBLE_EQ(d.wobble_angle_deg, 2.0);
  EXPECT_EQ(d.wobble_seed, 1U);
  EXPECT_EQ(d.frames, 720U);  // 2 turns of 12 s at 30 Hz
  const Scenario s = ParseScenario(WithCamera(R"("procedural": "circle", "radius": 0.6, "turns": 2.25, "period": 56,
                                                 "wobble": 0.02, "wobble_angle_deg": 1.5, "wobble_seed": 9)"),
                                   "x.json");
  const ProceduralPathOptions& p = s.camera.procedural;
  EXPECT_DOUBLE_EQ(p.radius, 0.6);
  EXPECT_DOUBLE_EQ(p.wobble, 0.02);
  EXPECT_DOUBLE_EQ(p.wobble_angle_deg, 1.5);
  EXPECT_EQ(p.wobble_seed, 9U);
  EXPECT_EQ(p.frames, 3780U);  // 2.25 turns of 56 s at 30 Hz
  EXPECT_EQ(ParseScenario(WithCamera(R"("procedural": "circle", "frames": 10)"), "x.json").camera.procedural.frames,
            10U);
}

TEST(Scenario, CircleKeysOutOfRangeOrOutOfPlaceAreNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {R"("procedural": "circle", "radius": 0)", "camera.radius: 0 is outside [0.05, 10]"},
      {R"("procedural": "circle", "turns": -1)", "camera.turns: -1 is outside [0.01, 1000]"},
      {R"("procedural": "circle", "wobble": 0.8)", "camera.wobble: 0.8 is outside [0, 0.5]"},
      {R"("procedural": "circle", "wobble_angle_deg": 45)", "camera.wobble_angle_deg: 45 is outside [0, 10]"},
      {R"("procedural": "circle", "wobble_seed": -2)", "camera.wobble_seed: must be a whole number >= 0"},
      {R"("procedural": "circle", "turns": 2, "frames": 100)", "camera.turns: give either 'turns' or 'frames'"},
      {R"("procedural": "circle", "turns": 1000, "period": 1000)",
       "camera.turns: 1000 turns of 1000 s at 30 fps are 30000000 frames, more than 1000000"},
      {R"("procedural": "circle", "wobbel": 0.01)", "camera.wobbel: unknown key"},
      {R"("procedural": "xyz", "radius": 0.5)", "camera.radius: only for the circle camera"},
      {R"("tum": "fr3_walking_xyz", "turns": 2)", "camera.turns: only for a procedural circle camera"},
  };
  for (const auto& [camera_keys, message] : cases) {
    EXPECT_THAT(ParseError(WithCamera(camera_keys)), HasSubstr(std::string("x.json: ") + message));
  }
}

TEST(Scenario, CoveredStretchesAreParsedInTimeOrderAndCheckedByKey) {
  const Scenario s = ParseScenario(
      WithCamera(R"("procedural": "circle")", R"( "covered": [{"from": 2, "for": 0.5}, {"from": 4, "for": 1}],)"),
      "x.json");
  ASSERT_EQ(s.covered.size(), 2U);
  EXPECT_DOUBLE_EQ(s.covered[1].from, 4.0);
  EXPECT_DOUBLE_EQ(s.covered[1].duration, 1.0);
  EXPECT_FALSE(s.LensCoveredAt(1.99));
  EXPECT_TRUE(s.LensCoveredAt(2.0));
  EXPECT_TRUE(s.LensCoveredAt(2.49));
  EXPECT_FALSE(s.LensCoveredAt(2.5));  // the first frame at the stretch's end is uncovered
  EXPECT_TRUE(s.LensCoveredAt(4.5));
  EXPECT_FALSE(s.LensCoveredAt(5.0));
  EXPECT_TRUE(ParseScenario(WithCamera(R"("procedural": "circle")"), "x.json").covered.empty());

  const auto covered = [](const std::string& list) {
    return ParseError(WithCamera(R"("procedural": "circle")", R"( "covered": )" + list + ","));
  };
  EXPECT_THAT(covered(R"([{"from": 2, "for": 2}, {"from": 3, "for": 1}])"),
              HasSubstr("x.json: covered[1].from: must not be before the end of covered[0] at 4 s"));
  EXPECT_THAT(covered(R"([{"from": 2, "for": 0}])"), HasSubstr("x.json: covered[0].for: 0 is outside [0.001, 100000]"));
  EXPECT_THAT(covered(R"([{"from": -1, "for": 2}])"), HasSubstr("x.json: covered[0].from: -1 is outside [0, 1000000]"));
  EXPECT_THAT(covered(R"([{"from": 1}])"), HasSubstr("x.json: covered[0]: missing key 'for'"));
  EXPECT_THAT(covered(R"([{"from": 1, "for": 2, "dark": true}])"), HasSubstr("x.json: covered[0].dark: unknown key"));
  EXPECT_THAT(covered(R"({"from": 1, "for": 2})"), HasSubstr("x.json: covered: must be an array"));
}

TEST(Scenario, DarkStretchesDimTheLightsInTimeOrderAndAreCheckedByKey) {
  const Scenario s = ParseScenario(
      WithCamera(R"("procedural": "circle")",
                 R"( "dark": [{"from": 2, "for": 0.5, "level": 0.2}, {"from": 4, "for": 1}],
                     "covered": [{"from": 4.5, "for": 1}],)"),
      "x.json");
  ASSERT_EQ(s.dark.size(), 2U);
  EXPECT_DOUBLE_EQ(s.dark[0].level, 0.2);
  EXPECT_DOUBLE_EQ(s.dark[1].level, 0.1);  // the default
  EXPECT_DOUBLE_EQ(s.LightLevelAt(1.99), 1.0);
  EXPECT_DOUBLE_EQ(s.LightLevelAt(2.0), 0.2);
  EXPECT_DOUBLE_EQ(s.LightLevelAt(2.49), 0.2);
  EXPECT_DOUBLE_EQ(s.LightLevelAt(2.5), 1.0);  // the first frame at the stretch's end is lit
  EXPECT_DOUBLE_EQ(s.LightLevelAt(4.7), 0.1);  // dark and covered may overlap: a covered lens is dark anyway
  EXPECT_TRUE(s.LensCoveredAt(4.7));
  EXPECT_TRUE(ParseScenario(WithCamera(R"("procedural": "circle")"), "x.json").dark.empty());

  const auto dark = [](const std::string& list) {
    return ParseError(WithCamera(R"("procedural": "circle")", R"( "dark": )" + list + ","));
  };
  EXPECT_THAT(dark(R"([{"from": 2, "for": 2}, {"from": 3, "for": 1}])"),
              HasSubstr("x.json: dark[1].from: must not be before the end of dark[0] at 4 s"));
  EXPECT_THAT(dark(R"([{"from": 2, "for": 1, "level": 0}])"), HasSubstr("x.json: dark[0].level: 0 is outside (0, 1]"));
  EXPECT_THAT(dark(R"([{"from": 2, "for": 1, "level": 1.5}])"),
              HasSubstr("x.json: dark[0].level: 1.5 is outside (0, 1]"));
  EXPECT_THAT(dark(R"([{"from": 2, "for": 1, "level": "dim"}])"), HasSubstr("x.json: dark[0].level: must be a number"));
  EXPECT_THAT(dark(R"([{"from": 2, "for": 0}])"), HasSubstr("x.json: dark[0].for: 0 is outside [0.001, 100000]"));
  EXPECT_THAT(dark(R"([{"for": 2}])"), HasSubstr("x.json: dark[0]: missing key 'from'"));
  EXPECT_THAT(dark(R"([{"from": 1, "for": 2, "lvl": 0.5}])"), HasSubstr("x.json: dark[0].lvl: unknown key"));
  EXPECT_THAT(dark(R"({"from": 1, "for": 2})"), HasSubstr("x.json: dark: must be an array"));
}

// A valid scenario whose waypoints camera has `waypoints` (a JSON array) and `camera_keys` besides.
std::string WithWaypoints(const std::string& waypoints, const std::string& camera_keys = "") {
  return R"({"name": "t", "camera": {"procedural": "waypoints", )" + camera_keys + R"("waypoints": )" + waypoints +
         R"(}, "people": []})";
}

constexpr const char* kThreeWaypoints = R"([{"time": 0, "position": [2, 2, 1.4], "yaw_deg": 90, "pitch_deg": -10},
    {"time": 2.5, "position": [3, 2, 1.5], "yaw_deg": 120, "roll_deg": 5},
    {"time": 4, "position": [3, 3, 1.5]}])";

TEST(Scenario, ParsesTheWaypointsCamera) {
  const Scenario s = ParseScenario(WithWaypoints(kThreeWaypoints, R"("fps": 10, "wobble": 0.01, "wobble_seed": 3, )"),
                                   "x.json");
  const ProceduralPathOptions& p = s.camera.procedural;
  EXPECT_EQ(p.motion, ProceduralMotion::kWaypoints);
  ASSERT_EQ(p.waypoints.size(), 3U);
  EXPECT_DOUBLE_EQ(p.waypoints[1].time, 2.5);
  EXPECT_DOUBLE_EQ(p.waypoints[1].roll_deg, 5.0);
  EXPECT_DOUBLE_EQ(p.waypoints[1].pitch_deg, 0.0);   // the default
  EXPECT_DOUBLE_EQ(p.waypoints[2].yaw_deg, 90.0);    // the default
  EXPECT_EQ(p.frames, 41U);                           // 0 to 4 s at 10 Hz
  EXPECT_DOUBLE_EQ(p.wobble, 0.01);
  EXPECT_DOUBLE_EQ(p.wobble_angle_deg, 2.0);          // the default
  EXPECT_EQ(p.wobble_seed, 3U);
  // The first waypoint is the anchor.
  EXPECT_TRUE(s.camera.T_anchor.isApprox(CameraPoseFromYawPitch({2, 2, 1.4}, 90.0, -10.0), 1e-12));
  EXPECT_EQ(CameraPath::Procedural(p).size(), 41U);
}

TEST(Scenario, WaypointKeysOutOfOrderRangeOrPlaceAreNamed) {
  const std::pair<std::string, const char*> cases[] = {
      {WithWaypoints(R"([{"time": 0, "position": [2, 2, 1.4]}, {"time": 2, "position": [3, 2, 1.4]},
                         {"time": 3, "position": [3, 3, 1.4]}, {"time": 3, "position": [2, 3, 1.4]}])"),
       "x.json: camera.waypoints[3].time: must be after waypoints[2].time (3 s), got 3"},
      {WithWaypoints(R"([{"time": 1, "position": [2, 2, 1.4]}, {"time": 2, "position": [3, 2, 1.4]}])"),
       "x.json: camera.waypoints[0].time: must be 0"},
      {WithWaypoints(R"([{"time": 0, "position": [2, 2, 1.4]}])"),
       "x.json: camera.waypoints: needs at least two waypoints, got 1"},
      {WithWaypoints(R"([{"time": 0, "position": [2, 2, 1.4]}, {"time": 2, "position": [3, 2]}])"),
       "x.json: camera.waypoints[1].position: must be an array of 3 numbers"},
      {WithWaypoints(R"([{"time": 0, "position": [2, 2, 1.4], "pitch_deg": 95}, {"time": 2, "position": [3, 2, 1]}])"),
       "x.json: camera.waypoints[0].pitch_deg: 95 is outside [-89, 89]"},
      {WithWaypoints(R"([{"time": 0, "position": [2, 2, 1.4], "yaw": 95}, {"time": 2, "position": [3, 2, 1]}])"),
       "x.json: camera.waypoints[0].yaw: unknown key"},
      {WithWaypoints(R"([{"position": [2, 2, 1.4]}, {"time": 2, "position": [3, 2, 1]}])"),
       "x.json: camera.waypoints[0]: missing key 'time'"},
      {WithWaypoints(kThreeWaypoints, R"("position": [1, 1, 1], )"),
       "x.json: camera.position: not for the waypoints camera: it starts at its first waypoint"},
      {WithWaypoints(kThreeWaypoints, R"("frames": 10, )"), "x.json: camera.frames: not for the waypoints camera"},
      {WithWaypoints(kThreeWaypoints, R"("radius": 1, )"), "x.json: camera.radius: only for the circle camera"},
      {WithWaypoints(kThreeWaypoints, R"("wobble": 0.9, )"), "x.json: camera.wobble: 0.9 is outside [0, 0.5]"},
      {R"({"name": "t", "camera": {"procedural": "waypoints"}})", "x.json: camera: missing key 'waypoints'"},
      {WithCamera(R"("procedural": "circle", "waypoints": [])"),
       "x.json: camera.waypoints: only for the waypoints camera"},
      {WithCamera(R"("procedural": "xyz", "wobble": 0.01)"),
       "x.json: camera.wobble: only for the circle and waypoints cameras"},
      {WithCamera(R"("tum": "fr3_walking_xyz", "waypoints": [])"),
       "x.json: camera.waypoints: only for a procedural waypoints camera"},
  };
  for (const auto& [text, message] : cases) EXPECT_THAT(ParseError(text), HasSubstr(message));
}

// The camera path of a shipped scenario with a procedural camera.
std::vector<CameraFrame> ShippedPath(const std::string& name) {
  const Scenario scenario = LoadScenario(name);
  EXPECT_TRUE(scenario.camera.tum.empty()) << name;
  return CameraPath::Procedural(scenario.camera.procedural).frames();
}

double Distance(const CameraFrame& a, const CameraFrame& b) {
  return (a.T_wc.translation() - b.T_wc.translation()).norm();
}

double Angle(const CameraFrame& a, const CameraFrame& b) {
  return Eigen::AngleAxisd(a.T_wc.linear().transpose() * b.T_wc.linear()).angle();
}

// True when some frame before `last` saw the place from nearly the pose of `frame`.
bool SeenBefore(const std::vector<CameraFrame>& path, std::size_t last, const CameraFrame& frame) {
  return std::any_of(path.begin(), path.begin() + static_cast<std::ptrdiff_t>(last), [&](const CameraFrame& f) {
    return Distance(f, frame) < 0.15 && Angle(f, frame) < 5.0 * std::numbers::pi / 180.0;
  });
}

TEST(Scenario, LoopGoesRoundTwiceInTwoMinutesWithPeopleAtWork) {
  const Scenario loop = LoadScenario("loop");
  const std::vector<CameraFrame> path = ShippedPath("loop");
  EXPECT_GE(path.size(), 3600U);  // at least 2 minutes at 30 Hz
  EXPECT_NEAR(path.back().timestamp - path.front().timestamp, 126.0, 0.1);
  const double seconds_a_turn = loop.camera.procedural.period;
  EXPECT_GE((path.back().timestamp - path.front().timestamp) / seconds_a_turn, 2.0);
  EXPECT_GE(loop.people.size(), 3U);
  // Every pose of the second turn is close to, but not the same as, the pose a turn earlier: the shake moves
  // each of them at most `wobble` along each axis.
  const auto frames_a_turn = static_cast<std::size_t>(std::lround(seconds_a_turn * loop.camera.procedural.fps));
  for (std::size_t i = frames_a_turn; i < path.size(); i += 30) {
    EXPECT_LE(Distance(path[i], path[i - frames_a_turn]), 2.0 * std::sqrt(3.0) * loop.camera.procedural.wobble);
    EXPECT_GT(Distance(path[i], path[i - frames_a_turn]) + Angle(path[i], path[i - frames_a_turn]), 1e-4);
  }
}

TEST(Scenario, KidnapMovesTheCoveredCameraOnAndUncoversItWhereItHasBeen) {
  const Scenario kidnap = LoadScenario("kidnap");
  const std::vector<CameraFrame> path = ShippedPath("kidnap");
  ASSERT_EQ(kidnap.covered.size(), 1U);
  EXPECT_DOUBLE_EQ(kidnap.covered[0].duration, 2.0);
  const auto at = [&](double time) {
    return static_cast<std::size_t>(std::lround(time * kidnap.camera.procedural.fps));
  };
  const CameraFrame& covered = path[at(kidnap.covered[0].from)];
  const CameraFrame& uncovered = path[at(kidnap.covered[0].end())];
  EXPECT_GE(Distance(covered, uncovered), 0.6);
  // Turned further than the image is wide (62.7 degrees): nothing in view at the uncovering was in view before.
  EXPECT_GE(Angle(covered, uncovered), 65.0 * std::numbers::pi / 180.0);
  EXPECT_TRUE(SeenBefore(path, at(kidnap.covered[0].from), uncovered));
  EXPECT_GT(path.size(), at(kidnap.covered[0].end()) + 300);  // 10 s and more to relocalise and go on
}

TEST(Scenario, KidnapUnmappedUncoversTheCameraFacingWhatItHasNotSeenAndBringsItBack) {
  const Scenario kidnap = LoadScenario("kidnap_unmapped");
  const std::vector<CameraFrame> path = ShippedPath("kidnap_unmapped");
  ASSERT_EQ(kidnap.covered.size(), 1U);
  const auto at = [&](double time) {
    return static_cast<std::size_t>(std::lround(time * kidnap.camera.procedural.fps));
  };
  const std::size_t covered = at(kidnap.covered[0].from), uncovered = at(kidnap.covered[0].end());
  // Every view before the cover looked further away than the image is wide (62.7 degrees) from the uncovered one.
  for (std::size_t i = 0; i < covered; ++i) {
    EXPECT_GE(Angle(path[i], path[uncovered]), 65.0 * std::numbers::pi / 180.0) << "frame " << i;
  }
  // Later the camera looks again from where it started.
  EXPECT_TRUE(std::any_of(path.begin() + static_cast<std::ptrdiff_t>(uncovered), path.end(),
                          [&](const CameraFrame& frame) { return SeenBefore(path, 1, frame); }));
}

TEST(Scenario, RevisitPassesAreTwoPathsOverTheSamePlacesAtOtherTimes) {
  const Scenario first = LoadScenario("revisit_a");
  const Scenario second = LoadScenario("revisit_b");
  EXPECT_EQ(first.document.at("office"), second.document.at("office"));
  EXPECT_FALSE(first.people.empty());
  EXPECT_FALSE(second.people.empty());
  const std::vector<CameraFrame> a = ShippedPath("revisit_a");
  const std::vector<CameraFrame> b = ShippedPath("revisit_b");
  EXPECT_LT(a.back().timestamp, b.front().timestamp);
  // The second pass starts where the first has looked, from 0.3 m aside, and never takes a pose of the first.
  const double degree = std::numbers::pi / 180.0;
  EXPECT_TRUE(std::any_of(a.begin(), a.end(), [&](const CameraFrame& frame) {
    return Distance(frame, b.front()) < 0.4 && Angle(frame, b.front()) < 5.0 * degree;
  }));
  for (std::size_t i = 0; i < b.size(); i += 10) {
    EXPECT_TRUE(std::none_of(a.begin(), a.end(), [&](const CameraFrame& frame) {
      return Distance(frame, b[i]) < 0.1 && Angle(frame, b[i]) < 10.0 * degree;
    })) << "revisit_b frame " << i;
  }
}

TEST(Scenario, CustomOfficeLayoutsAreChecked) {
  const Scenario s = ParseScenario(
      Valid("[]",
            R"("office": {"base": "default", "objects": [{"name": "mug", "type": "cup", "position": [3, 3.8]}]},)"),
      "x.json");
  ASSERT_NE(s.office.FindObject("mug"), nullptr);
  EXPECT_NE(s.office.FindObject("tv_1"), nullptr);
  EXPECT_THAT(ParseError(Valid("[]", R"("office": {"objects": [{"name": "m", "type": "mug", "position": [3, 3]}]},)")),
              HasSubstr("office.objects[0].type: unknown object type 'mug'"));
  EXPECT_THAT(ParseError(Valid("[]", R"("office": {"base": "default", "objects": [
                  {"name": "cup_1", "type": "cup", "position": [3, 3]}]},)")),
              HasSubstr("office.objects[0].name: duplicate name 'cup_1'"));
  EXPECT_THAT(ParseError(Valid("[]", R"("office": {"objects": [{"name": "a", "type": "cup", "position": [3, 3]},
                                                               {"name": "a", "type": "cup", "position": [3, 4]}]},)")),
              HasSubstr("office.objects[1].name: duplicate name 'a'"));
  EXPECT_THAT(ParseError(Valid("[]", R"("office": "big",)")), HasSubstr("office: must be \"default\""));
}

TEST(Scenario, WallPanelsReplaceTheDefaultDecoration) {
  const Scenario s = ParseScenario(Valid("[]", R"("office": {"base": "empty", "room": [6, 5, 2.7], "walls": [
      {"type": "poster", "wall": "back", "at": 2, "z": 1.7, "size": [0.6, 0.8], "variant": 3},
      {"type": "door", "wall": "left", "at": 1.2},
      {"type": "whiteboard", "wall": "front", "at": 3}]},)"),
                                   "x.json");
  ASSERT_TRUE(s.office.walls.has_value());
  const std::vector<WallPanel>& walls = *s.office.walls;
  ASSERT_EQ(walls.size(), 3U);
  EXPECT_EQ(walls[0].kind, PanelKind::kPoster);
  EXPECT_EQ(walls[0].wall, Wall::kBack);
  EXPECT_EQ(walls[0].variant, 3);
  EXPECT_DOUBLE_EQ(walls[1].z, 1.05);  // a door stands on the floor
  EXPECT_TRUE(walls[1].size.isApprox(DefaultPanelSize(PanelKind::kDoor)));
  EXPECT_TRUE(walls[2].size.isApprox(Eigen::Vector2d(1.6, 1.0)));
  EXPECT_FALSE(ParseScenario(Valid("[]", R"("office": {"base": "default", "walls": "default"},)"), "x.json")
                   .office.walls.has_value());
  EXPECT_FALSE(ParseScenario(Valid(), "x.json").office.walls.has_value());

  const auto walls_error = [](const std::string& list) {
    return ParseError(Valid("[]", R"("office": {"base": "empty", "room": [6, 5, 2.7], "walls": )" + list + "},"));
  };
  EXPECT_THAT(walls_error(R"([{"type": "poster", "wall": "north", "at": 2}])"),
              HasSubstr("x.json: office.walls[0].wall: unknown wall 'north' (expected front, right, back or left)"));
  EXPECT_THAT(walls_error(R"([{"type": "mirror", "wall": "back", "at": 2}])"),
              HasSubstr("x.json: office.walls[0].type: unknown panel type 'mirror'"));
  EXPECT_THAT(walls_error(R"([{"type": "poster", "wall": "left", "at": 4.8}])"),
              HasSubstr("x.json: office.walls[0].at: a panel 0.7 m wide at 4.8 m does not fit the left wall (0..5 m)"));
  EXPECT_THAT(walls_error(R"([{"type": "poster", "wall": "back", "at": 2, "z": 2.5}])"),
              HasSubstr("x.json: office.walls[0].z: a panel 0.9 m high at 2.5 m does not fit"));
  EXPECT_THAT(walls_error(R"([{"type": "door", "wall": "back", "at": 2, "z": 1}])"),
              HasSubstr("x.json: office.walls[0].z: not for a door: it stands on the floor"));
  EXPECT_THAT(walls_error(R"([{"type": "whiteboard", "wall": "back", "at": 2, "variant": 1}])"),
              HasSubstr("x.json: office.walls[0].variant: only for a poster"));
  EXPECT_THAT(walls_error(R"([{"type": "poster", "wall": "back", "at": 2, "size": [0, 1]}])"),
              HasSubstr("x.json: office.walls[0].size: must be positive"));
  EXPECT_THAT(walls_error(R"("bare")"), HasSubstr("x.json: office.walls: must be \"default\" or an array"));
}

TEST(Scenario, OfficeErrorsNameTheUsersOwnIndexOverTheDefaultBase) {
  EXPECT_THAT(ParseError(Valid("[]", R"("office": {"base": "default", "desks": [
                  {"name": "desk_9", "position": [9, 1]}]},)")),
              HasSubstr("x.json: office.desks[0].position: outside the room"));
  EXPECT_THAT(ParseError(Valid("[]", R"("office": {"base": "default", "shelves": [
                  {"name": "shelf_1", "position": [1, 1]}]},)")),
              HasSubstr("x.json: office.shelves[0].name: duplicate name 'shelf_1' (the base office has it)"));
  EXPECT_THAT(ParseError(Valid("[]", R"("office": {"base": "default", "room": [4, 4, 2.8]},)")),
              HasSubstr("x.json: office.room: desk_2 of the base office"));
}

TEST(Scenario, NamesAreCheckedAgainstTheirListsWithTheKey) {
  EXPECT_THAT(ParseError(Valid(R"([{"name": "a", "start": [1, 2], "actions": [{"action": "dance"}]}])")),
              HasSubstr("x.json: people[0].actions[0].action: unknown action 'dance' (expected walk_to, stop,"));
  EXPECT_THAT(ParseError(R"({"name": "t", "camera": {"procedural": "zigzag", "position": [4, 1, 1.4]}})"),
              HasSubstr("x.json: camera.procedural: unknown camera motion 'zigzag' (expected static, xyz,"));
}

TEST(Scenario, BrokenJsonNamesTheLine) {
  EXPECT_THAT(ParseError("{\n  \"name\": \"t\",\n  \"seed\": ,\n}"), HasSubstr("x.json:3: not valid JSON"));
  // A number beyond double's range is an out_of_range error of nlohmann::json, which carries no position.
  EXPECT_THAT(ParseError("{\n  \"name\": \"t\",\n  \"seed\": 1e400\n}"),
              HasSubstr("x.json:3: not valid JSON: [json.exception.out_of_range.406] number overflow parsing '1e400'"));
  EXPECT_THAT(ParseError(Valid("[]", R"( "frames": 18446744073709551615,)")),
              HasSubstr("x.json: frames: 18446744073709551615 is outside [0, 10000000]"));
}

TEST(Scenario, LoadsUserFilesAndNamesMissingOnes) {
  testing::TempDir temp;
  const auto file = temp / "mine.json";
  std::ofstream(file) << Valid();
  EXPECT_EQ(LoadScenario(file.string()).source, file.string());
  try {
    LoadScenario((temp / "nope.json").string());
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nope.json: no such scenario file"));
    EXPECT_THAT(e.what(), HasSubstr("walking_xyz"));
  }
}

TEST(Scenario, AFolderIsNotTakenForAnEmptyFile) {
  testing::TempDir temp;
  std::filesystem::create_directories(temp / "folder.json");
  try {
    LoadScenario((temp / "folder.json").string());
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("folder.json: is a folder or a special file, not a scenario file"));
  }
}

TEST(Scenario, PrintedTextIsTheShippedFile) {
  const auto text = BuiltinScenarioText("walking_xyz");
  ASSERT_TRUE(text.has_value());
  EXPECT_THAT(std::string(*text), HasSubstr("\"tum\": \"fr3_walking_xyz\""));
  EXPECT_FALSE(BuiltinScenarioText("no_such").has_value());
}

}  // namespace
}  // namespace hoidslam::synth
