#include "hoidslam/synth/camera_path.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/error.h"
#include "support/geometry.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::synth {
namespace {

using ::hoidslam::testing::PoseFromAxisAngle;
using ::hoidslam::testing::WriteText;

void ExpectPoseNear(const core::Pose& a, const core::Pose& b, double tolerance) {
  EXPECT_LT((a.translation() - b.translation()).norm(), tolerance);
  EXPECT_LT((a.linear() - b.linear()).norm(), tolerance);
}

std::string Message(const std::function<void()>& action) {
  try {
    action();
  } catch (const core::InputError& error) {
    return error.what();
  }
  return "";
}


TEST(CameraPath, InterpolationIsExactOnKnotsAndHalfwayBetween) {
  const core::Trajectory trajectory = {{10.0, PoseFromAxisAngle({0, 0, 0}, {0, 0, 0})},
                                       {11.0, PoseFromAxisAngle({0, 0, 0.4}, {1, 2, 0})},
                                       {13.0, PoseFromAxisAngle({0.4, 0, 0}, {1, 2, 3})}};
  for (const core::StampedPose& knot : trajectory) ExpectPoseNear(InterpolatePose(trajectory, knot.timestamp), knot.T_wc, 1e-12);
  const core::Pose half = InterpolatePose(trajectory, 10.5);
  EXPECT_LT((half.translation() - Eigen::Vector3d(0.5, 1.0, 0.0)).norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(half.linear()).angle(), 0.2, 1e-12);
  const core::Pose quarter = InterpolatePose(trajectory, 11.5);
  EXPECT_LT((quarter.translation() - Eigen::Vector3d(1.0, 2.0, 0.75)).norm(), 1e-12);
  // Outside the span: clamped to the ends.
  ExpectPoseNear(InterpolatePose(trajectory, 9.0), trajectory.front().T_wc, 1e-12);
  ExpectPoseNear(InterpolatePose(trajectory, 14.0), trajectory.back().T_wc, 1e-12);
}

class TumFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    // Ground truth from t = 100.0 to 100.5 at 10 Hz: moving along x, turning about z.
    std::string truth = "# timestamp tx ty tz qx qy qz qw\n";
    for (int i = 0; i <= 5; ++i) {
      const double angle = 0.1 * i;
      truth += std::to_string(100.0 + 0.1 * i) + " " + std::to_string(0.2 * i) + " -3.0 1.4 0 0 " +
               std::to_string(std::sin(angle / 2)) + " " + std::to_string(std::cos(angle / 2)) + "\n";
    }
    WriteText(dir_ / "groundtruth.txt", truth);
    // Frames at 30 Hz from before the ground truth starts to after it ends.
    std::string associations;
    for (int i = 0; i < 20; ++i) {
      const double t = 99.95 + i / 30.0;
      associations += std::to_string(t) + " rgb/" + std::to_string(t) + ".png " + std::to_string(t + 0.00002) +
                      " depth/" + std::to_string(t) + ".png\n";
    }
    WriteText(dir_ / "associations.txt", associations);
  }
  testing::TempDir dir_;
};

TEST_F(TumFiles, ReanchorsTheFirstPoseAndKeepsRelativeMotion) {
  const core::Pose anchor = CameraPoseFromYawPitch({1.0, 2.0, 1.5}, 30.0, -10.0);
  const CameraPath path = CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "associations.txt", anchor);
  // Frames before 100.0 and after 100.5 are dropped: 99.95 + i/30 within [100, 100.5] for i = 2..16.
  ASSERT_EQ(path.size(), 15U);
  EXPECT_NEAR(path.frames().front().timestamp, 99.95 + 2.0 / 30.0, 1e-6);
  EXPECT_NEAR(path.frames().front().depth_timestamp - path.frames().front().timestamp, 0.00002, 1e-6);
  ExpectPoseNear(path.frames().front().T_wc, anchor, 1e-12);

  const core::Trajectory truth = [&] {
    core::Trajectory t;
    for (int i = 0; i <= 5; ++i) {
      t.push_back({100.0 + 0.1 * i, PoseFromAxisAngle({0, 0, 0.1 * i}, {0.2 * i, -3.0, 1.4})});
    }
    return t;
  }();
  const core::Pose first_tum = InterpolatePose(truth, path.frames().front().timestamp);
  for (const CameraFrame& frame : path.frames()) {
    const core::Pose relative_synth = path.frames().front().T_wc.inverse() * frame.T_wc;
    const core::Pose relative_tum = first_tum.inverse() * InterpolatePose(truth, frame.timestamp);
    ExpectPoseNear(relative_synth, relative_tum, 1e-5);  // the file holds 6 decimals
  }
  EXPECT_EQ(path.Trajectory().size(), path.size());

  const CameraPath cut = CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "associations.txt", anchor, 4);
  EXPECT_EQ(cut.size(), 4U);
}

TEST_F(TumFiles, BadFilesNameTheFileAndLine) {
  const core::Pose anchor = core::Pose::Identity();
  EXPECT_NE(Message([&] { CameraPath::FromTum(dir_ / "missing.txt", dir_ / "associations.txt", anchor); })
                .find("missing.txt"),
            std::string::npos);
  EXPECT_NE(Message([&] { CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "nope.txt", anchor); }).find("nope.txt"),
            std::string::npos);
  WriteText(dir_ / "short.txt", "100.0 rgb/a.png 100.0 depth/a.png\n100.1 rgb/b.png\n");
  EXPECT_NE(Message([&] { CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "short.txt", anchor); })
                .find("short.txt:2:"),
            std::string::npos);
  WriteText(dir_ / "text.txt", "100.0 rgb/a.png 100.0 depth/a.png\n100.1 rgb/b.png one depth/b.png\n");
  EXPECT_NE(Message([&] { CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "text.txt", anchor); })
                .find("text.txt:2:"),
            std::string::npos);
  WriteText(dir_ / "later.txt", "200.0 rgb/a.png 200.0 depth/a.png\n");
  EXPECT_NE(Message([&] { CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "later.txt", anchor); })
                .find("no frame falls within"),
            std::string::npos);
}

TEST_F(TumFiles, LinesOutOfOrderAreTakenInTimeOrder) {
  WriteText(dir_ / "backwards.txt", "100.2 rgb/a.png 100.2 depth/a.png\n100.1 rgb/b.png 100.1 depth/b.png\n");
  const CameraPath path = CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "backwards.txt", core::Pose::Identity());
  ASSERT_EQ(path.size(), 2U);
  EXPECT_DOUBLE_EQ(path.frames()[0].timestamp, 100.1);
  EXPECT_DOUBLE_EQ(path.frames()[1].timestamp, 100.2);
}

// Frames are written to files named by StampText: two frames whose stamps print alike would write one file.
TEST_F(TumFiles, FramesThatWouldShareAFileNameTheirLines) {
  const core::Pose anchor = core::Pose::Identity();
  // Two colour images paired with one depth image.
  WriteText(dir_ / "shared_depth.txt", "100.0 rgb/a.png 100.0 depth/a.png\n"
                                       "100.1 rgb/b.png 100.1 depth/b.png\n"
                                       "100.2 rgb/c.png 100.1 depth/b.png\n");
  const std::string shared =
      Message([&] { CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "shared_depth.txt", anchor); });
  EXPECT_NE(shared.find("shared_depth.txt:3: the depth timestamp 100.100000 is the same as on line 2"),
            std::string::npos)
      << shared;
  // Two colour times that differ below a microsecond.
  WriteText(dir_ / "close_rgb.txt", "100.0000001 rgb/a.png 100.0 depth/a.png\n"
                                    "100.0000002 rgb/b.png 100.1 depth/b.png\n");
  const std::string close =
      Message([&] { CameraPath::FromTum(dir_ / "groundtruth.txt", dir_ / "close_rgb.txt", anchor); });
  EXPECT_NE(close.find("close_rgb.txt:2: the RGB timestamp 100.000000 is the same as on line 1"), std::string::npos)
      << close;
}

TEST(CameraPath, ProceduralFramesTooFastForTheStampsAreAnError) {
  ProceduralPathOptions options;
  options.frames = 3;
  options.fps = 30.0;
  EXPECT_EQ(CameraPath::Procedural(options).size(), 3U);
  options.fps = 4e6;  // 0.25 microseconds apart
  EXPECT_NE(Message([&] { CameraPath::Procedural(options); }).find("parameter camera.fps"), std::string::npos);
}

TEST(CameraPath, LerpPoseIsExactAtItsEnds) {
  const core::Pose a = PoseFromAxisAngle(0.3 * Eigen::Vector3d(1, 1, 0).normalized(), {1, 2, 3});
  const core::Pose b = PoseFromAxisAngle(1.1 * Eigen::Vector3d(0, 1, 1).normalized(), {-1, 0, 2});
  EXPECT_TRUE(LerpPose(a, b, 0.0).isApprox(a, 0.0));
  EXPECT_TRUE(LerpPose(a, b, 1.0).isApprox(b, 0.0));
  const core::Pose half = LerpPose(a, b, 0.5);
  EXPECT_LT((half.translation() - Eigen::Vector3d(0, 1, 2.5)).norm(), 1e-12);
  // Halfway in rotation: as far from a as from b.
  const double from_a = Eigen::AngleAxisd(a.linear().transpose() * half.linear()).angle();
  const double from_b = Eigen::AngleAxisd(half.linear().transpose() * b.linear()).angle();
  EXPECT_NEAR(from_a, from_b, 1e-12);
  EXPECT_GT(from_a, 0.1);
}

TEST(CameraPath, RealWalkingXyzPathHasTheRealTimingAndSpeed) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(groundtruth, "data/tum/groundtruth/fr3_walking_xyz.txt");
  HOIDSLAM_SHARED_PATH_OR_SKIP(associations, "data/tum/associations/fr3_walking_xyz.txt");
  const core::Pose anchor = CameraPoseFromYawPitch({1.0, 3.0, 1.4}, 0.0, -15.0);
  const CameraPath path = CameraPath::FromTum(groundtruth, associations, anchor);
  EXPECT_GT(path.size(), 800U);
  EXPECT_LE(path.size(), 827U);  // the associations file's frames, minus any outside the ground truth
  const double duration = path.frames().back().timestamp - path.frames().front().timestamp;
  EXPECT_NEAR(duration, 28.0, 2.0);
  double length = 0.0;
  double largest_step = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double step = (path.frames()[i].T_wc.translation() - path.frames()[i - 1].T_wc.translation()).norm();
    length += step;
    largest_step = std::max(largest_step, step);
  }
  // A hand-held camera swept along x, y, z: a few metres in all, at most a few centimetres a frame.
  EXPECT_GT(length / duration, 0.05);
  EXPECT_LT(length / duration, 1.0);
  EXPECT_LT(largest_step, 0.1);
  // It stays near its start: the desks remain in view.
  for (const CameraFrame& frame : path.frames()) {
    EXPECT_LT((frame.T_wc.translation() - anchor.translation()).norm(), 1.0);
  }
}

TEST(CameraPath, ProceduralPathsStartAtTheAnchorAndMoveAsNamed) {
  ProceduralPathOptions options;
  options.T_anchor = CameraPoseFromYawPitch({2.0, 1.0, 1.3}, 45.0, -10.0);
  options.frames = 90;
  options.fps = 30.0;
  options.start_time = 5.0;
  for (const ProceduralMotion motion : {ProceduralMotion::kStatic, ProceduralMotion::kXyz,
                                       ProceduralMotion::kHalfsphere, ProceduralMotion::kRpy,
                                       ProceduralMotion::kCircle}) {
    options.motion = motion;
    EXPECT_EQ(ParseProceduralMotion(ToString(motion), "camera.motion"), motion);
    const CameraPath path = CameraPath::Procedural(options);
    ASSERT_EQ(path.size(), 90U);
    EXPECT_DOUBLE_EQ(path.frames()[0].timestamp, 5.0);
    EXPECT_NEAR(path.frames()[30].timestamp, 6.0, 1e-12);
    ExpectPoseNear(path.frames().front().T_wc, options.T_anchor, 1e-12);
    double moved = 0.0;
    double turned = 0.0;
    for (const CameraFrame& frame : path.frames()) {
      const core::Pose relative = options.T_anchor.inverse() * frame.T_wc;
      moved = std::max(moved, relative.translation().norm());
      turned = std::max(turned, Eigen::AngleAxisd(relative.linear()).angle());
      if (motion == ProceduralMotion::kHalfsphere) {
        // The pivot stays at the image centre.
        const Eigen::Vector3d pivot_w = options.T_anchor * Eigen::Vector3d(0, 0, options.pivot_distance);
        const Eigen::Vector3d pivot_c = frame.T_wc.inverse() * pivot_w;
        EXPECT_NEAR(pivot_c.x(), 0.0, 1e-9);
        EXPECT_NEAR(pivot_c.y(), 0.0, 1e-9);
      }
    }
    const bool circle = motion == ProceduralMotion::kCircle;
    EXPECT_EQ(moved > 0.01, motion == ProceduralMotion::kXyz || motion == ProceduralMotion::kHalfsphere || circle)
        << ToString(motion);
    EXPECT_EQ(turned > 0.01, motion == ProceduralMotion::kRpy || motion == ProceduralMotion::kHalfsphere || circle)
        << ToString(motion);
  }
  EXPECT_NE(Message([] { ParseProceduralMotion("spin", "camera.motion"); }).find("camera.motion"), std::string::npos);
  options.fps = 0.0;
  EXPECT_NE(Message([&] { CameraPath::Procedural(options); }).find("camera.fps"), std::string::npos);
}

// Two turns of 10 s at 10 Hz round a circle of 0.6 m, starting at (4.0, 2.5, 1.4) looking along +y, 10 degrees down.
ProceduralPathOptions TwoTurns(double wobble, double wobble_angle_deg, std::uint64_t wobble_seed = 1) {
  ProceduralPathOptions options;
  options.motion = ProceduralMotion::kCircle;
  options.T_anchor = CameraPoseFromYawPitch({4.0, 2.5, 1.4}, 90.0, -10.0);
  options.radius = 0.6;
  options.period = 10.0;
  options.fps = 10.0;
  options.frames = 200;
  options.wobble = wobble;
  options.wobble_angle_deg = wobble_angle_deg;
  options.wobble_seed = wobble_seed;
  return options;
}

// Heading of the camera's view on the level, radians (0 = +x, pi/2 = +y).
double Heading(const core::Pose& T_wc) {
  const Eigen::Vector3d forward = T_wc.linear().col(2);
  return std::atan2(forward.y(), forward.x());
}

TEST(CameraPath, CircleGoesRoundTheCentreBehindTheFirstPoseFacingOutwards) {
  const CameraPath path = CameraPath::Procedural(TwoTurns(0.0, 0.0));
  ASSERT_EQ(path.size(), 200U);
  const Eigen::Vector2d centre(4.0, 1.9);
  double turned = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const core::Pose& T_wc = path.frames()[i].T_wc;
    const Eigen::Vector2d outwards = T_wc.translation().head<2>() - centre;
    EXPECT_NEAR(outwards.norm(), 0.6, 1e-9);
    EXPECT_NEAR(T_wc.translation().z(), 1.4, 1e-9);
    EXPECT_NEAR(Heading(T_wc), std::atan2(outwards.y(), outwards.x()), 1e-9);
    EXPECT_NEAR(T_wc.linear().col(2).z(), -std::sin(10.0 * std::numbers::pi / 180.0), 1e-9);  // pitch kept
    EXPECT_NEAR(T_wc.linear().col(0).z(), 0.0, 1e-9);                                       // level horizon
    if (i > 0) {
      const double step = std::remainder(Heading(T_wc) - Heading(path.frames()[i - 1].T_wc), 2.0 * std::numbers::pi);
      EXPECT_NEAR(step, 2.0 * std::numbers::pi / 100.0, 1e-9);  // counter-clockwise, a turn in 100 frames
      turned += step;
    }
  }
  EXPECT_NEAR(turned, 2.0 * std::numbers::pi * 199.0 / 100.0, 1e-6);
  ExpectPoseNear(path.frames()[100].T_wc, path.frames()[0].T_wc, 1e-9);  // without a shake, turns repeat exactly
}

TEST(CameraPath, CircleShakeIsSmallSmoothSeededAndMakesEveryTurnDiffer) {
  const double wobble = 0.03;
  const double wobble_angle = 2.0 * std::numbers::pi / 180.0;
  const CameraPath plain = CameraPath::Procedural(TwoTurns(0.0, 0.0));
  const CameraPath shaken = CameraPath::Procedural(TwoTurns(wobble, 2.0));
  const CameraPath again = CameraPath::Procedural(TwoTurns(wobble, 2.0));
  const CameraPath other_seed = CameraPath::Procedural(TwoTurns(wobble, 2.0, 2));
  double largest_shift = 0.0;
  double largest_tilt = 0.0;
  double smallest_turn_difference = 1.0;
  double largest_turn_difference = 0.0;
  double largest_seed_difference = 0.0;
  for (std::size_t i = 0; i < plain.size(); ++i) {
    const core::Pose shake = plain.frames()[i].T_wc.inverse() * shaken.frames()[i].T_wc;
    EXPECT_LE(shake.translation().cwiseAbs().maxCoeff(), wobble + 1e-12);
    EXPECT_LE(Eigen::AngleAxisd(shake.linear()).angle(), 3.0 * wobble_angle);
    largest_shift = std::max(largest_shift, shake.translation().norm());
    largest_tilt = std::max(largest_tilt, Eigen::AngleAxisd(shake.linear()).angle());
    EXPECT_TRUE(again.frames()[i].T_wc.isApprox(shaken.frames()[i].T_wc, 0.0));
    largest_seed_difference = std::max(
        largest_seed_difference,
        (other_seed.frames()[i].T_wc.translation() - shaken.frames()[i].T_wc.translation()).norm());
    if (i > 0) {  // smooth: a sway of at most 0.5 Hz moves at most 16 mm in 0.1 s (noise would move up to 0.1 m)
      const core::Pose before = plain.frames()[i - 1].T_wc.inverse() * shaken.frames()[i - 1].T_wc;
      EXPECT_LT((shake.translation() - before.translation()).norm(), 0.02);
    }
    if (i >= 100) {  // the same phase of the first turn: close, but never the same pose
      const core::Pose& first = shaken.frames()[i - 100].T_wc;
      const core::Pose& second = shaken.frames()[i].T_wc;
      const double difference = std::max((second.translation() - first.translation()).norm(),
                                         Eigen::AngleAxisd(first.linear().transpose() * second.linear()).angle());
      smallest_turn_difference = std::min(smallest_turn_difference, difference);
      largest_turn_difference = std::max(largest_turn_difference, difference);
    }
  }
  // The shake uses much of its bounds, and it differs from one turn to the next by millimetres to centimetres.
  EXPECT_GT(largest_shift, 0.3 * wobble);
  EXPECT_GT(largest_tilt, 0.3 * wobble_angle);
  EXPECT_GT(smallest_turn_difference, 1e-4);
  EXPECT_GT(largest_turn_difference, 0.01);
  EXPECT_LT(largest_turn_difference, 2.0 * std::sqrt(3.0) * wobble + 1e-9);
  EXPECT_GT(largest_seed_difference, 0.01);
}

TEST(CameraPath, CircleOptionsOutOfRangeNameTheirKey) {
  ProceduralPathOptions options = TwoTurns(0.03, 2.0);
  options.radius = 0.0;
  EXPECT_NE(Message([&] { CameraPath::Procedural(options); }).find("camera.radius"), std::string::npos);
  options = TwoTurns(0.6, 2.0);
  EXPECT_NE(Message([&] { CameraPath::Procedural(options); }).find("camera.wobble"), std::string::npos);
  options = TwoTurns(0.03, 11.0);
  EXPECT_NE(Message([&] { CameraPath::Procedural(options); }).find("camera.wobble_angle_deg"), std::string::npos);
  options = TwoTurns(0.03, 2.0);
  options.T_anchor = core::Pose::Identity();  // looks straight up: no level direction to turn about
  EXPECT_NE(Message([&] { CameraPath::Procedural(options); }).find("camera.pitch_deg"), std::string::npos);
}

// Four waypoints at uneven times: a walk along x, a turn on the spot through +-180 degrees of yaw, a climb with
// pitch and roll.
std::vector<CameraWaypoint> FourWaypoints() {
  return {{0.0, {1.0, 2.0, 1.4}, 170.0, -10.0, 0.0},
          {1.5, {2.0, 2.2, 1.4}, -160.0, -5.0, 10.0},  // 30 degrees on from 170, the shorter way round
          {2.5, {2.5, 2.2, 1.5}, -120.0, 5.0, -20.0},
          {4.0, {2.5, 3.0, 1.6}, -100.0, 0.0, 0.0}};
}

ProceduralPathOptions WaypointOptions(std::vector<CameraWaypoint> waypoints, double fps) {
  ProceduralPathOptions options;
  options.motion = ProceduralMotion::kWaypoints;
  options.fps = fps;
  options.waypoints = std::move(waypoints);
  options.frames = WaypointFrameCount(options.waypoints, fps);
  options.wobble = 0.0;
  options.wobble_angle_deg = 0.0;
  return options;
}

TEST(CameraPath, WaypointsArePassedExactlyAtTheirTimes) {
  const std::vector<CameraWaypoint> waypoints = FourWaypoints();
  const CameraPath path = CameraPath::Procedural(WaypointOptions(waypoints, 10.0));
  ASSERT_EQ(path.size(), 41U);  // 0 to 4 s at 10 Hz, both ends included
  for (const CameraWaypoint& w : waypoints) {
    const core::Pose expected = CameraPoseFromYawPitchRoll(w.position, w.yaw_deg, w.pitch_deg, w.roll_deg);
    const CameraFrame& frame = path.frames()[static_cast<std::size_t>(std::lround(w.time * 10.0))];
    EXPECT_TRUE(frame.T_wc.translation() == w.position) << w.time;  // to the bit
    ExpectPoseNear(frame.T_wc, expected, 1e-12);
  }
  // Roll turns the image's right side down: the camera's x axis dips.
  const core::Pose rolled = CameraPoseFromYawPitchRoll({0, 0, 1}, 90.0, 0.0, 30.0);
  EXPECT_NEAR(rolled.linear().col(0).z(), -0.5, 1e-12);
  EXPECT_LT((rolled.linear().col(2) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  // Before the first and after the last waypoint, the path holds still.
  const WaypointCurve curve(waypoints);
  ExpectPoseNear(curve.At(-1.0), path.frames().front().T_wc, 1e-12);
  ExpectPoseNear(curve.At(9.0), path.frames().back().T_wc, 1e-12);
}

TEST(CameraPath, WaypointPathHasAContinuousVelocityAndNoOvershoot) {
  const std::vector<CameraWaypoint> waypoints = FourWaypoints();
  const WaypointCurve curve(waypoints);
  // Velocity (of position, and of the rotation) by central differences just before and just after each
  // waypoint: equal as the step shrinks (C1), and zero at both ends (it starts and ends at rest).
  const auto velocity = [&](double t, double h) {
    const core::Pose a = curve.At(t - h);
    const core::Pose b = curve.At(t + h);
    Eigen::Matrix<double, 6, 1> v;
    v.head<3>() = (b.translation() - a.translation()) / (2.0 * h);
    const Eigen::AngleAxisd turn(a.linear().transpose() * b.linear());
    v.tail<3>() = a.linear() * turn.axis() * turn.angle() / (2.0 * h);
    return v;
  };
  for (std::size_t k = 1; k + 1 < waypoints.size(); ++k) {
    const double t = waypoints[k].time;
    const double jump_coarse = (velocity(t - 1e-3, 1e-4) - velocity(t + 1e-3, 1e-4)).norm();
    const double jump_fine = (velocity(t - 1e-5, 1e-6) - velocity(t + 1e-5, 1e-6)).norm();
    EXPECT_LT(jump_fine, 1e-3) << t;
    EXPECT_LT(jump_fine, 0.1 * jump_coarse + 1e-6) << t;
    EXPECT_GT(velocity(t, 1e-5).norm(), 0.01) << t;  // moving through (not stopping at) the middle waypoints
  }
  EXPECT_LT(velocity(1e-6, 1e-7).head<3>().norm(), 1e-3);
  EXPECT_LT(velocity(4.0 - 1e-6, 1e-7).head<3>().norm(), 1e-3);
  // Between two waypoints each value stays between theirs: x never passes 2.5, z never drops below 1.4.
  for (double t = 0.0; t <= 4.0; t += 0.01) {
    const Eigen::Vector3d p = curve.At(t).translation();
    EXPECT_LE(p.x(), 2.5 + 1e-12);
    EXPECT_GE(p.z(), 1.4 - 1e-12);
    EXPECT_LE(p.z(), 1.6 + 1e-12);
  }
  // The yaw goes from 170 to 200 degrees the short way: the view never swings through 0.
  for (double t = 0.0; t <= 1.5; t += 0.01) EXPECT_LT(curve.At(t).linear().col(2).x(), -0.5);
}

TEST(CameraPath, WaypointShakeStartsAtTheFirstWaypointAndStaysWithinItsBounds) {
  ProceduralPathOptions options = WaypointOptions(FourWaypoints(), 30.0);
  const CameraPath plain = CameraPath::Procedural(options);
  options.wobble = 0.02;
  options.wobble_angle_deg = 1.0;
  options.wobble_seed = 5;
  const CameraPath shaken = CameraPath::Procedural(options);
  ExpectPoseNear(shaken.frames().front().T_wc, plain.frames().front().T_wc, 1e-12);
  double largest = 0.0;
  for (std::size_t i = 0; i < plain.size(); ++i) {
    const core::Pose shake = plain.frames()[i].T_wc.inverse() * shaken.frames()[i].T_wc;
    EXPECT_LE(shake.translation().cwiseAbs().maxCoeff(), 0.02 + 1e-12);
    largest = std::max(largest, shake.translation().norm());
  }
  EXPECT_GT(largest, 0.001);
}

TEST(CameraPath, WaypointOptionsOutOfOrderOrRangeNameTheirKey) {
  const auto message = [](std::vector<CameraWaypoint> waypoints, std::size_t frames = 0) {
    ProceduralPathOptions options = WaypointOptions(std::move(waypoints), 10.0);
    if (frames > 0) options.frames = frames;
    return Message([&] { CameraPath::Procedural(options); });
  };
  std::vector<CameraWaypoint> w = FourWaypoints();
  w[2].time = 1.5;
  EXPECT_NE(message(w).find("camera.waypoints[2].time: must be after waypoints[1].time (1.5 s)"), std::string::npos);
  w = FourWaypoints();
  w[0].time = 0.5;
  EXPECT_NE(message(w).find("camera.waypoints[0].time: must be 0"), std::string::npos);
  w = FourWaypoints();
  w[3].pitch_deg = 90.0;
  EXPECT_NE(message(w).find("camera.waypoints[3].pitch_deg"), std::string::npos);
  EXPECT_NE(message({FourWaypoints()[0]}).find("camera.waypoints: needs at least two waypoints"), std::string::npos);
  EXPECT_NE(message(FourWaypoints(), 42).find("camera.frames: 42 frames at 10 fps run past the last waypoint"),
            std::string::npos);
  ProceduralPathOptions options = WaypointOptions(FourWaypoints(), 10.0);
  options.wobble = 0.7;
  EXPECT_NE(Message([&] { CameraPath::Procedural(options); }).find("camera.wobble"), std::string::npos);
}

TEST(CameraPath, PoseHelpersFollowTheOpticalFrameConvention) {
  const core::Pose level = CameraPoseFromYawPitch({0, 0, 1}, 0.0, 0.0);
  EXPECT_LT((level.linear().col(2) - Eigen::Vector3d::UnitX()).norm(), 1e-12);   // looks along +x
  EXPECT_LT((level.linear().col(0) + Eigen::Vector3d::UnitY()).norm(), 1e-12);   // image right is -y
  EXPECT_LT((level.linear().col(1) + Eigen::Vector3d::UnitZ()).norm(), 1e-12);   // image down is -z
  EXPECT_NEAR(level.linear().determinant(), 1.0, 1e-12);
  const core::Pose down = CameraPoseFromYawPitch({0, 0, 1}, 90.0, -30.0);
  EXPECT_NEAR(down.linear().col(2).z(), -0.5, 1e-12);
  EXPECT_NEAR(down.linear().col(2).y(), std::sqrt(3.0) / 2.0, 1e-12);

  const Eigen::Vector3d target(3.0, 1.0, 0.7);
  const core::Pose look = CameraPoseLookingAt({0.5, -1.0, 1.6}, target);
  const core::CameraIntrinsics k;
  const Eigen::Vector2d pixel = k.Project(look.inverse() * target);
  EXPECT_NEAR(pixel.x(), k.cx, 1e-9);
  EXPECT_NEAR(pixel.y(), k.cy, 1e-9);
  EXPECT_NEAR(look.linear().col(0).z(), 0.0, 1e-12);  // level horizon
  EXPECT_THROW(CameraPoseLookingAt({0, 0, 1}, {0, 0, 0}), core::InputError);
}

}  // namespace
}  // namespace hoidslam::synth
