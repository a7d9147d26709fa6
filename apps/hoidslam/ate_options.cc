#include "ate_options.h"

namespace hoidslam::apps {

void AddAteOptions(CLI::App& command, eval::AteOptions& options) {
  command.add_option("--max-difference", options.association.max_difference,
                     "Largest time difference (s) of an associated pose pair for ATE")
      ->capture_default_str();
  command.add_option("--offset", options.association.offset,
                     "Time offset (s) added to the estimated stamps before comparing them")
      ->capture_default_str();
  command.add_flag("--scale", options.estimate_scale,
                   "Align with scale (Sim(3)) for ATE, for estimates of unknown scale such as monocular ones");
}

}  // namespace hoidslam::apps
