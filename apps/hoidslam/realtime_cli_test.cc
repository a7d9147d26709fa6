// End-to-end tests of `hoidslam run` in real time, as a user runs it live: the detector in its own thread, the
// camera's pace, and Ctrl-C. They are the command-line tests ThreadSanitizer runs (label `threaded`): the threads a
// user's run starts, all at once in one process.
#include <algorithm>
#include <chrono>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "hoidslam/core/sanitizers.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::apps {
namespace {

using ::hoidslam::testing::ReadText;
using ::testing::HasSubstr;

namespace fs = std::filesystem;

TEST(CliRun, RealTimePacedRunLogsHowOldTheDetectionsWere) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", {60, 1});  // 2 s at 30 Hz
  const fs::path out = scratch / "run";
  // 64 MB hold about 30 frames: the replay decodes the second half when it gets there.
  const RunResult run = RunHoidslam(scratch, {"run", sequence.string(), "--realtime", "--pace", "--preload-mb", "64",
                                              "--detector-latency", "50", "--out", out.string()});
  ASSERT_EQ(run.exit_status, 0) << run.err;
  EXPECT_THAT(run.err, HasSubstr("the camera's clock held meanwhile"));
  EXPECT_THAT(run.out, HasSubstr("frames dropped"));
  EXPECT_THAT(run.out, HasSubstr("detections: median age"));
  const nlohmann::json summary = Summary(out);
  EXPECT_TRUE(summary["realtime"].get<bool>());
  EXPECT_TRUE(summary["paced"].get<bool>());
  EXPECT_EQ(summary["frames"].get<int>() + summary["dropped"].get<int>(), 60);
  // 50 ms is more than a frame, as long as tracking a frame takes less than the detector's 50 ms. Under a
  // sanitizer it takes longer (and the paced run drops most frames), so the newest detections are mostly those of
  // the frame itself.
  if (!kSanitized) {
    EXPECT_GE(summary["detections"]["median_age_frames"].get<double>(), 1.0);
  }
  EXPECT_GE(summary["detections"]["median_detector_ms"].get<double>(), 50.0);
  EXPECT_THAT(ReadText(out / "frames.jsonl"), HasSubstr(R"("age_ms":)"));
  // The real-time mode gives up the same output on every run.
  ExpectOneErrorLine(RunHoidslam(scratch, {"run", sequence.string(), "--realtime", "--deterministic", "--out",
                                           (scratch / "no").string()}),
                     "--realtime");
  // A usage error, as for every option out of its range: the option named, and a pointer to --help.
  const RunResult no_memory =
      RunHoidslam(scratch, {"run", sequence.string(), "--pace", "--preload-mb", "0", "--out", (scratch / "no").string()});
  EXPECT_NE(no_memory.exit_status, 0);
  EXPECT_THAT(no_memory.err, HasSubstr("--preload-mb: Value 0 not in range"));
  EXPECT_FALSE(fs::exists(scratch / "no"));
}

TEST(CliRun, CtrlCAtAnyMomentLeavesCompleteOutputsOrNone) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", {90, 1});  // 3 s at 30 Hz
  for (const int ms : {50, 400, 1500}) {
    const fs::path out = scratch / ("run" + std::to_string(ms));
    const RunResult run = RunHoidslam(scratch,
                                      {"run", sequence.string(), "--realtime", "--pace", "--detector-latency", "40",
                                       "--out", out.string()},
                                      std::chrono::milliseconds(ms));
    EXPECT_EQ(run.exit_status, 130) << ms << " ms: " << run.err;  // 128 + SIGINT, as an interrupted program
    if (!fs::exists(out)) continue;  // stopped before the run began: nothing written
    const nlohmann::json summary = Summary(out);
    EXPECT_TRUE(summary["interrupted"].get<bool>()) << ms;
    const auto lines = [](const std::string& text) { return std::count(text.begin(), text.end(), '\n'); };
    EXPECT_EQ(lines(ReadText(out / "frames.jsonl")), summary["frames"].get<int>()) << ms;
    EXPECT_EQ(lines(ReadText(out / "trajectory.txt")) - 1, summary["tracked"].get<int>()) << ms;  // one header line
    EXPECT_TRUE(fs::exists(out / "map.ply")) << ms;
  }
}

}  // namespace
}  // namespace hoidslam::apps
