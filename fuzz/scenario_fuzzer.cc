// Scenario files: the bytes are a scenario (JSON, docs/synthetic-benchmark.md), parsed from text as
// synth::LoadScenario parses a file.

#include <string>
#include <string_view>

#include "fuzz/targets.h"
#include "hoidslam/synth/scenario.h"

namespace hoidslam::fuzz {

void FuzzScenario(Bytes input) {
  const std::string source = "scenario.json";
  const std::string_view text(reinterpret_cast<const char*>(input.data()), input.size());
  const auto scenario = ParseOrReject([&] { return synth::ParseScenario(text, source); }, source);
  if (!scenario) return;
  // Every place and size is a finite number.
  Require(scenario->camera.T_anchor.matrix().allFinite(), "the camera anchor is not finite");
  const synth::OfficeLayout& office = scenario->office;
  Require(office.room.allFinite(), "the room size is not finite");
  for (const synth::Desk& desk : office.desks) {
    Require(desk.position.allFinite() && desk.size.allFinite(), "a desk is not finite");
  }
  for (const synth::Shelf& shelf : office.shelves) {
    Require(shelf.position.allFinite() && shelf.size.allFinite(), "a shelf is not finite");
  }
  for (const synth::OfficeObject& object : office.objects) {
    Require(object.position.allFinite(), "an object's position is not finite");
  }
  for (const synth::PersonSpec& person : scenario->people) {
    Require(person.start.allFinite(), "a person's start is not finite");
    for (const synth::Action& action : person.actions) {
      Require(action.to.allFinite() && (!action.position || action.position->allFinite()),
              "an action's place is not finite");
    }
  }
}

}  // namespace hoidslam::fuzz
