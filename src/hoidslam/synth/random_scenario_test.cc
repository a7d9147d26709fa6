#include "hoidslam/synth/random_scenario.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <span>
#include <vector>

#include "hoidslam/core/error.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/synth/sequence_writer.h"
#include "hoidslam/synth/test_scenarios.h"
#include "hoidslam/synth/world.h"
#include "support/temp_dir.h"

namespace hoidslam::synth {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kDegree = std::numbers::pi / 180.0;

// The scenarios of seeds 0 to count - 1, drawn once for all the tests of one run (about 10 ms a seed). The span
// holds until a call with a larger count.
std::span<const Scenario> FirstSeeds(std::size_t count) {
  static std::vector<Scenario> drawn;
  for (std::uint64_t seed = drawn.size(); seed < count; ++seed) drawn.push_back(RandomScenario(seed));
  return std::span<const Scenario>(drawn).first(count);
}

std::vector<CameraFrame> Frames(const Scenario& scenario) {
  return CameraPath::Procedural(scenario.camera.procedural).frames();
}

double TurnRate(const CameraFrame& a, const CameraFrame& b) {
  return Eigen::AngleAxisd(a.T_wc.linear().transpose() * b.T_wc.linear()).angle() / (b.timestamp - a.timestamp);
}

double Speed(const CameraFrame& a, const CameraFrame& b) {
  return (b.T_wc.translation() - a.T_wc.translation()).norm() / (b.timestamp - a.timestamp);
}

// Heading of the view on the level, radians.
double Heading(const CameraFrame& frame) {
  const Eigen::Vector3d forward = frame.T_wc.linear().col(2);
  return std::atan2(forward.y(), forward.x());
}

// The inward normal and the distance of the wall nearest to `xy`.
std::pair<Wall, double> NearestWall(const OfficeLayout& office, const Eigen::Vector2d& xy) {
  const std::array<std::pair<Wall, double>, 4> walls = {{{Wall::kFront, xy.y()},
                                                         {Wall::kRight, office.room.x() - xy.x()},
                                                         {Wall::kBack, office.room.y() - xy.y()},
                                                         {Wall::kLeft, xy.x()}}};
  return *std::min_element(walls.begin(), walls.end(),
                           [](const auto& a, const auto& b) { return a.second < b.second; });
}

// True when the camera of `frame` looks squarely at a bare stretch of wall 0.55-1.25 m ahead: nothing on the wall
// within 0.3 m of where the view meets it, and no furniture in between.
bool StaresAtBareWall(const OfficeLayout& office, const CameraFrame& frame) {
  const Eigen::Vector2d xy = frame.T_wc.translation().head<2>();
  const auto [wall, distance] = NearestWall(office, xy);
  const Eigen::Vector3d forward = frame.T_wc.linear().col(2);
  if (distance < 0.55 || distance > 1.25 || -forward.head<2>().dot(InwardNormal(wall)) < std::cos(15.0 * kDegree)) {
    return false;
  }
  const Eigen::Vector2d hit = xy - InwardNormal(wall) * distance;
  const double at = wall == Wall::kFront || wall == Wall::kBack ? hit.x() : hit.y();
  for (const WallPanel& panel : *office.walls) {
    if (panel.wall == wall && std::abs(panel.at - at) < panel.size.x() / 2.0 + 0.3) return false;
  }
  for (double s = 0.0; s <= distance; s += 0.05) {
    if (office.IsBlocked(xy - InwardNormal(wall) * s, 0.0)) return false;
  }
  return true;
}

// Stretches in which the camera comes back, at least 12 s later, to within 0.3 m and 15 degrees of a pose it held
// before: the returns a loop detector can find (separate when 3 s apart).
int Returns(const std::vector<CameraFrame>& frames) {
  int returns = 0;
  double last = -1e9;
  for (std::size_t i = 0; i < frames.size(); i += 15) {
    const double t = frames[i].timestamp;
    bool seen = false;
    for (std::size_t j = 0; j < i && frames[j].timestamp <= t - 12.0 && !seen; j += 3) {
      seen = (frames[j].T_wc.translation() - frames[i].T_wc.translation()).norm() < 0.3 &&
             Eigen::AngleAxisd(frames[j].T_wc.linear().transpose() * frames[i].T_wc.linear()).angle() < 15.0 * kDegree;
    }
    if (seen && t - last > 3.0) ++returns;
    if (seen) last = t;
  }
  return returns;
}

TEST(RandomScenario, OneSeedGivesOneDocumentAndOthersOthers) {
  const nlohmann::json a = RandomScenarioDocument(17);
  EXPECT_EQ(a.dump(), RandomScenarioDocument(17).dump());
  EXPECT_NE(a.dump(), RandomScenarioDocument(18).dump());
  EXPECT_EQ(a.at("name"), "random-17");
  EXPECT_EQ(RandomScenarioName(17), "random-17");
  // An ordinary document: parsed, it is itself again.
  const Scenario scenario = RandomScenario(17);
  EXPECT_EQ(scenario.name, "random-17");
  EXPECT_EQ(scenario.document, a);
  EXPECT_EQ(scenario.camera.procedural.motion, ProceduralMotion::kWaypoints);
  EXPECT_EQ(scenario.camera.procedural.frames, 2251U);  // 75 s at 30 fps, both ends included
  RandomScenarioOptions shorter;
  shorter.duration = 20.0;
  EXPECT_EQ(RandomScenario(17, shorter).camera.procedural.frames, 601U);
}

TEST(RandomScenario, DurationOutOfRangeNamesTheOption) {
  RandomScenarioOptions options;
  options.duration = 5.0;
  EXPECT_THAT([&] { RandomScenarioDocument(1, options); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("--random-duration")));
}

TEST(RandomScenario, TwoHundredSeedsParseAndPlan) {
  for (const Scenario& scenario : FirstSeeds(200)) {
    SCOPED_TRACE(scenario.name);
    EXPECT_NO_THROW(World(scenario, fixtures::DefaultTextures()));
    EXPECT_EQ(scenario.camera.procedural.frames, 2251U);
    EXPECT_LE(scenario.people.size(), 4U);
  }
}

TEST(RandomScenario, CameraStaysInTheRoomClearOfFurnitureAndWithinItsSpeeds) {
  for (const Scenario& scenario : FirstSeeds(100)) {
    const OfficeLayout& office = scenario.office;
    const std::vector<CameraFrame> frames = Frames(scenario);
    double closest = 1e9;
    double fastest = 0.0;
    double fastest_turn = 0.0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const Eigen::Vector3d p = frames[i].T_wc.translation();
      closest = std::min({closest, p.x(), p.y(), office.room.x() - p.x(), office.room.y() - p.y()});
      if (office.IsBlocked(p.head<2>(), kRandomCameraClearance)) closest = 0.0;
      for (const OfficeObject& object : office.objects) {
        if (object.kind != ObjectKind::kChair) continue;
        // The chair's footprint as a circle: its half extents' diagonal.
        const Eigen::Vector3d half = ObjectHalfExtents(ObjectKind::kChair);
        closest = std::min(closest, (object.position - p.head<2>()).norm() - half.head<2>().norm());
      }
      if (i == 0) continue;
      fastest = std::max(fastest, Speed(frames[i - 1], frames[i]));
      fastest_turn = std::max(fastest_turn, TurnRate(frames[i - 1], frames[i]));
    }
    EXPECT_GE(closest, kRandomCameraClearance) << scenario.name;
    EXPECT_LE(fastest, kRandomCameraMaxSpeed) << scenario.name;
    EXPECT_LE(fastest_turn, kRandomCameraMaxTurnRate * kDegree) << scenario.name;
  }
}

TEST(RandomScenario, OverManySeedsEveryKindOfMomentAndCrowdOccurs) {
  int rings = 0, walks = 0, rpy = 0, stares = 0, covered = 0, dark = 0, nobody = 0, several = 0, close = 0;
  int returns = 0, with_two_returns = 0;
  const std::size_t seeds = 60;
  for (const Scenario& scenario : FirstSeeds(seeds)) {
    const std::vector<CameraFrame> frames = Frames(scenario);
    // A ring: the view turns one way by more than a full turn. Fast turns: faster than 100 degrees a second (a walk
    // turns at most 80). A stare: a second squarely at a bare wall. A walk: 1.05 m in 2 s (faster than any ring).
    double turned = 0.0;
    double most_turned = 0.0;
    int stare = 0;
    bool walked = false;
    bool fast = false;
    bool stared = false;
    for (std::size_t i = 1; i < frames.size(); ++i) {
      const double step = std::remainder(Heading(frames[i]) - Heading(frames[i - 1]), 2.0 * std::numbers::pi);
      turned = turned * step > 0.0 ? turned + step : step;
      most_turned = std::max(most_turned, std::abs(turned));
      fast = fast || TurnRate(frames[i - 1], frames[i]) > 100.0 * kDegree;
      stare = StaresAtBareWall(scenario.office, frames[i]) ? stare + 1 : 0;
      stared = stared || stare >= 30;
      walked = walked || (i >= 60 && (frames[i].T_wc.translation() - frames[i - 60].T_wc.translation()).norm() > 1.05);
    }
    rings += most_turned > 2.0 * std::numbers::pi ? 1 : 0;
    rpy += fast ? 1 : 0;
    stares += stared ? 1 : 0;
    walks += walked ? 1 : 0;
    const int back = Returns(frames);
    returns += back;
    with_two_returns += back >= 2 ? 1 : 0;
    if (!scenario.covered.empty()) {
      ++covered;
      EXPECT_GE(scenario.covered[0].duration, 1.0);
      EXPECT_LE(scenario.covered[0].duration, 3.0);
    }
    if (!scenario.dark.empty()) {
      ++dark;
      EXPECT_GT(scenario.dark[0].level, 0.0);
      EXPECT_LT(scenario.dark[0].level, 1.0);
    }
    nobody += scenario.people.empty() ? 1 : 0;
    several += scenario.people.size() >= 3 ? 1 : 0;
    // Someone 0.6-1.5 m in front of the camera, in its view.
    const World world(scenario, fixtures::DefaultTextures());
    bool near = false;
    for (std::size_t i = 0; i < frames.size() && !near; i += 3) {
      const double t = frames[i].timestamp - frames.front().timestamp;
      if (scenario.LensCoveredAt(t)) continue;
      for (std::size_t p = 0; p < scenario.people.size() && !near; ++p) {
        const auto pose = world.PersonPose(p, t);
        if (!pose) continue;
        const Eigen::Vector2d to_person = pose->position - frames[i].T_wc.translation().head<2>();
        const Eigen::Vector3d forward = frames[i].T_wc.linear().col(2);
        const double distance = to_person.norm();
        near = distance >= 0.6 && distance <= 1.5 &&
               to_person.normalized().dot(forward.head<2>().normalized()) > std::cos(30.0 * kDegree);
      }
    }
    close += near ? 1 : 0;
  }
  // Drawn: a ring always, fast turns and a stare in 85 % of the sequences (some of them fit no more), covered and
  // dark in 45 %, nobody in 12 %, three people or more in 40 %.
  EXPECT_GE(rings, 50);
  EXPECT_GE(walks, 40);
  EXPECT_GE(rpy, 35);  // peaks of 90-100 degrees a second are not counted here
  EXPECT_GE(stares, 35);
  EXPECT_GE(covered, 15);
  EXPECT_GE(dark, 15);
  EXPECT_GE(nobody, 2);
  EXPECT_GE(several, 10);
  EXPECT_GE(close, 15);
  EXPECT_GE(returns, 2 * static_cast<int>(seeds));  // several returns per sequence, on average
  EXPECT_GE(with_two_returns, 40);
}

TEST(RandomScenario, RendersAndRendersTheSameAgainFromItsScenarioFile) {
  const testing::TempDir temp;
  RandomScenarioOptions options;
  options.duration = 10.0;
  const Scenario scenario = RandomScenario(5, options);
  SynthOptions synth;
  synth.out = temp / "b" / "seq";
  synth.threads = 1;
  synth.frame_step = 100;  // a frame every 3.3 s
  fs::create_directories(temp / "b");
  ASSERT_EQ(WriteSequence(scenario, synth).frames, 4U);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / "b" / "seq");
  EXPECT_EQ(sequence.size(), 4U);
  // The scenario file beside the sequence renders it again, byte for byte.
  const Scenario again = LoadScenario((temp / "b" / "seq" / "scenario.json").string());
  EXPECT_EQ(again.name, "random-5");
  synth.out = temp / "c" / "seq";
  fs::create_directories(temp / "c");
  WriteSequence(again, synth);
  for (const auto& entry : fs::recursive_directory_iterator(temp / "b" / "seq")) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), temp / "b" / "seq");
    std::ifstream first(entry.path(), std::ios::binary);
    std::ifstream second(temp / "c" / "seq" / relative, std::ios::binary);
    ASSERT_TRUE(second) << relative;
    EXPECT_TRUE(std::equal(std::istreambuf_iterator<char>(first), {}, std::istreambuf_iterator<char>(second), {}))
        << relative;
  }
}

}  // namespace
}  // namespace hoidslam::synth
