#include "hoidslam/eval/loop_recall.h"

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {
namespace {

constexpr double kPeriod = 20.0;  // seconds a lap of the circle takes

// A camera going round a circle of 1 m radius facing outwards, one lap in kPeriod seconds, at 30 Hz from `start`;
// with a `detour`, it spends that many seconds from 25 s on walking 2 m straight out and back before it goes on.
core::Trajectory Circle(double duration, double start = 100.0, double detour = 0.0) {
  core::Trajectory trajectory;
  for (int k = 0; k <= static_cast<int>(std::lround(duration * 30.0)); ++k) {
    const double t = k / 30.0;
    double lap_time = t, radius = 1.0;
    if (detour > 0.0 && t > 25.0) {
      lap_time = t < 25.0 + detour ? 25.0 : t - detour;
      if (t < 25.0 + detour) radius += 2.0 * (1.0 - std::abs(2.0 * (t - 25.0) / detour - 1.0));
    }
    const double angle = 2.0 * std::numbers::pi * lap_time / kPeriod;
    core::Pose T_wc = core::Pose::Identity();
    T_wc.translate(Eigen::Vector3d(radius * std::cos(angle), radius * std::sin(angle), 1.4));
    T_wc.rotate(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(-std::numbers::pi / 2.0, Eigen::Vector3d::UnitY()));
    trajectory.push_back({start + t, T_wc});
  }
  return trajectory;
}

// A camera walking along a straight line: it never comes back.
core::Trajectory Line(double duration, double start = 100.0) {
  core::Trajectory trajectory;
  for (int k = 0; k <= static_cast<int>(std::lround(duration * 30.0)); ++k) {
    core::Pose T_wc = core::Pose::Identity();
    T_wc.translate(Eigen::Vector3d(0.3 * k / 30.0, 0.0, 1.4));
    trajectory.push_back({start + k / 30.0, T_wc});
  }
  return trajectory;
}

// Every 15th pose (a keyframe every half second) as estimated: the truth seen from another world frame, drifting
// `drift` metres a second along x.
core::Trajectory Keyframes(const core::Trajectory& truth, double drift) {
  core::Pose world = core::Pose::Identity();
  world.translate(Eigen::Vector3d(3.0, -2.0, 0.5));
  world.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  core::Trajectory keyframes;
  for (std::size_t k = 0; k < truth.size(); k += 15) {
    core::Pose T_wc = truth[k].T_wc;
    T_wc.pretranslate(Eigen::Vector3d(drift * (truth[k].timestamp - truth.front().timestamp), 0.0, 0.0));
    keyframes.push_back({truth[k].timestamp, world * T_wc});
  }
  return keyframes;
}

// A loop closed at `time` (seconds into the run) onto the place `place` seconds in, with the true relative pose
// moved `error` metres.
RelativePose Loop(const core::Trajectory& truth, double time, double place, double error = 0.0) {
  const auto at = [&](double t) { return truth[static_cast<std::size_t>(std::lround(t * 30.0))]; };
  core::Pose T = at(place).T_wc.inverse() * at(time).T_wc;
  T.pretranslate(Eigen::Vector3d(error, 0.0, 0.0));
  return {at(time).timestamp, at(place).timestamp, T};
}

struct Case {
  std::string name;
  core::Trajectory truth;
  double drift = 0.0;                     // m/s
  std::vector<RelativePose> closures;
  std::size_t events = 0, closed = 0, consistent = 0;
  std::optional<double> recall, precision;
};

class LoopRecallCases : public ::testing::TestWithParam<Case> {};

TEST_P(LoopRecallCases, CountReturnsAndLoopsAsDefined) {
  const Case& c = GetParam();
  const LoopRecall recall = ComputeLoopRecall(c.truth, Keyframes(c.truth, c.drift), c.closures, {}, {});
  EXPECT_EQ(recall.events.size(), c.events);
  EXPECT_EQ(recall.Closed(), c.closed);
  EXPECT_EQ(recall.Consistent(), c.consistent);
  EXPECT_EQ(recall.Recall(), c.recall);
  EXPECT_EQ(recall.Precision(), c.precision);
  EXPECT_EQ(recall.unmatched_keyframes, 0U);
  EXPECT_EQ(recall.unmatched_closures, 0U);
}

// 25 s on the circle: from 18.5 s on (27° of arc and 0.47 m before the start) the camera comes back over the first
// lap's path, one return event.
const core::Trajectory kLap = Circle(25.0);

INSTANTIATE_TEST_SUITE_P(
    LoopRecall, LoopRecallCases,
    ::testing::Values(
        Case{.name = "ALoopClosedOnTheReturnRecallsIt", .truth = kLap, .drift = 0.01,
             .closures = {Loop(kLap, 20.5, 0.5)}, .events = 1, .closed = 1, .consistent = 0, .recall = 1.0,
             .precision = 1.0},
        Case{.name = "AMapThatDidNotDriftIsAlreadyConsistent", .truth = kLap, .drift = 0.0, .closures = {},
             .events = 1, .closed = 0, .consistent = 1, .recall = 1.0, .precision = std::nullopt},
        Case{.name = "ADriftedReturnWithoutALoopIsMissed", .truth = kLap, .drift = 0.01, .closures = {},
             .events = 1, .closed = 0, .consistent = 0, .recall = 0.0, .precision = std::nullopt},
        Case{.name = "AFalseLoopRecallsNothingAndCostsPrecision", .truth = kLap, .drift = 0.01,
             .closures = {Loop(kLap, 21.0, 1.0, 0.3)}, .events = 1, .closed = 0, .consistent = 0, .recall = 0.0,
             .precision = 0.0},
        Case{.name = "NoReturnLeavesRecallUndefined", .truth = Line(25.0), .drift = 0.01, .closures = {},
             .events = 0, .closed = 0, .consistent = 0, .recall = std::nullopt, .precision = std::nullopt},
        Case{.name = "ALoopWithoutAReturnStillCountsForPrecision", .truth = Line(25.0), .drift = 0.01,
             .closures = {Loop(Line(25.0), 20.0, 5.0)}, .events = 0, .closed = 0, .consistent = 0,
             .recall = std::nullopt, .precision = 1.0}),
    [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

TEST(LoopRecall, TheReturnIsJudgedWhereItComesNearestTheEarlierKeyframe) {
  const LoopRecall recall = ComputeLoopRecall(kLap, Keyframes(kLap, 0.01), {}, {}, {});
  ASSERT_EQ(recall.events.size(), 1U);
  const ReturnEvent& event = recall.events[0];
  // From 1.5 s of arc before a full lap (27°, 0.47 m from the start) to the end.
  EXPECT_NEAR(event.start, 118.5, 1e-6);
  EXPECT_NEAR(event.end, 125.0, 1e-6);
  EXPECT_EQ(event.keyframes, 14U);
  EXPECT_NEAR(event.timestamp - event.place_timestamp, kPeriod, 1e-6);
  EXPECT_NEAR(event.true_distance, 0.0, 1e-9);
  EXPECT_NEAR(event.position_error, 0.01 * kPeriod, 1e-6);  // the drift of one lap
}

// The keyframes of `truth` (Keyframes, without drift) but those made in [from, to] seconds into the run.
core::Trajectory KeyframesBut(const core::Trajectory& truth, double from, double to) {
  core::Trajectory keyframes;
  for (const core::StampedPose& pose : Keyframes(truth, 0.0)) {
    const double t = pose.timestamp - truth.front().timestamp;
    if (t < from || t > to) keyframes.push_back(pose);
  }
  return keyframes;
}

TEST(LoopRecall, KeyframesOfOnePassAreNotReturnsAndSeparateReturnsAreSeparateEvents) {
  // Three quarters of a lap: a camera that passes places and goes on is not returning to them.
  EXPECT_TRUE(ComputeLoopRecall(Circle(15.0), Keyframes(Circle(15.0), 0.01), {}, {}, {}).events.empty());
  // Two laps and a quarter: from the end of the first lap on every keyframe returns, one event.
  const core::Trajectory laps = Circle(2.25 * kPeriod);
  EXPECT_EQ(ComputeLoopRecall(laps, Keyframes(laps, 0.0), {}, {}, {}).events.size(), 1U);
  // Still one when no keyframe was made from 25 s to 40 s: a system that finds its map makes few keyframes on a
  // return, and the path, not the keyframes, says whether the camera went away.
  EXPECT_EQ(ComputeLoopRecall(laps, KeyframesBut(laps, 25.1, 39.9), {}, {}, {}).events.size(), 1U);
  // A camera that walks 2 m out and back (for 10 s, more than 3 s of it over 0.5 m away) returns twice.
  const core::Trajectory detour = Circle(50.0, 100.0, 10.0);
  const LoopRecall recall = ComputeLoopRecall(detour, Keyframes(detour, 0.0), {}, {}, {});
  ASSERT_EQ(recall.events.size(), 2U);
  EXPECT_LT(recall.events[0].end, 128.0);
  EXPECT_GT(recall.events[1].start, 132.0);
  EXPECT_EQ(recall.Consistent(), 2U);
}

TEST(LoopRecall, ALoopClosedSoonAfterTheReturnRecallsItOneLaterDoesNot) {
  // Keyframes until 20 s: the event is [18.5 s, 20 s]; close_within is 3 s.
  const core::Trajectory longer = Circle(29.0);
  const core::Trajectory keyframes = Keyframes(Circle(20.0), 0.01);
  const auto closed = [&](const RelativePose& loop) {
    const LoopRecall recall = ComputeLoopRecall(longer, keyframes, std::vector{loop}, {}, {});
    EXPECT_EQ(recall.confirmed, 1U);
    return recall.events.at(0).closed_by.has_value();
  };
  EXPECT_TRUE(closed(Loop(longer, 22.5, 2.5)));
  EXPECT_FALSE(closed(Loop(longer, 23.5, 3.5)));
  EXPECT_FALSE(closed(Loop(longer, 18.0, 0.5)));  // before the return: not this event's loop
}

TEST(LoopRecall, GroundTruthIsMatchedByTimestampNotByLine) {
  // The ground truth at 100 Hz with a gap where one keyframe lies: that keyframe takes no part, the others match.
  core::Trajectory truth;
  for (const core::StampedPose& pose : Circle(25.0)) {
    if (std::abs(pose.timestamp - 110.0) > 0.05) truth.push_back(pose);
  }
  const LoopRecall recall = ComputeLoopRecall(truth, Keyframes(Circle(25.0), 0.0), {}, {}, {});
  EXPECT_EQ(recall.unmatched_keyframes, 1U);
  EXPECT_EQ(recall.events.size(), 1U);
  EXPECT_EQ(recall.Consistent(), 1U);
  // A loop whose end has no ground truth is not judged.
  const core::Trajectory lap = Circle(25.0);
  const LoopRecall unmatched =
      ComputeLoopRecall(truth, Keyframes(lap, 0.0), std::vector{Loop(lap, 20.0, 10.0)}, {}, {});
  EXPECT_EQ(unmatched.unmatched_closures, 1U);
  EXPECT_EQ(unmatched.Precision(), std::nullopt);
}

TEST(LoopRecall, JsonSaysUndefinedAsNullAndKeepsTheOptions) {
  const nlohmann::json none =
      LoopRecallToJson(ComputeLoopRecall(Line(25.0), Keyframes(Line(25.0), 0.0), {}, {}, {}), {});
  EXPECT_EQ(none["events"], 0);
  EXPECT_TRUE(none["recall"].is_null());
  EXPECT_TRUE(none["precision"].is_null());
  EXPECT_EQ(none["options"]["min_separation_s"], 10.0);
  EXPECT_EQ(none["options"]["max_return_distance_m"], 0.5);
  EXPECT_EQ(none["options"]["max_consistent_position_error_m"], 0.02);
  EXPECT_EQ(none["options"]["closure_max_position_error_m"], 0.10);

  const nlohmann::json closed =
      LoopRecallToJson(ComputeLoopRecall(kLap, Keyframes(kLap, 0.01), std::vector{Loop(kLap, 20.5, 0.5)}, {}, {}), {});
  EXPECT_EQ(closed["events"], 1);
  EXPECT_EQ(closed["recalled"], 1);
  EXPECT_EQ(closed["closed"], 1);
  EXPECT_EQ(closed["consistent"], 0);
  EXPECT_EQ(closed["recall"], 1.0);
  EXPECT_EQ(closed["closures"], 1);
  EXPECT_EQ(closed["confirmed"], 1);
  EXPECT_EQ(closed["precision"], 1.0);
  EXPECT_NEAR(closed["returns"][0]["closed_by"].get<double>(), 120.5, 1e-9);
}

TEST(LoopRecallOptions, CheckNamesTheParameter) {
  const auto message = [](const LoopRecallOptions& options) {
    try {
      options.Check();
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message({}), "");
  LoopRecallOptions options;
  options.min_separation = -1.0;
  EXPECT_NE(message(options).find("loop_recall.min_separation"), std::string::npos);
  options = {};
  options.max_return_distance = 0.0;
  EXPECT_NE(message(options).find("loop_recall.max_return_distance"), std::string::npos);
  options = {};
  options.max_return_angle_deg = 200.0;
  EXPECT_NE(message(options).find("loop_recall.max_return_angle_deg"), std::string::npos);
  options = {};
  options.max_consistent_position_error = std::nan("");
  EXPECT_NE(message(options).find("loop_recall.max_consistent_position_error"), std::string::npos);
  options = {};
  options.closure.max_rotation_error_deg = 0.0;
  EXPECT_NE(message(options).find("loop_recall.closure.max_rotation_error_deg"), std::string::npos);
  EXPECT_THROW(ComputeLoopRecall(kLap, kLap, {}, {}, options), core::InputError);
}

}  // namespace
}  // namespace hoidslam::eval
