#pragma once
// Random scenarios: offices, camera paths and people that nobody wrote by hand, drawn from a seed, so that
// tracking can be tuned and tested on a distribution of scenes rather than on a few (`hoidslam synth --random SEED`;
// what is drawn and its ranges: docs/synthetic-benchmark.md, "Random sequences").
//
// A random scenario is an ordinary scenario document: a random office ("base": "empty" with desks, shelves,
// objects and wall panels), a "waypoints" camera composed of rings, hand-held walks (some of them back to places
// seen before), fast roll/pitch/yaw turns and a stare at a bare stretch of wall, maybe a covered lens and a dark
// moment, and 0-4 people doing random things. Every draw is checked the way `--scenario` checks a file: the
// document is parsed (ParseScenario), the people's plans are made (World) and the camera path is built and held to
// its bounds (inside the room, clear of the furniture, never too fast); a draw that fails is replaced by a draw
// from a seed derived from the first, so every seed gives a valid scenario, and always the same one.

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "hoidslam/synth/scenario.h"

namespace hoidslam::synth {

// Bounds every random camera path keeps on every frame (checked on each draw, and tested on many seeds).
// Clearance: metres from the walls, from the desks' and shelves' footprints, and from a chair's footprint taken as
// the circle about its centre through its corners.
inline constexpr double kRandomCameraClearance = 0.3;
inline constexpr double kRandomCameraMaxSpeed = 1.5;       // metres per second
inline constexpr double kRandomCameraMaxTurnRate = 220.0;  // degrees per second (fast turns peak at 90-190)

struct RandomScenarioOptions {
  double duration = 75.0;  // seconds of camera path (frames at 30 fps), in [10, 3600]

  // Throws InputError naming the parameter ("--random-duration").
  void Check() const;
};

// The name of the random scenario of `seed`: "random-<seed>".
std::string RandomScenarioName(std::uint64_t seed);

// The scenario document (the JSON format of docs/synthetic-benchmark.md) of `seed`; the same seed and options give
// the same document, to the byte once dumped. Applies options.Check().
nlohmann::json RandomScenarioDocument(std::uint64_t seed, const RandomScenarioOptions& options = {});

// RandomScenarioDocument parsed, as `--scenario` would parse it from a file (its source is the scenario's name).
Scenario RandomScenario(std::uint64_t seed, const RandomScenarioOptions& options = {});

}  // namespace hoidslam::synth
