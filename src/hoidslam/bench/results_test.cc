#include "hoidslam/bench/results.h"

#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hoidslam/bench/test_sequences.h"
#include "hoidslam/core/error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::bench {
namespace {

namespace fs = std::filesystem;

TEST(CoveredFrames, CountsTheFramesOfTheRunBetweenCoveringAndUncovering) {
  const testing::TempDir scratch;
  const fs::path events = scratch / "events.jsonl";
  testing::WriteText(events,
                     "{\"action\":\"enter\",\"person\":\"anna\",\"time\":0.0,\"to\":[2.7,2.95,0.0]}\n"
                     "{\"action\":\"cover_lens\",\"frame\":600,\"time\":20.0}\n"
                     "\n"
                     "{\"action\":\"uncover_lens\",\"frame\":660,\"time\":22.0}\n"
                     "{\"action\":\"cover_lens\",\"frame\":900,\"time\":30.0}\n");  // covered to the end
  EXPECT_EQ(CoveredFrames(events, 1000), 60U + 100U);
  EXPECT_EQ(CoveredFrames(events, 630), 30U);  // a run of the first 630 frames
  EXPECT_EQ(CoveredFrames(events, 500), 0U);
  EXPECT_EQ(CoveredFrames(scratch / "none.jsonl", 1000), 0U);  // a real recording has no events

  testing::WriteText(events, "{\"action\":\"cover_lens\",\"frame\":600}\n{\"action\":\"uncover_lens\"}\n");
  try {
    CoveredFrames(events, 1000);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(events.string() + ":2:"));
  }
}

TEST(ReadRunResult, ReadsMergesLoopRecallAndTheCoveredFrames) {
  const testing::TempDir scratch;
  BenchOptions options;
  options.runs = 1;
  options.modes = {"hoidplus"};
  options.area_sweep = options.depth_sweep = {};
  BenchSequence sequence = SyntheticSequence("kidnap");
  sequence.path = scratch / "kidnap";
  const Plan plan = MakePlan(options, {sequence}, "/bin/hoidslam", scratch.path());
  fs::create_directories(scratch / "kidnap");
  fs::create_directories(plan.RunFolder(plan.runs[0]));
  testing::WriteText(scratch / "kidnap" / "events.jsonl",
                     "{\"action\":\"cover_lens\",\"frame\":60}\n{\"action\":\"uncover_lens\",\"frame\":66}\n");
  testing::WriteText(plan.RunFolder(plan.runs[0]) / "summary.json", R"({
    "interrupted": false, "frames": 100, "tracked": 94, "lost": 6, "before_initialization": 0,
    "median_ms": {"load": 1, "extract": 2, "detect": 0, "filter": 0, "track": 2, "tracking_total": 4},
    "evaluation": {"ate": {"error_m": {"rmse": 0.01, "mean": 0.009, "median": 0.008}},
                   "loops": {"count": 2, "false": 0}, "merges": {"count": 1, "false": 1},
                   "loop_recall": {"events": 3, "recalled": 2, "closures": 3, "confirmed": 2}}})");
  const RunResult result = ReadRunResult(plan, plan.runs[0]);
  EXPECT_EQ(result.status, RunStatus::kOk);
  EXPECT_EQ(result.merges, 1.0);
  EXPECT_EQ(result.false_merges, 1.0);
  EXPECT_EQ(result.return_events, 3.0);
  EXPECT_EQ(result.returns_recalled, 2.0);
  EXPECT_EQ(result.closures_judged, 3.0);
  EXPECT_EQ(result.closures_confirmed, 2.0);
  EXPECT_EQ(result.covered, 6U);
  EXPECT_EQ(RunResultToJson(result)["covered"], 6);
}

}  // namespace
}  // namespace hoidslam::bench
