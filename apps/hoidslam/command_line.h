#pragma once
// The command line hoidslam was started with, kept for the outputs that record how they were made (summary.json):
// the arguments as given and the folder they were given in, so that relative paths can be followed again.

#include <nlohmann/json.hpp>

namespace hoidslam::apps {

// Called once by main() before parsing.
void RememberCommandLine(int argc, char** argv);

// {"argv": ["hoidslam", "run", ...], "working_directory": "/home/..."}.
nlohmann::json CommandLineJson();

}  // namespace hoidslam::apps
