#include "fuzz/targets.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace hoidslam::fuzz {

std::span<const Target> Targets() {
  static constexpr std::array kTargets = {
      Target{"settings", &FuzzSettings},       Target{"tum_lists", &FuzzTumLists},
      Target{"associations", &FuzzAssociations}, Target{"trajectory", &FuzzTrajectory},
      Target{"detections", &FuzzDetections},   Target{"scenario", &FuzzScenario},
      Target{"vocabulary", &FuzzVocabulary},     Target{"map_file", &FuzzMapFile},
      Target{"ply", &FuzzPly},
  };
  return kTargets;
}

const Target& FindTarget(std::string_view name) {
  const auto targets = Targets();
  const auto it = std::find_if(targets.begin(), targets.end(), [&](const Target& t) { return t.name == name; });
  if (it == targets.end()) throw std::invalid_argument("no fuzz target named " + std::string(name));
  return *it;
}

}  // namespace hoidslam::fuzz
