#include "hoidslam/synth/world.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <set>
#include <string>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/test_scenarios.h"

namespace hoidslam::synth {
namespace {

using ::testing::HasSubstr;

// "a" moves a cup and a chair; "b" waits, then takes the same cup elsewhere, sits down and leaves.
const char* kTwoPeople = R"([
  {"name": "a", "start": [2.0, 2.5], "actions": [
    {"action": "pick_up", "object": "cup_2"},
    {"action": "carry_to", "to": [2.0, 2.4]},
    {"action": "put_down", "to": [2.6, 3.65]},
    {"action": "stand_at", "object": "tv_1", "duration": 2},
    {"action": "push", "object": "chair_5", "to": [1.5, 2.0]}]},
  {"name": "b", "start": [6.5, 2.5], "facing_deg": 180, "enter_at": 1.0, "actions": [
    {"action": "stop", "duration": 1},
    {"action": "pick_up", "object": "cup_2", "at": 16},
    {"action": "put_down", "to": [5.0, 4.0]},
    {"action": "sit_on", "object": "chair_2", "duration": 3},
    {"action": "leave", "to": [7.8, 1.0]}]}
])";

const WorldEvent& FindEvent(const World& world, const std::string& person, const std::string& action) {
  const auto& events = world.events();
  const auto it = std::find_if(events.begin(), events.end(),
                               [&](const WorldEvent& e) { return e.person == person && e.action == action; });
  if (it == events.end()) throw std::runtime_error("no event " + person + " " + action);
  return *it;
}

std::string PlanError(const std::string& people) {
  try {
    World(fixtures::SmallScenario(people), fixtures::DefaultTextures());
  } catch (const core::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

// Objects that no event names keep their resting pose, exactly, at every sampled time.
void ExpectUntouchedObjectsStill(const Scenario& scenario, const World& world) {
  std::set<std::string> touched;
  for (const WorldEvent& event : world.events()) touched.insert(event.object);
  for (const OfficeObject& object : scenario.office.objects) {
    if (touched.contains(object.name)) continue;
    const core::Pose rest = scenario.office.RestPose(object);
    for (double t = 0.0; t <= world.end_time() + 1.0; t += 0.25) {
      ASSERT_TRUE(world.ObjectPose(object.name, t)->matrix() == rest.matrix()) << object.name << " at " << t;
    }
  }
}

TEST(World, ObjectsNobodyTouchesNeverMove) {
  const Scenario scenario = fixtures::SmallScenario(kTwoPeople);
  const World world(scenario, fixtures::DefaultTextures());
  ExpectUntouchedObjectsStill(scenario, world);
}

TEST(World, ACarriedObjectMovesWithTheHand) {
  const Scenario scenario = fixtures::SmallScenario(kTwoPeople);
  const World world(scenario, fixtures::DefaultTextures());
  const double picked = FindEvent(world, "a", "pick_up").time;
  const double put = FindEvent(world, "a", "put_down").time;
  // Between the end of the lift (0.7 s) and the start of the placing (0.8 s) the cup rides in the hand.
  std::optional<Eigen::Vector3d> grip;
  Eigen::Vector3d first_position = Eigen::Vector3d::Zero();
  double travelled = 0.0;
  for (double t = picked + 0.75; t < put - 0.85; t += 0.1) {
    const core::Pose cup = *world.ObjectPose("cup_2", t);
    const Eigen::Vector3d hand = world.PersonSkeleton(0, t)->hand[kRight];
    const Eigen::Vector3d in_cup = cup.inverse() * hand;
    if (!grip) {
      grip = in_cup;
      first_position = cup.translation();
    }
    EXPECT_LT((in_cup - *grip).norm(), 1e-6) << "at " << t;
    travelled = std::max(travelled, (cup.translation() - first_position).norm());
    EXPECT_THAT(world.MovingAt(t), ::testing::Contains("cup_2"));
  }
  EXPECT_GT(travelled, 0.5);
}

TEST(World, AnObjectStaysWhereItWasPutDown) {
  const Scenario scenario = fixtures::SmallScenario(kTwoPeople);
  const World world(scenario, fixtures::DefaultTextures());
  const WorldEvent& put = FindEvent(world, "a", "put_down");
  const double taken_again = FindEvent(world, "b", "pick_up").time;
  ASSERT_TRUE(put.to.has_value());
  EXPECT_NEAR(put.to->x(), 2.6, 1e-9);
  EXPECT_NEAR(put.to->y(), 3.65, 1e-9);
  EXPECT_NEAR(put.to->z(), 0.74, 1e-9);  // on desk_1
  const core::Pose at_release = *world.ObjectPose("cup_2", put.time);
  for (double t = put.time; t < taken_again; t += 0.1) {
    EXPECT_TRUE(world.ObjectPose("cup_2", t)->matrix() == at_release.matrix()) << "at " << t;
    EXPECT_THAT(world.MovingAt(t), ::testing::Not(::testing::Contains("cup_2")));
  }
  // b found it there and took it to desk_2.
  const WorldEvent& b_put = FindEvent(world, "b", "put_down");
  EXPECT_TRUE(FindEvent(world, "b", "pick_up").from->isApprox(*put.to));
  EXPECT_TRUE(world.ObjectPose("cup_2", world.end_time() + 5.0)->translation().isApprox(*b_put.to));
}

TEST(World, PushedChairEndsWhereAsked) {
  const Scenario scenario = fixtures::SmallScenario(kTwoPeople);
  const World world(scenario, fixtures::DefaultTextures());
  const WorldEvent& push = FindEvent(world, "a", "push");
  EXPECT_NEAR(push.to->x(), 1.5, 1e-6);
  EXPECT_NEAR(push.to->y(), 2.0, 1e-6);
  EXPECT_NEAR(world.ObjectPose("chair_5", world.end_time())->translation().z(), 0.0, 1e-9);
}

TEST(World, PeopleMoveExceptWhenTheyStandStill) {
  const Scenario scenario = fixtures::SmallScenario(kTwoPeople);
  const World world(scenario, fixtures::DefaultTextures());
  EXPECT_THAT(world.MovingAt(0.2), ::testing::Contains("a"));
  const double standing = FindEvent(world, "a", "stand_at").time + 1.0;
  EXPECT_THAT(world.MovingAt(standing), ::testing::Not(::testing::Contains("a")));
  const double sitting = FindEvent(world, "b", "sit_down").time + 1.2 + 1.0;  // seated, still
  EXPECT_THAT(world.MovingAt(sitting), ::testing::Not(::testing::Contains("b")));
  EXPECT_GT(world.PersonPose(1, sitting)->sit, 0.99);
  // The chair someone sits on stays put.
  EXPECT_TRUE(world.ObjectPose("chair_2", sitting)->matrix() ==
              scenario.office.RestPose(*scenario.office.FindObject("chair_2")).matrix());
  // Snapshot flags agree with MovingAt.
  const SceneSnapshot snapshot = world.Snapshot(standing);
  const int a_id = *world.InstanceId("a");
  for (const SceneInstance& instance : snapshot.instances) {
    if (instance.id == a_id) {
      EXPECT_FALSE(instance.moving);
    }
  }
}

TEST(World, APersonTurnsOnTheSpotToFaceAPoint) {
  // Facing +x, a person turns to the camera of the fixture (4.0, 1.2), a quarter turn to their right.
  const World world(fixtures::SmallScenario(R"([{"name": "a", "start": [4.0, 2.4], "facing_deg": 0, "actions": [
      {"action": "face", "to": [4.0, 1.2]}, {"action": "stop", "duration": 2}]}])"),
                    fixtures::DefaultTextures());
  EXPECT_THAT(world.MovingAt(0.2), ::testing::Contains("a"));
  const BodyPose turned = *world.PersonPose(0, 1.5);
  EXPECT_THAT(world.MovingAt(1.5), ::testing::Not(::testing::Contains("a")));
  EXPECT_NEAR(turned.yaw, -std::numbers::pi / 2.0, 1e-9);
  EXPECT_TRUE(turned.position.isApprox(Eigen::Vector2d(4.0, 2.4)));
}

TEST(World, PeopleAppearWhenTheyEnterAndVanishWhenTheyLeave) {
  const World world(fixtures::SmallScenario(kTwoPeople), fixtures::DefaultTextures());
  const int b_id = *world.InstanceId("b");
  auto has_b = [&](double t) {
    const SceneSnapshot s = world.Snapshot(t);
    return std::any_of(s.instances.begin(), s.instances.end(), [&](const SceneInstance& i) { return i.id == b_id; });
  };
  EXPECT_FALSE(world.PersonPose(1, 0.5).has_value());
  EXPECT_FALSE(has_b(0.5));
  EXPECT_TRUE(has_b(1.5));
  const double left = FindEvent(world, "b", "leave").time;
  EXPECT_TRUE(has_b(left - 0.1));
  EXPECT_FALSE(has_b(left + 0.1));
}

TEST(World, IdsAreUniqueAndStable) {
  const World world(fixtures::SmallScenario(kTwoPeople), fixtures::DefaultTextures());
  const SceneSnapshot early = world.Snapshot(2.0);
  const SceneSnapshot late = world.Snapshot(20.0);
  std::set<int> ids;
  for (const SceneInstance& instance : early.instances) {
    EXPECT_GT(instance.id, kNoInstance);
    EXPECT_TRUE(ids.insert(instance.id).second);
  }
  ASSERT_EQ(early.instances.size(), late.instances.size());
  for (std::size_t i = 0; i < early.instances.size(); ++i) {
    EXPECT_EQ(early.instances[i].id, late.instances[i].id);
    EXPECT_EQ(early.instances[i].label, late.instances[i].label);
  }
}

TEST(World, NoPeopleNothingMoves) {
  const World world(fixtures::SmallScenario("[]"), fixtures::DefaultTextures());
  EXPECT_TRUE(world.events().empty());
  for (double t = 0.0; t < 5.0; t += 0.5) {
    EXPECT_TRUE(world.MovingAt(t).empty());
    for (const SceneInstance& instance : world.Snapshot(t).instances) EXPECT_FALSE(instance.moving);
  }
}

TEST(World, ImpossibleActionsNameTheirKey) {
  EXPECT_THAT(PlanError(R"([{"name": "a", "start": [2, 2.5], "actions": [{"action": "put_down", "to": [3, 3]}]}])"),
              HasSubstr("small.json: people[0].actions[0]: a carries nothing to put down"));
  EXPECT_THAT(PlanError(R"([{"name": "a", "start": [2, 2.5], "actions": [
                  {"action": "pick_up", "object": "cup_1"}, {"action": "pick_up", "object": "cup_2"}]}])"),
              HasSubstr("people[0].actions[1]: a cannot pick_up while carrying 'cup_1'"));
  EXPECT_THAT(PlanError(R"([{"name": "a", "start": [2, 2.5], "actions": [{"action": "pick_up", "object": "cup_1"}]},
                            {"name": "b", "start": [3, 2.5], "actions": [{"action": "pick_up", "object": "cup_1",
                                                                         "at": 5}]}])"),
              HasSubstr("people[1].actions[0]: 'cup_1' is held by a"));
  EXPECT_THAT(PlanError(R"([{"name": "a", "start": [2, 2.5], "actions": [{"action": "carry_to", "to": [3, 2]}]}])"),
              HasSubstr("people[0].actions[0]: a carries nothing"));
  EXPECT_THAT(PlanError(R"([{"name": "a", "start": [2, 2.5], "actions": [{"action": "face", "to": [2, 2.5]}]}])"),
              HasSubstr("people[0].actions[0]: a stands at (2.00, 2.50): no direction to face"));
  // Not straight through the desk: there is no way into the middle of it.
  EXPECT_THAT(PlanError(R"([{"name": "a", "start": [2, 2.5], "actions": [
                  {"action": "walk_to", "to": [4, 2.5]}, {"action": "walk_to", "to": [3.2, 3.9]}]}])"),
              HasSubstr("small.json: people[0].actions[1]: a finds no way from (4.00, 2.50) to (3.20, 3.90)"));
}

TEST(World, ShippedScenariosPlanAndLeaveUntouchedObjectsAlone) {
  for (const std::string& name : BuiltinScenarioNames()) {
    SCOPED_TRACE(name);
    const Scenario scenario = LoadScenario(name);
    const World world(scenario, fixtures::DefaultTextures());
    EXPECT_EQ(world.events().empty(), scenario.people.empty());
    // People are done within 40 s (the TUM paths last 24-36 s), or within a longer procedural camera path.
    const ProceduralPathOptions& procedural = scenario.camera.procedural;
    const double longer_path = scenario.camera.tum.empty() ? procedural.frames / procedural.fps : 0.0;
    EXPECT_LT(world.end_time(), std::max(40.0, longer_path));
    ExpectUntouchedObjectsStill(scenario, world);
  }
}

TEST(World, ShippedScenariosKeepPeopleOutOfDesksAndShelves) {
  for (const std::string& name : BuiltinScenarioNames()) {
    const Scenario scenario = LoadScenario(name);
    const World world(scenario, fixtures::DefaultTextures());
    for (std::size_t p = 0; p < scenario.people.size(); ++p) {
      for (double t = 0.0; t <= world.end_time(); t += 0.1) {
        const auto pose = world.PersonPose(p, t);
        if (!pose) continue;
        EXPECT_FALSE(scenario.office.IsBlocked(pose->position, 0.05))
            << name << ": " << scenario.people[p].name << " at (" << pose->position.transpose() << "), t = " << t;
      }
    }
  }
}

// True when the boxes of two objects (their extents at their poses) overlap: some point of a grid over one
// lies inside the other.
bool Overlap(ObjectKind kind_a, const core::Pose& a, ObjectKind kind_b, const core::Pose& b) {
  const Eigen::Vector3d ea = ObjectHalfExtents(kind_a);
  const Eigen::Vector3d eb = ObjectHalfExtents(kind_b);
  for (int i = 0; i <= 8; ++i) {
    for (int j = 0; j <= 8; ++j) {
      for (int k = 0; k <= 4; ++k) {
        const Eigen::Vector3d p_a(ea.x() * (i / 4.0 - 1.0), ea.y() * (j / 4.0 - 1.0), 2.0 * ea.z() * k / 4.0);
        const Eigen::Vector3d p_b = b.inverse() * (a * p_a);
        if (std::abs(p_b.x()) < eb.x() && std::abs(p_b.y()) < eb.y() && p_b.z() > 0.0 && p_b.z() < 2.0 * eb.z()) {
          return true;
        }
      }
    }
  }
  return false;
}

TEST(World, ShippedScenariosPutThingsWhereThereIsRoom) {
  for (const std::string& name : BuiltinScenarioNames()) {
    const Scenario scenario = LoadScenario(name);
    const World world(scenario, fixtures::DefaultTextures());
    // Check the office after every put-down and push, and at the start.
    std::vector<double> times = {0.0};
    for (const WorldEvent& event : world.events()) {
      if (event.action == "put_down" || event.action == "push") times.push_back(event.time);
    }
    const auto& objects = scenario.office.objects;
    for (const double t : times) {
      for (std::size_t i = 0; i < objects.size(); ++i) {
        for (std::size_t j = i + 1; j < objects.size(); ++j) {
          EXPECT_FALSE(Overlap(objects[i].kind, *world.ObjectPose(objects[i].name, t), objects[j].kind,
                               *world.ObjectPose(objects[j].name, t)))
              << name << ": " << objects[i].name << " and " << objects[j].name << " at " << t;
        }
      }
    }
  }
}

}  // namespace
}  // namespace hoidslam::synth
