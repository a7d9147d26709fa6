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
  // Beside each ATE the frames tracked: the median over the same runs (100, 100 and 98 of 100).
  EXPECT_THAT(ate.rows[0], ElementsAre("walking_xyz", "0.1020 (100/100 tracked)", "0.0060 (100/100 tracked)",
                                       "0.0060 (100/100 tracked)", "0.0060 (100/100 tracked)"));
  // Runs 1 and 3 of hoid2d finished: the median of 0.005 and 0.007, of 100 and 98 frames tracked.
  EXPECT_THAT(ate.rows[1], ElementsAre("carry", "0.1020 (100/100 tracked)", "0.0060 (99/100 tracked) (2/3)", "failed",
                                       "0.0060 (100/100 tracked)"));
  EXPECT_THAT(ate.rows[2], ElementsAre("gone", "missing", "missing", "missing", "missing"));
  EXPECT_EQ(ate.rows[3][0], "median of the sequences");
  EXPECT_EQ(ate.rows[3][1], "–");  // not every sequence has a number
  EXPECT_NE(ate.note.find("gone is missing: rendering failed"), std::string::npos);
}

TEST_F(BenchTables, StatisticsSweepsAndTwoAgainstThree) {
  EXPECT_EQ(Find(tables_, "ate_statistics").rows[0][2], "0.0060 / 0.0054 / 0.0048 (100/100 tracked)");
  EXPECT_EQ(Find(tables_, "ate_statistics").rows[1][3], "failed");
  const report::Table& sweep = Find(tables_, "area_sweep");
  EXPECT_THAT(sweep.header, ElementsAre("sequence", "0.3", "0.4"));
  EXPECT_THAT(sweep.rows[0], ElementsAre("walking_xyz", "0.0080 (100/100 tracked)",
                                         "0.0060 (100/100 tracked)"));  // 0.4 is the plain hoid2d
  const report::Table& versus = Find(tables_, "hoid_2d_3d");
  EXPECT_THAT(versus.rows[0],
              ElementsAre("walking_xyz", "0.0060 (100/100 tracked)", "0.0060 (100/100 tracked)", "+0.0000"));
  EXPECT_THAT(versus.rows[1], ElementsAre("carry", "0.0060 (99/100 tracked) (2/3)", "failed", "–"));
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
  EXPECT_THAT(Find(tables, "ate").rows[1],
              ElementsAre("walking_halfsphere", "0.0200 (100/100 tracked)", "0.0200 (100/100 tracked)"));
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
  EXPECT_THAT(Find(real_tables, "ate").rows[0],
              ElementsAre("walking_halfsphere", "0.0200 (100/100 tracked)", "0.0200 (100/100 tracked)"));
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

TEST_F(BenchTables, NoDenseTablesWithoutADenseMap) {
  for (const NamedTable& t : tables_) EXPECT_FALSE(t.name.starts_with("dense")) << t.name;
}

TEST_F(BenchTables, LostExclusionQualityAndTiming) {
  EXPECT_EQ(Find(tables_, "lost").rows[0][1], "0");  // median of 0, 0, 2
  EXPECT_EQ(Find(tables_, "leaked").rows[0][2], "10.0 %");
  EXPECT_EQ(Find(tables_, "wasted").rows[0][2], "20.0 %");
  const report::Table& timing = Find(tables_, "timing");
  EXPECT_THAT(timing.header, ElementsAre("mode", "load", "extract", "detect", "filter", "track", "tracking", "runs"));
  EXPECT_THAT(timing.rows[1], ElementsAre("hoid2d", "10.00", "4.00", "0.10", "0.01", "2.00", "6.00", "5"));
}


// A run of a sequence with returns: its ATE and frames tracked, one relocalisation (right), one loop (false when
// `false_loop`), two returns of which `recalled` were recalled, and one loop judged (confirmed unless false).
RunResult Returning(double ate, std::size_t tracked, bool false_loop, double recalled) {
  RunResult r = Ok(ate);
  r.tracked = tracked;
  r.relocalizations = 1.0;
  r.false_relocalizations = 0.0;
  r.loops = 1.0;
  r.false_loops = false_loop ? 1.0 : 0.0;
  r.merges = 0.0;
  r.false_merges = 0.0;
  r.return_events = 2.0;
  r.returns_recalled = recalled;
  r.closures_judged = 1.0;
  r.closures_confirmed = false_loop ? 0.0 : 1.0;
  return r;
}

TEST(BuildTables, RobustnessShowsTrackingTheAteSpreadFalseEventsAndPooledLoopRecall) {
  BenchOptions options;
  options.runs = 3;
  options.modes = {"none", "hoidplus"};
  options.area_sweep = {};
  options.depth_sweep = {};
  BenchSequence missing = SyntheticSequence("gone");
  missing.problem = "rendering failed";
  const Plan plan = MakePlan(options, {SyntheticSequence("loop"), TumSequence("no_groundtruth"), missing},
                             "/bin/hoidslam", "/b");
  std::vector<RunResult> results;
  for (const RunSpec& spec : plan.runs) {
    const std::string& sequence = plan.sequences[spec.sequence].name;
    const std::string& mode = plan.variants[spec.variant].mode;
    if (sequence == "no_groundtruth") {
      RunResult r = Ok(0.0);
      r.ate_rmse.reset();
      r.relocalizations.reset();
      r.false_relocalizations.reset();
      results.push_back(r);
    } else if (mode == "none") {
      // Run 3 jumped (4 times the median) and closed its loop wrongly; run 2 lost 3 frames.
      const double ates[] = {0.010, 0.012, 0.040};
      const std::size_t tracked[] = {100, 97, 100};
      const double recalled[] = {1.0, 2.0, 0.0};
      results.push_back(Returning(ates[spec.run - 1], tracked[spec.run - 1], spec.run == 3, recalled[spec.run - 1]));
    } else if (spec.run == 2) {
      results.push_back(Failed());
    } else {
      // Nothing to recall and nothing closed: neither share is 100 %.
      RunResult r = Returning(0.01, 100, false, 0.0);
      r.return_events = 0.0;
      r.loops = 0.0;
      r.false_loops = 0.0;
      r.closures_judged = 0.0;
      r.closures_confirmed = 0.0;
      results.push_back(r);
    }
  }
  const std::vector<NamedTable> tables = BuildTables(plan, results);
  const report::Table& table = Find(tables, "robustness");
  EXPECT_THAT(table.header, ElementsAre("sequence", "mode", "runs", "tracked % (median)", "tracked % (min)",
                                        "ATE median (m)", "ATE max / median", "false relocalisations", "false loops",
                                        "false merges", "loop recall", "loop precision"));
  ASSERT_EQ(table.rows.size(), 6U);
  EXPECT_THAT(table.rows[0], ElementsAre("loop", "none", "3", "100.0 %", "97.0 %", "0.0120", "3.33", "0 of 3", "1 of 3",
                                         "0 of 0", "50 % (3 of 6)", "67 % (2 of 3)"));
  EXPECT_THAT(table.rows[1], ElementsAre("loop", "hoidplus", "2 of 3", "100.0 %", "100.0 %", "0.0100", "1.00", "0 of 2",
                                         "0 of 0", "0 of 0", "no return", "no loop"));
  EXPECT_THAT(table.rows[2],
              ElementsAre("no_groundtruth", "none", "3", "100.0 %", "100.0 %", "–", "–", "–", "–", "–", "–", "–"));
  EXPECT_EQ(table.rows[4][0], "gone");
  EXPECT_EQ(table.rows[4][2], "missing");
  EXPECT_EQ(table.rows[4].size(), table.header.size());
  EXPECT_THAT(table.note, ::testing::HasSubstr("gone is missing: rendering failed"));
}

TEST(BuildTables, TheRandomSequencesHaveADistributionOfTheirOwn) {
  BenchOptions options;
  options.runs = 3;
  options.modes = {"hoidplus"};
  options.area_sweep = {};
  options.depth_sweep = {};
  const auto random = [](std::uint64_t seed) {
    BenchSequence sequence = SyntheticSequence("random-" + std::to_string(seed));
    sequence.scenario.clear();
    sequence.random_seed = seed;
    return sequence;
  };
  const Plan plan = MakePlan(options, {random(1), random(2), SyntheticSequence("carry")}, "/bin/hoidslam", "/b");
  std::vector<RunResult> results;
  for (const RunSpec& spec : plan.runs) {
    const std::size_t k = spec.run - 1;
    RunResult r = Ok(1.0);  // carry: not a random sequence, left out of the distribution
    r.relocalizations = r.false_relocalizations = 0.0;
    if (plan.sequences[spec.sequence].name == "random-1") {
      // The lens covered for 10 of the 100 frames; run 2 tracked 89 of the other 90 (under 99 %); run 3 jumped.
      r = Returning(std::vector{0.010, 0.011, 0.050}[k], std::vector<std::size_t>{90, 89, 90}[k], false, 0.0);
      r.covered = 10;
      r.relocalizations = r.false_relocalizations = 0.0;
      r.return_events = 1.0;
      r.returns_recalled = 1.0;
    } else if (plan.sequences[spec.sequence].name == "random-2") {
      // No return, no loop; run 3 tracked 98 of 100.
      r = Ok(std::vector{0.020, 0.022, 0.024}[k], k == 2 ? 2 : 0);
      r.relocalizations = r.false_relocalizations = r.loops = r.false_loops = r.merges = r.false_merges = 0.0;
      r.return_events = r.returns_recalled = r.closures_judged = r.closures_confirmed = 0.0;
    }
    results.push_back(r);
  }
  const std::vector<NamedTable> tables = BuildTables(plan, results);
  const report::Table& table = Find(tables, "random");
  EXPECT_EQ(table.title, "Over 2 random sequences: the distribution of the runs");
  EXPECT_THAT(table.header, ElementsAre("measure", "hoidplus"));
  std::vector<std::string> cells;
  for (const std::vector<std::string>& row : table.rows) cells.push_back(row[0] + ": " + row[1]);
  EXPECT_THAT(cells, ElementsAre("runs finished: 6 of 6",
                                 // 0.90, 0.89, 0.90, 1.00, 1.00, 0.98 of the frames
                                 "tracked % (median / min): 94.0 % / 89.0 %",
                                 "runs tracking under 99 % of the uncovered frames: 2 of 6",
                                 // 0.010, 0.011, 0.020, 0.022, 0.024, 0.050: between the 5th and 6th
                                 "ATE RMSE median / 90th percentile (m): 0.0210 / 0.0370",
                                 "runs above 3× their sequence's median ATE: 1 of 6",
                                 "false relocalisations: 0 of 0", "false loops: 0 of 3", "false merges: 0 of 0",
                                 "loop recall: 100 % (3 of 3)", "loop precision: 100 % (3 of 3)"));
  // Without random sequences there is no such table.
  const Plan shipped = MakePlan(options, {SyntheticSequence("carry")}, "/bin/hoidslam", "/b");
  EXPECT_EQ(FindTable(BuildTables(shipped, std::vector<RunResult>(shipped.runs.size(), Ok(0.01))), "random"), nullptr);
}

// A run with --dense: its map's cost and size, and its score against the sequence's geometry unless `ghost_area` is
// absent (a real recording).
RunResult Dense(double fuse_ms, double build_seconds, std::optional<double> ghost_area = std::nullopt,
                double accuracy = 0.0, double completeness = 0.0, double ghost_cells = 0.0) {
  RunResult r = Ok(0.01);
  r.dense_area = 11.0;
  r.dense_volume_mb = 48.0;
  r.dense_fuse_ms = fuse_ms;
  r.dense_build_seconds = build_seconds;
  r.dense_people_kept = 0.01 * build_seconds;
  if (!ghost_area) return r;
  r.dense_ghost_area = *ghost_area;
  r.dense_ghost_share = *ghost_area / 11.0;
  r.dense_accuracy_median = accuracy;
  r.dense_accuracy_p90 = 3.0 * accuracy;
  r.dense_completeness = completeness;
  r.dense_occupied_cells = 2000.0;
  r.dense_ghost_cells = ghost_cells;
  return r;
}

TEST(BuildTables, DenseTablesShowEachCellsMediansAndTheRatiosToNoneAndOracle) {
  BenchOptions options;
  options.runs = 3;
  options.modes = {"none", "hoidplus", "oracle"};
  options.area_sweep = options.depth_sweep = {};
  options.dense = true;
  // walking_xyz carries its geometry; fr3_walking is a real recording: its dense maps are not scored, and it has
  // no oracle.
  const Plan plan = MakePlan(options, {SyntheticSequence("walking_xyz"), TumSequence("fr3_walking")}, "/bin/hoidslam",
                             "/b");
  std::vector<RunResult> results;
  for (const RunSpec& spec : plan.runs) {
    const std::size_t k = spec.run - 1;
    const std::string& mode = plan.variants[spec.variant].mode;
    if (plan.sequences[spec.sequence].name == "fr3_walking") {
      if (mode == "hoidplus" && spec.run == 2) {
        results.push_back(Failed());
      } else {
        results.push_back(Dense(std::vector{16.0, 15.0, 14.0}[k], std::vector{1.7, 1.6, 1.5}[k]));
      }
    } else if (mode == "none") {
      results.push_back(Dense(20.0, 2.0, std::vector{1.2, 1.0, 1.1}[k], 0.010, 0.85, std::vector{40.0, 50.0, 60.0}[k]));
    } else if (mode == "hoidplus") {
      // Run 2 fused a person: the median is the others'.
      results.push_back(Dense(22.0, 2.2, std::vector{0.11, 0.44, 0.10}[k], std::vector{0.006, 0.009, 0.005}[k], 0.88,
                              std::vector{3.0, 9.0, 2.0}[k]));
    } else {
      results.push_back(Dense(21.0, 2.1, std::vector{0.05, 0.06, 0.07}[k], 0.005, 0.90, 1.0));
    }
  }
  const std::vector<NamedTable> tables = BuildTables(plan, results);

  const report::Table& ghost = Find(tables, "dense_ghost_area");
  EXPECT_THAT(ghost.header, ElementsAre("sequence", "none", "hoidplus", "oracle"));
  EXPECT_THAT(ghost.rows, ElementsAre(ElementsAre("walking_xyz", "1.100 / 10.0 %", "0.110 / 1.0 %", "0.060 / 0.5 %"),
                                      ElementsAre("fr3_walking", "–", "–", "–"),
                                      ElementsAre("median of the sequences", "–", "–", "–")));
  EXPECT_THAT(ghost.title, ::testing::HasSubstr("farther than 5 cm"));
  EXPECT_THAT(ghost.note, ::testing::HasSubstr("static_geometry.ply"));
  EXPECT_THAT(Find(tables, "dense_accuracy").rows[0], ElementsAre("walking_xyz", "10.0 / 30.0", "6.0 / 18.0", "5.0 / 15.0"));
  EXPECT_THAT(Find(tables, "dense_completeness").rows[0], ElementsAre("walking_xyz", "85.0 %", "88.0 %", "90.0 %"));
  EXPECT_THAT(Find(tables, "dense_ghost_cells").rows[0],
              ElementsAre("walking_xyz", "50 of 2000", "3 of 2000", "1 of 2000"));

  const report::Table& against = Find(tables, "dense_against");
  EXPECT_THAT(against.header, ElementsAre("sequence", "mode", "ghost surface / none's", "ghost surface / oracle's",
                                          "accuracy / oracle's", "completeness / oracle's"));
  EXPECT_THAT(against.rows,
              ElementsAre(ElementsAre("walking_xyz", "none", "1.00×", "18.33×", "2.00×", "0.94×"),
                          ElementsAre("walking_xyz", "hoidplus", "0.10×", "1.83×", "1.20×", "0.98×"),
                          ElementsAre("walking_xyz", "oracle", "0.05×", "1.00×", "1.00×", "1.00×"),
                          ElementsAre("fr3_walking", "none", "–", "–", "–", "–"),
                          ElementsAre("fr3_walking", "hoidplus", "–", "–", "–", "–")));

  // What the map cost, on every sequence.
  const report::Table& time = Find(tables, "dense_time");
  EXPECT_THAT(time.rows, ElementsAre(ElementsAre("walking_xyz", "20.0 / 2.0", "22.0 / 2.2", "21.0 / 2.1"),
                                     ElementsAre("fr3_walking", "15.0 / 1.6", "15.0 / 1.6 (2/3)", "–"),
                                     ElementsAre("median of the sequences", "17.5 / 1.8", "18.5 / 1.9", "–")));
  EXPECT_THAT(Find(tables, "dense_size").rows[1], ElementsAre("fr3_walking", "11.0 / 48.0", "11.0 / 48.0 (2/3)", "–"));
  // The people kept, judged in the person boxes: on the real recording too.
  EXPECT_THAT(Find(tables, "dense_people").rows[1], ElementsAre("fr3_walking", "1.6 %", "1.6 % (2/3)", "–"));

  // Dense maps of real recordings only: what they cost, nothing scored.
  const Plan real = MakePlan(options, {TumSequence("fr3_walking")}, "/bin/hoidslam", "/b");
  const std::vector<NamedTable> real_tables = BuildTables(real, std::vector<RunResult>(real.runs.size(), Dense(15, 1.5)));
  EXPECT_NE(FindTable(real_tables, "dense_time"), nullptr);
  EXPECT_NE(FindTable(real_tables, "dense_size"), nullptr);
  EXPECT_NE(FindTable(real_tables, "dense_people"), nullptr);
  for (const char* name : {"dense_ghost_area", "dense_accuracy", "dense_completeness", "dense_against",
                           "dense_ghost_cells"}) {
    EXPECT_EQ(FindTable(real_tables, name), nullptr) << name;
  }
}

}  // namespace
}  // namespace hoidslam::bench
