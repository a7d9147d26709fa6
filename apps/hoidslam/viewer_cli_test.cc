// End-to-end tests of `hoidslam run --view` in a real browser: web/tests/viewer_test.mjs starts the run, opens the
// page in Debian's Chromium (driven by playwright-core from the build's npm packages) and checks what the page shows
// against the files the run writes; a second run has its tab closed while it goes. They are threaded tests: under
// ThreadSanitizer the viewer's threads read the map while tracking and local mapping change it.
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include "support/temp_dir.h"

namespace hoidslam::apps {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

// The browser test's verdict on a run of `sequence`; `more` goes to the test before the run's own arguments.
RunResult DriveViewer(const testing::TempDir& scratch, const fs::path& sequence, const std::vector<std::string>& more) {
  std::vector<std::string> arguments = {"--hoidslam", HOIDSLAM_BINARY, "--out", (scratch / "run").string()};
  arguments.insert(arguments.end(), more.begin(), more.end());
  arguments.insert(arguments.end(), {"--", sequence.string(), "--force"});
  return RunPageTest(scratch, arguments);
}

TEST(CliView, ThePageShowsTheMapAndTheFrameTheRunWrites) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", ThinnedUnderSanitizers({90, 1}));
  const RunResult test = DriveViewer(scratch, sequence, {"--screenshot", (scratch / "viewer.png").string()});
  EXPECT_EQ(test.exit_status, 0) << test.out << test.err;
  EXPECT_THAT(test.out, HasSubstr("ok: stat-points (main map) against map.ply"));
  EXPECT_THAT(test.out, HasSubstr("viewer test passed"));
}

TEST(CliView, ATabClosedWhileTheRunGoesLetsItFinish) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", ThinnedUnderSanitizers({240, 1}));
  const RunResult test = DriveViewer(scratch, sequence, {"--close-tab-midway"});
  EXPECT_EQ(test.exit_status, 0) << test.out << test.err;
  EXPECT_THAT(test.out, HasSubstr("viewer test passed"));
}

}  // namespace
}  // namespace hoidslam::apps
