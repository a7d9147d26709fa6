#pragma once
// Bench sequences for the bench tests, as RequestedSequences / InspectSequence would describe them.

#include <string>

#include "hoidslam/bench/plan.h"

namespace hoidslam::bench {

// A shipped scenario, rendered into /b/sequences/<name>, with masks and the default HOID settings.
inline BenchSequence SyntheticSequence(const std::string& name) {
  BenchSequence sequence;
  sequence.name = name;
  sequence.path = "/b/sequences/" + name;
  sequence.scenario = name;
  sequence.has_masks = true;
  sequence.min_interaction_area = 0.4;
  sequence.depth_threshold = 0.2;
  return sequence;
}

// A TUM folder, /data/<name>, with the fr3 settings file and no masks.
inline BenchSequence TumSequence(const std::string& name) {
  BenchSequence sequence;
  sequence.name = name;
  sequence.path = "/data/" + name;
  sequence.settings = "/cfg/TUM3.yaml";
  sequence.min_interaction_area = 0.4;
  sequence.depth_threshold = 0.2;
  return sequence;
}

}  // namespace hoidslam::bench
