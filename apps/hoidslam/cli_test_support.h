#pragma once
// What the end-to-end tests share: running the built hoidslam as a user does, checking its one error line, and
// rendering short synthetic sequences to run on.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/temp_dir.h"

namespace hoidslam::apps {

struct RunResult {
  int exit_status = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs the built hoidslam with `args`, stdout and stderr captured in files of `scratch`; with `interrupt_after`,
// sends it SIGINT (Ctrl-C) that long after the start.
RunResult RunHoidslam(const testing::TempDir& scratch, const std::vector<std::string>& args,
                      std::optional<std::chrono::milliseconds> interrupt_after = std::nullopt);

// Runs `argv` the same way, e.g. GNU parallel or a browser; argv[0] is looked up on PATH when it has no '/'.
RunResult RunProgram(const testing::TempDir& scratch, const std::vector<std::string>& argv,
                     std::optional<std::chrono::milliseconds> interrupt_after = std::nullopt);

// The one line a user sees for bad input: "error: ..." and nothing else on stderr, exit status 1.
void ExpectOneErrorLine(const RunResult& result, const std::string& names);

// Renders `frames` frames of a shipped scenario, every `step`-th frame of its camera path, into scratch/<scenario>.
std::filesystem::path Render(const testing::TempDir& scratch, const std::string& scenario, int frames, int step);

// The summary.json of a run folder.
nlohmann::json Summary(const std::filesystem::path& out);

}  // namespace hoidslam::apps
