#pragma once
// Small scenarios for the synth tests: a procedural camera (no data files) looking at the default office's
// front desks from (4.0, 1.2, 1.45), and people whose actions are given by the test.

#include <fmt/format.h>

#include <cstddef>
#include <filesystem>
#include <string>

#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/sequence_writer.h"
#include "hoidslam/synth/textures.h"

namespace hoidslam::synth::fixtures {

// The default textures, made once for all the tests of a binary (making them takes a while).
inline const TextureSet& DefaultTextures() {
  static const TextureSet textures;
  return textures;
}

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

// A short walking_xyz sequence (people carrying things on the real TUM camera path of `tum_dir`) of `frames`
// frames in `folder`: every 4th frame, so that people are in view from about the 25th frame on. Returns `folder`.
inline std::filesystem::path RenderShortWalk(const std::filesystem::path& folder, const std::filesystem::path& tum_dir,
                                             std::size_t frames) {
  constexpr int kStep = 4;
  Scenario scenario = LoadScenario("walking_xyz");
  scenario.max_frames = frames * kStep;
  SynthOptions options;
  options.out = folder;
  options.tum_dir = tum_dir;
  options.frame_step = kStep;
  WriteSequence(scenario, options);
  return folder;
}

}  // namespace hoidslam::synth::fixtures
