#pragma once
// Small scenarios for the synth tests: a procedural camera (no data files) looking at the default office's
// front desks from (4.0, 1.2, 1.45), and people whose actions are given by the test.

#include <fmt/format.h>

#include <string>

#include "hoidslam/synth/scenario.h"

namespace hoidslam::synth::fixtures {

// A scenario of `people_json` (the JSON array of people), `frames` frames at 10 Hz of a static camera.
inline Scenario SmallScenario(const std::string& people_json, int frames = 12, const std::string& motion = "static") {
  return ParseScenario(fmt::format(R"({{
    "name": "small", "seed": 7,
    "camera": {{"procedural": "{}", "fps": 10, "frames": {}, "position": [4.0, 1.2, 1.45], "look_at": [4.0, 4.5, 0.85]}},
    "office": "default",
    "people": {}
  }})",
                                   motion, frames, people_json),
                       "small.json");
}

// One person who walks across the view close to the camera for about 1.1 s, then stands still.
inline const char* kWalkThenStop = R"([{"name": "walker", "start": [3.2, 2.4], "facing_deg": 0,
  "actions": [{"action": "walk_to", "to": [4.4, 2.4]}, {"action": "stop", "duration": 5}]}])";

}  // namespace hoidslam::synth::fixtures
