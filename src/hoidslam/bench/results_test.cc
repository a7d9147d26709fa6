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

// A plan of one hoidplus run of the scenario `name`, its sequence and run folders made in `scratch`.
Plan OneRun(const testing::TempDir& scratch, const std::string& name) {
  BenchOptions options;
  options.runs = 1;
  options.modes = {"hoidplus"};
  options.area_sweep = options.depth_sweep = {};
  BenchSequence sequence = SyntheticSequence(name);
  sequence.path = scratch / name;
  const Plan plan = MakePlan(options, {sequence}, "/bin/hoidslam", scratch.path());
  fs::create_directories(sequence.path);
  fs::create_directories(plan.RunFolder(plan.runs[0]));
  return plan;
}

// The start of a summary.json, up to the objects a test adds.
constexpr const char* kSummaryStart = R"({
    "interrupted": false, "frames": 100, "tracked": 94, "lost": 6, "before_initialization": 0,
    "median_ms": {"load": 1, "extract": 2, "detect": 0, "filter": 0, "track": 2, "tracking_total": 4})";

TEST(ReadRunResult, ReadsMergesLoopRecallAndTheCoveredFrames) {
  const testing::TempDir scratch;
  const Plan plan = OneRun(scratch, "kidnap");
  testing::WriteText(scratch / "kidnap" / "events.jsonl",
                     "{\"action\":\"cover_lens\",\"frame\":60}\n{\"action\":\"uncover_lens\",\"frame\":66}\n");
  testing::WriteText(plan.RunFolder(plan.runs[0]) / "summary.json", std::string(kSummaryStart) + R"(,
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
  // A run without --dense: no dense figures.
  EXPECT_EQ(result.dense_area, std::nullopt);
  EXPECT_EQ(result.dense_completeness, std::nullopt);
  EXPECT_TRUE(RunResultToJson(result)["dense"].is_null());
}

TEST(ReadRunResult, ReadsTheDenseMapAndItsScoreAgainstTheGeometry) {
  const testing::TempDir scratch;
  const Plan plan = OneRun(scratch, "walking_xyz");
  const fs::path summary = plan.RunFolder(plan.runs[0]) / "summary.json";
  const std::string dense = R"(,
    "dense": {"written": true, "keyframes": 12, "mesh": {"vertices": 5000, "triangles": 9000, "area_m2": 14.5},
              "cloud_points": 4000, "occupied_cells": 2100, "volume_mb": 48.2, "held_mb": 60.1,
              "median_fuse_ms": 23.5, "build_seconds": 1.75, "options": {"voxel_size": 0.02},
              "people": {"share": 0.031, "boxes": 20, "person_pixels": 90000, "fused_pixels": 2790}})";
  testing::WriteText(summary, std::string(kSummaryStart) + dense + R"(,
    "evaluation": {"ate": {"error_m": {"rmse": 0.01, "mean": 0.009, "median": 0.008}},
                   "dense": {"accuracy_m": {"mean": 0.006, "median": 0.004, "p90": 0.012}, "completeness": 0.87,
                             "seen_samples": 30000, "area_m2": 14.5, "ghost_area_m2": 0.3, "ghost_share": 0.0207,
                             "occupied_cells": 2000, "ghost_cells": 15, "options": {"ghost_distance": 0.05}}}})");
  RunResult result = ReadRunResult(plan, plan.runs[0]);
  EXPECT_EQ(result.dense_area, 14.5);
  EXPECT_EQ(result.dense_fuse_ms, 23.5);
  EXPECT_EQ(result.dense_build_seconds, 1.75);
  EXPECT_EQ(result.dense_volume_mb, 48.2);
  EXPECT_EQ(result.dense_people_kept, 0.031);
  EXPECT_EQ(result.dense_accuracy_median, 0.004);
  EXPECT_EQ(result.dense_accuracy_p90, 0.012);
  EXPECT_EQ(result.dense_completeness, 0.87);
  EXPECT_EQ(result.dense_ghost_area, 0.3);
  EXPECT_EQ(result.dense_ghost_share, 0.0207);
  EXPECT_EQ(result.dense_occupied_cells, 2000.0);
  EXPECT_EQ(result.dense_ghost_cells, 15.0);
  nlohmann::json json = RunResultToJson(result);
  EXPECT_EQ(json["dense"]["area_m2"], 14.5);
  EXPECT_EQ(json["dense"]["ghost_cells"], 15.0);
  EXPECT_EQ(json["dense"]["people_kept"], 0.031);

  // A sequence without its exact geometry (a real recording): the dense map, no score.
  testing::WriteText(summary, std::string(kSummaryStart) + dense + "}");
  result = ReadRunResult(plan, plan.runs[0]);
  EXPECT_EQ(result.dense_area, 14.5);
  EXPECT_EQ(result.dense_accuracy_median, std::nullopt);
  EXPECT_EQ(result.dense_ghost_area, std::nullopt);
  EXPECT_EQ(result.dense_ghost_cells, std::nullopt);
  json = RunResultToJson(result);
  EXPECT_EQ(json["dense"]["build_seconds"], 1.75);
  EXPECT_TRUE(json["dense"]["completeness"].is_null());
}

}  // namespace
}  // namespace hoidslam::bench
