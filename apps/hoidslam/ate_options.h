#pragma once
// The options of how ATE associates and aligns two trajectories, shared by `eval` and `plot` so that both speak
// of them alike and a plot's errors are the ones `eval` prints for the same flags.

#include <CLI/CLI.hpp>

#include "hoidslam/eval/ate.h"

namespace hoidslam::apps {

// --max-difference, --offset and --scale, written into `options`.
void AddAteOptions(CLI::App& command, eval::AteOptions& options);

}  // namespace hoidslam::apps
