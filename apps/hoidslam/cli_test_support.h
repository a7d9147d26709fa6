#pragma once
// What the end-to-end tests share: running the built hoidslam as a user does, checking its one error line, and
// rendering short synthetic sequences to run on.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "hoidslam/core/sanitizers.h"
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

// The stretch of a shipped scenario an end-to-end test renders and runs on: `frames` frames, every `step`-th frame of
// its camera path.
struct Stretch {
  int frames = 0;
  int step = 1;
};

// Under a sanitizer (scripts/sanitize.sh), where each frame costs 5–10 times as much, a test runs on the same
// stretch of the scenario (the same people, the same events) in a third of the frames, three times as far apart.
// The sanitized run goes through the same code looking for memory and threading errors; tracking over three times
// the motion between frames is less accurate, so the tightest checks of accuracy hold in the plain build only.
constexpr Stretch ThinnedUnderSanitizers(Stretch stretch) {
  return kSanitized ? Stretch{stretch.frames / 3, stretch.step * 3} : stretch;
}

// Renders a stretch of a shipped scenario into scratch/<scenario>.
std::filesystem::path Render(const testing::TempDir& scratch, const std::string& scenario, Stretch stretch);

// The summary.json of a run folder.
nlohmann::json Summary(const std::filesystem::path& out);

// The browser test of the viewer's page (web/tests/viewer_test.mjs, docs/viewer.md), run by Node.js with `arguments`
// and the build's playwright-core, within 600 s.
RunResult RunPageTest(const testing::TempDir& scratch, const std::vector<std::string>& arguments);

// A screenshot of the page `html` as headless Chromium renders it in a window of `window` pixels (the browser found
// when the build was configured). Without a browser, or when it fails, adds a test failure that says why and
// returns an empty image.
cv::Mat ChromiumScreenshot(const testing::TempDir& scratch, const std::filesystem::path& html, cv::Size window);

}  // namespace hoidslam::apps
