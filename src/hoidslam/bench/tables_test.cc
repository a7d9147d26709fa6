#include "hoidslam/bench/tables.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/bench/test_sequences.h"

namespace hoidslam::bench {
namespace {

using ::testing::ElementsAre;

RunResult Ok(double ate, std::size_t lost = 0) {
  RunResult r;
  r.status = RunStatus::kOk;
  r.frames = 100;
  r.tracked = 100 - lost;
  r.lost = lost;
  r.ate_rmse = ate;
  r.ate_mean = ate * 0.9;
  r.ate_median = ate * 0.8;
  r.rpe_translation_rmse = ate * 2;
  r.rpe_rotation_rmse = ate * 100;
  r.leaked = 0.1;
  r.wasted = 0.2;
  // A run that lost frames found them again twice, once wrongly.
  r.relocalizations = lost > 0 ? 2.0 : 0.0;
  r.false_relocalizations = lost > 0 ? 1.0 : 0.0;
  r.median_ms = {.load = 10, .extract = 4, .detect = 0.1, .filter = 0.01, .track = 2, .tracking_total = 6};
  return r;
}

RunResult Failed() {
  RunResult r;
  r.status = RunStatus::kFailed;
  r.message = "error: boom";
  return r;
}

const report::Table& Find(const std::vector<NamedTable>& tables, const std::string& name) {
  const report::Table* table = FindTable(tables, name);
  if (table == nullptr) throw std::runtime_error("no table " + name);
  return *table;
}

class BenchTables : public ::testing::Test {
 protected:
  BenchTables() {
    BenchOptions options;
    options.runs = 3;
    options.modes = {"none", "hoid2d", "hoid3d", "oracle"};
    options.area_sweep = {0.3, 0.4};
    options.depth_sweep = {};
    BenchSequence missing = SyntheticSequence("gone");
    missing.problem = "rendering failed";
    plan_ = MakePlan(options, {SyntheticSequence("walking_xyz"), SyntheticSequence("carry"), missing}, "/bin/hoidslam", "/b");
    // walking_xyz: everything fine; carry: hoid2d loses one run, hoid3d fails every run.
    for (const RunSpec& spec : plan_.runs) {
      const std::string& sequence = plan_.sequences[spec.sequence].name;
      const std::string variant = plan_.variants[spec.variant].Name();
      const double base = variant == "none" ? 0.1 : variant == "hoid2d area=0.3" ? 0.006 : 0.004;
      if (sequence == "carry" && variant == "hoid3d") {
        results_.push_back(Failed());
      } else if (sequence == "carry" && variant == "hoid2d" && spec.run == 2) {
        results_.push_back(Failed());
      } else {
        results_.push_back(Ok(base + 0.001 * static_cast<double>(spec.run), spec.run == 3 ? 2 : 0));
      }
    }
    tables_ = BuildTables(plan_, results_);
  }

  Plan plan_;
  std::vector<RunResult> results_;
  std::vector<NamedTable> tables_;
};

TEST_F(BenchTables, AteCellsAreMediansAndSayWhatIsMissing) {
  const report::Table& ate = Find(tables_, "ate");
  EXPECT_THAT(ate.header, ElementsAre("sequence", "none", "hoid2d", "hoid3d", "oracle"));
  ASSERT_EQ(ate.rows.size(), 4U);
  EXPECT_THAT(ate.rows[0], ElementsAre("walking_xyz", "0.1020", "0.0060", "0.0060", "0.0060"));
  // Runs 1 and 3 of hoid2d finished: the median of 0.005 and 0.007.
  EXPECT_THAT(ate.rows[1], ElementsAre("carry", "0.1020", "0.0060 (2/3)", "failed", "0.0060"));
  EXPECT_THAT(ate.rows[2], ElementsAre("gone", "missing", "missing", "missing", "missing"));
  EXPECT_EQ(ate.rows[3][0], "median of the sequences");
  EXPECT_EQ(ate.rows[3][1], "–");  // not every sequence has a number
  EXPECT_NE(ate.note.find("gone is missing: rendering failed"), std::string::npos);
}

TEST_F(BenchTables, StatisticsSweepsAndTwoAgainstThree) {
  EXPECT_EQ(Find(tables_, "ate_statistics").rows[0][2], "0.0060 / 0.0054 / 0.0048");
  EXPECT_EQ(Find(tables_, "ate_statistics").rows[1][3], "failed");
  const report::Table& sweep = Find(tables_, "area_sweep");
  EXPECT_THAT(sweep.header, ElementsAre("sequence", "0.3", "0.4"));
  EXPECT_THAT(sweep.rows[0], ElementsAre("walking_xyz", "0.0080", "0.0060"));  // 0.4 is the plain hoid2d
  const report::Table& versus = Find(tables_, "hoid_2d_3d");
  EXPECT_THAT(versus.rows[0], ElementsAre("walking_xyz", "0.0060", "0.0060", "+0.0000"));
  EXPECT_THAT(versus.rows[1], ElementsAre("carry", "0.0060 (2/3)", "failed", "–"));
  for (const NamedTable& t : tables_) EXPECT_NE(t.name, "depth_sweep");  // none asked
}

TEST_F(BenchTables, AteMediansAreTheAteTablesNumbersAndNaNWhereItHasNone) {
  const std::vector<std::vector<double>> medians = AteMedians(plan_, results_);
  ASSERT_EQ(medians.size(), 3U);
  EXPECT_DOUBLE_EQ(medians[0][0], 0.102);  // walking_xyz none: median of 0.101, 0.102, 0.103
  EXPECT_DOUBLE_EQ(medians[1][1], 0.006);  // carry hoid2d: runs 1 and 3 finished
  EXPECT_TRUE(std::isnan(medians[1][2]));  // carry hoid3d: failed
  EXPECT_TRUE(std::isnan(medians[2][0]));  // missing sequence
}

TEST(BuildTables, RunsThatNeverTrackedSaySoInsteadOfANumber) {
  BenchOptions options;
  options.runs = 2;
  options.modes = {"classes"};
  options.area_sweep = {};
  options.depth_sweep = {};
  const Plan plan = MakePlan(options, {SyntheticSequence("carry")}, "/bin/hoidslam", "/b");
  RunResult never;  // finished, but the map never started: no trajectory, no ATE
  never.status = RunStatus::kOk;
  never.frames = 100;
  never.before_initialization = 100;
  const std::vector<NamedTable> tables = BuildTables(plan, {never, never});
  EXPECT_EQ(Find(tables, "ate").rows[0][1], "no pose");
  EXPECT_EQ(Find(tables, "lost").rows[0][1], "100");
}

// Real recordings: no ground-truth masks, so no exclusion quality; one of them without ground truth either.
TEST(BuildTables, WhatARealRecordingCannotBeScoredOnIsNotApplicable) {
  BenchOptions options;
  options.runs = 2;
  options.modes = {"none", "hoid2d"};
  options.area_sweep = {};
  options.depth_sweep = {};
  const auto real = [](double ate) {
    RunResult r = Ok(ate);
    r.leaked.reset();
    r.wasted.reset();
    return r;
  };
  RunResult unscored = real(0.0);
  unscored.ate_rmse.reset();
  unscored.ate_mean.reset();
  unscored.ate_median.reset();
  unscored.rpe_translation_rmse.reset();
  unscored.rpe_rotation_rmse.reset();
  const Plan plan = MakePlan(
      options, {SyntheticSequence("walking_xyz"), TumSequence("walking_halfsphere"), TumSequence("no_groundtruth")},
      "/bin/hoidslam", "/b");
  std::vector<RunResult> results;
  for (const RunSpec& spec : plan.runs) {
    const std::string& sequence = plan.sequences[spec.sequence].name;
    results.push_back(sequence == "walking_xyz" ? Ok(0.01) : sequence == "walking_halfsphere" ? real(0.02) : unscored);
  }
  const std::vector<NamedTable> tables = BuildTables(plan, results);
  EXPECT_THAT(Find(tables, "ate").rows[1], ElementsAre("walking_halfsphere", "0.0200", "0.0200"));
  EXPECT_THAT(Find(tables, "ate").rows[2], ElementsAre("no_groundtruth", "–", "–"));
  EXPECT_THAT(Find(tables, "ate_statistics").rows[2], ElementsAre("no_groundtruth", "–", "–"));
  EXPECT_THAT(Find(tables, "rpe_rotation").rows[2], ElementsAre("no_groundtruth", "–", "–"));
  for (const char* name : {"leaked", "wasted"}) {
    const report::Table& table = Find(tables, name);
    EXPECT_NE(table.rows[0][1], "–") << name;
    EXPECT_THAT(table.rows[1], ElementsAre("walking_halfsphere", "–", "–")) << name;
    EXPECT_THAT(table.rows[3], ElementsAre("median of the sequences", "–", "–")) << name;
  }
  EXPECT_THAT(Find(tables, "ate").note, ::testing::HasSubstr("no ground-truth masks"));

  // Only real recordings: no exclusion-quality tables at all, every other table still there.
  const Plan real_only = MakePlan(options, {TumSequence("walking_halfsphere")}, "/bin/hoidslam", "/b");
  const std::vector<NamedTable> real_tables =
      BuildTables(real_only, std::vector<RunResult>(real_only.runs.size(), real(0.02)));
  EXPECT_EQ(FindTable(real_tables, "leaked"), nullptr);
  EXPECT_EQ(FindTable(real_tables, "wasted"), nullptr);
  EXPECT_THAT(Find(real_tables, "ate").rows[0], ElementsAre("walking_halfsphere", "0.0200", "0.0200"));
  EXPECT_EQ(Find(real_tables, "timing").rows[0][7], "2");
}

TEST_F(BenchTables, FalseRelocalisationsAreSummedOverTheRunsNotTheirMedian) {
  const report::Table& table = Find(tables_, "relocalizations");
  EXPECT_THAT(table.header, ElementsAre("sequence", "none", "hoid2d", "hoid3d", "oracle"));
  // Run 3 of each cell relocalised twice, once wrongly; the median run none.
  EXPECT_THAT(table.rows[0], ElementsAre("walking_xyz", "1 of 2", "1 of 2", "1 of 2", "1 of 2"));
  EXPECT_THAT(table.rows[1], ElementsAre("carry", "1 of 2", "1 of 2 (2/3)", "failed", "1 of 2"));
  EXPECT_EQ(table.rows[2][1], "missing");
  EXPECT_TRUE(table.note.starts_with("Summed over the 3 runs of each cell")) << table.note;
}

TEST_F(BenchTables, RunsFarAboveTheirCellsMedianAreCountedAsJumps) {
  // walking_xyz with no filter: run 3 lost its map (1 m where the others have 0.101 and 0.102).
  std::vector<RunResult> results = results_;
  for (std::size_t i = 0; i < plan_.runs.size(); ++i) {
    const RunSpec& spec = plan_.runs[i];
    if (plan_.sequences[spec.sequence].name == "walking_xyz" && plan_.variants[spec.variant].Name() == "none" &&
        spec.run == 3) {
      results[i].ate_rmse = 1.0;
    }
  }
  const std::vector<NamedTable> tables = BuildTables(plan_, results);
  const report::Table& table = Find(tables, "jumps");
  EXPECT_THAT(table.rows[0], ElementsAre("walking_xyz", "1 of 3", "0 of 3", "0 of 3", "0 of 3"));
  EXPECT_THAT(table.rows[1], ElementsAre("carry", "0 of 3", "0 of 2 (2/3)", "failed", "0 of 3"));
  EXPECT_TRUE(table.note.starts_with("Of the 3 runs of each cell")) << table.note;
}

TEST_F(BenchTables, LostExclusionQualityAndTiming) {
  EXPECT_EQ(Find(tables_, "lost").rows[0][1], "0");  // median of 0, 0, 2
  EXPECT_EQ(Find(tables_, "leaked").rows[0][2], "10.0 %");
  EXPECT_EQ(Find(tables_, "wasted").rows[0][2], "20.0 %");
  const report::Table& timing = Find(tables_, "timing");
  EXPECT_THAT(timing.header, ElementsAre("mode", "load", "extract", "detect", "filter", "track", "tracking", "runs"));
  EXPECT_THAT(timing.rows[1], ElementsAre("hoid2d", "10.00", "4.00", "0.10", "0.01", "2.00", "6.00", "5"));
}

}  // namespace
}  // namespace hoidslam::bench
