// End-to-end tests of `hoidslam bench`: the direct bench, the same sweep planned and run through GNU parallel,
// resuming, and failures that must show as failures, never as numbers.
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "hoidslam/core/sanitizers.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::apps {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// The sweep's walking_xyz: every third of its first 120 frames (people come into view at about the 100th), or
// under a sanitizer (see ThinnedUnderSanitizers) every ninth of its first 180, and the folder the bench renders it
// into.
const Stretch kSweep = kSanitized ? Stretch{20, 9} : Stretch{40, 3};
const std::string kSynthFrames = std::to_string(kSweep.frames * kSweep.step);
const std::string kSynthStep = std::to_string(kSweep.step);
const std::string kSequenceFolder = "walking_xyz-f" + kSynthFrames + "-s" + kSynthStep;
// Runs of each mode: two, whose median the tables show; one under a sanitizer, where each run costs most.
const int kRuns = kSanitized ? 1 : 2;

// A small sweep: two modes and one extra interaction area, kRuns runs each, in the deterministic mode so that two
// benches must agree to the last digit.
std::vector<std::string> SmallSweep(const fs::path& sequences, const fs::path& out) {
  return {"bench", "--scenarios", "walking_xyz", "--synth-frames", kSynthFrames, "--synth-frame-step", kSynthStep,
          "--modes", "none,hoid2d", "--runs", std::to_string(kRuns), "--area-sweep", "0.3,0.4",
          "--depth-sweep", "none", "--deterministic", "--jobs", "2", "--sequences-dir", sequences.string(),
          "--out", out.string()};
}

nlohmann::json Results(const fs::path& bench) { return nlohmann::json::parse(testing::ReadText(bench / "results.json")); }

// The tables without the one that measures time, which differs from run to run by nature.
nlohmann::json TablesWithoutTiming(const nlohmann::json& results) {
  nlohmann::json tables = nlohmann::json::array();
  for (const nlohmann::json& table : results["tables"]) {
    if (table["name"] != "timing") tables.push_back(table);
  }
  return tables;
}

const nlohmann::json& Table(const nlohmann::json& results, const std::string& name) {
  for (const nlohmann::json& table : results["tables"]) {
    if (table["name"] == name) return table;
  }
  throw std::runtime_error("no table " + name);
}

TEST(CliBench, APlannedSweepRunThroughGnuParallelGivesTheDirectBenchsTables) {
  const testing::TempDir scratch;
  const fs::path sequences = scratch / "sequences";

  // Planned: nothing runs yet; GNU parallel renders the scenario, then runs the jobs; --collect builds the tables.
  std::vector<std::string> plan_args = SmallSweep(sequences, scratch / "planned");
  plan_args.push_back("--plan");
  const RunResult plan = RunHoidslam(scratch, plan_args);
  ASSERT_EQ(plan.exit_status, 0) << plan.err;
  EXPECT_FALSE(fs::exists(sequences / kSequenceFolder));
  const std::string jobs = testing::ReadText(scratch / "planned" / "jobs.txt");
  EXPECT_EQ(std::count(jobs.begin(), jobs.end(), '\n'), 3 * kRuns);  // (none, hoid2d, hoid2d area=0.3) × runs
  // The one scenario is rendered as task 1 of a Slurm array would render it, the runs by GNU parallel.
  const RunResult render = RunProgram(scratch, {"env", "SLURM_ARRAY_TASK_ID=1", "bash", HOIDSLAM_SCRIPTS_DIR
                                                "/bench-slurm.sbatch", (scratch / "planned" / "prepare.txt").string()});
  ASSERT_EQ(render.exit_status, 0) << render.err;
  EXPECT_TRUE(fs::exists(sequences / kSequenceFolder / "rgb.txt"));
  const RunResult parallel = RunProgram(scratch, {HOIDSLAM_PARALLEL, "--will-cite", "--halt", "now,fail=1", "-j", "2",
                                                  "-a", (scratch / "planned" / "jobs.txt").string()});
  ASSERT_EQ(parallel.exit_status, 0) << parallel.err;
  const RunResult collect = RunHoidslam(scratch, {"bench", "--collect", "--out", (scratch / "planned").string()});
  ASSERT_EQ(collect.exit_status, 0) << collect.err;
  EXPECT_THAT(collect.out, HasSubstr("| walking_xyz |"));

  // Direct, on the sequence rendered above.
  const RunResult direct = RunHoidslam(scratch, SmallSweep(sequences, scratch / "direct"));
  ASSERT_EQ(direct.exit_status, 0) << direct.err;
  const std::string runs = std::to_string(3 * kRuns);
  EXPECT_THAT(direct.err, HasSubstr(runs + " runs planned, " + runs + " to run"));

  const nlohmann::json planned = Results(scratch / "planned");
  const nlohmann::json direct_results = Results(scratch / "direct");
  EXPECT_EQ(TablesWithoutTiming(planned), TablesWithoutTiming(direct_results));
  // And the tables hold real numbers: every run finished with an ATE, people leak into `none` only.
  for (const nlohmann::json& run : direct_results["runs"]) {
    EXPECT_EQ(run["status"], "ok") << run.dump();
    EXPECT_GT(run["ate_rmse"].get<double>(), 0.0) << run.dump();
    if (!kSanitized) {
      EXPECT_LT(run["ate_rmse"].get<double>(), 0.05) << run.dump();
    }
  }
  // Beside the ATE, the frames tracked; and the robustness of each sequence and mode over its runs.
  const std::string tracked = std::to_string(kSweep.frames) + "/" + std::to_string(kSweep.frames) + " tracked)";
  EXPECT_THAT(Table(direct_results, "ate")["rows"][0][1].get<std::string>(), ::testing::EndsWith(tracked));
  const nlohmann::json& robustness = Table(direct_results, "robustness");
  ASSERT_EQ(robustness["rows"].size(), 2U);
  EXPECT_EQ(robustness["rows"][1][0], "walking_xyz");
  EXPECT_EQ(robustness["rows"][1][1], "hoid2d");
  EXPECT_EQ(robustness["rows"][1][2], std::to_string(kRuns));
  EXPECT_EQ(robustness["rows"][1][7], "0 of 0");      // no relocalisation
  EXPECT_EQ(robustness["rows"][1][10], "no return");  // a few seconds of walk: nothing to come back to
  const nlohmann::json& leaked = Table(direct_results, "leaked");
  EXPECT_EQ(leaked["header"], (nlohmann::json{"sequence", "none", "hoid2d"}));
  EXPECT_EQ(leaked["rows"][0][1], "100.0 %");
  EXPECT_EQ(Table(direct_results, "area_sweep")["rows"][0][2], Table(direct_results, "ate")["rows"][0][2]);
  for (const char* file : {"tables.md", "tables/ate.csv", "tables/area_sweep.csv", "plan.json",
                           "runs/walking_xyz.hoid2d.r1/report.html"}) {
    EXPECT_TRUE(fs::exists(scratch / "direct" / file)) << file;
  }
  // The bench's page: the ATE chart, every table, and the trajectories of none and hoid2d over the ground truth.
  const std::string page = testing::ReadText(scratch / "direct" / "report.html");
  EXPECT_THAT(page, HasSubstr("ATE RMSE (m) per filter mode"));
  EXPECT_THAT(page, HasSubstr("Exclusion quality"));
  EXPECT_THAT(page, HasSubstr("Robustness over the runs"));
  EXPECT_THAT(page, HasSubstr("walking_xyz hoid2d"));
  EXPECT_NE(page.find("<svg"), std::string::npos);
}

TEST(CliBench, FailuresAreRecordedAsFailuresAndResumeRunsOnlyWhatIsLeft) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", {30, 4});
  const fs::path bench = scratch / "bench";
  const std::vector<std::string> base = {"bench", sequence.string(), (scratch / "no_such_sequence").string(),
                                         "--modes", "none", "--area-sweep", "none", "--depth-sweep", "none",
                                         "--out", bench.string()};

  // A time limit nobody can meet: the run is recorded as failed, and the missing folder as missing.
  std::vector<std::string> args = base;
  args.insert(args.end(), {"--runs", "1", "--timeout", "0.05"});
  const RunResult timed_out = RunHoidslam(scratch, args);
  ASSERT_EQ(timed_out.exit_status, 0) << timed_out.err;
  EXPECT_THAT(timed_out.err, HasSubstr("no_such_sequence: left out"));
  EXPECT_THAT(timed_out.out, HasSubstr("| walking_xyz | failed |"));
  EXPECT_THAT(timed_out.out, HasSubstr("| no_such_sequence | missing |"));
  EXPECT_THAT(testing::ReadText(bench / "runs" / "walking_xyz.none.r1.log"), HasSubstr("timed out"));

  // The same folder again without --resume or --force: one error line naming --out, nothing touched.
  ExpectOneErrorLine(RunHoidslam(scratch, args), "--resume");

  // Resumed with two runs and time enough: the failed run and the new one run, and both finish.
  args = base;
  args.insert(args.end(), {"--runs", "2", "--resume"});
  const RunResult resumed = RunHoidslam(scratch, args);
  ASSERT_EQ(resumed.exit_status, 0) << resumed.err;
  EXPECT_THAT(resumed.err, HasSubstr("2 runs planned, 2 to run"));
  const RunResult again = RunHoidslam(scratch, args);
  ASSERT_EQ(again.exit_status, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("2 runs planned, 0 to run"));
  EXPECT_THAT(again.out, ::testing::ContainsRegex("\\| walking_xyz \\| 0\\.0[0-9]{3} \\([0-9]+/30 tracked\\) \\|"));
}

// The shared real recording by its name, with the fr1 camera, and random sequences rendered by `synth --random`:
// planned only, nothing runs.
TEST(CliBench, ANamedRecordingAndRandomSequencesArePlannedLikeTheOthers) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(recording, "data/tum/fr1_rpy");
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  const testing::TempDir scratch;
  const fs::path bench = scratch / "bench";
  const RunResult plan = RunHoidslam(scratch, {"bench", "fr1_rpy", "--random", "2", "--seed", "5", "--random-duration",
                                               "20", "--modes", "none,hoidplus", "--model", model.string(), "--runs",
                                               "1", "--area-sweep", "none", "--depth-sweep", "none", "--plan", "--out",
                                               bench.string()});
  ASSERT_EQ(plan.exit_status, 0) << plan.err;
  const nlohmann::json planned = nlohmann::json::parse(testing::ReadText(bench / "plan.json"));
  ASSERT_EQ(planned["sequences"].size(), 3U);
  EXPECT_EQ(planned["sequences"][0]["name"], "random-5");
  EXPECT_EQ(planned["sequences"][1]["name"], "random-6");
  EXPECT_EQ(planned["sequences"][2]["name"], "fr1_rpy");
  EXPECT_EQ(fs::canonical(planned["sequences"][2]["path"].get<std::string>()), fs::canonical(recording));
  EXPECT_EQ(fs::path(planned["sequences"][2]["settings"].get<std::string>()).filename(), "TUM1.yaml");
  EXPECT_EQ(planned["sequences"][2]["problem"], "");

  const std::string prepare = testing::ReadText(bench / "prepare.txt");
  EXPECT_THAT(prepare, HasSubstr("synth --random 5 --random-duration 20"));
  EXPECT_THAT(prepare, HasSubstr("synth --random 6 --random-duration 20"));
  if (fs::is_directory(testing::SharedPath("data/textures"))) {
    EXPECT_THAT(prepare, HasSubstr("--textures"));
  }
  // The recording has no detections file: hoidplus runs the detector on it; the random sequences bring their own.
  std::istringstream jobs(testing::ReadText(bench / "jobs.txt"));
  int count = 0;
  for (std::string job; std::getline(jobs, job); ++count) {
    const bool detector = job.find("fr1_rpy.hoidplus") != std::string::npos;
    EXPECT_EQ(job.find("--model") != std::string::npos, detector) << job;
  }
  EXPECT_EQ(count, 6);
}

// `bench --dense`: --help says it, and every planned run makes a dense map.
TEST(CliBench, DenseIsInTheHelpAndInEveryPlannedRun) {
  const testing::TempDir scratch;
  const RunResult help = RunHoidslam(scratch, {"bench", "--help"});
  ASSERT_EQ(help.exit_status, 0) << help.err;
  EXPECT_THAT(help.out, HasSubstr("--dense"));
  const fs::path bench = scratch / "bench";
  const RunResult plan = RunHoidslam(scratch, {"bench", "--scenarios", "walking_xyz", "--modes", "none,hoidplus",
                                               "--runs", "2", "--area-sweep", "none", "--depth-sweep", "none",
                                               "--dense", "--plan", "--out", bench.string()});
  ASSERT_EQ(plan.exit_status, 0) << plan.err;
  EXPECT_EQ(nlohmann::json::parse(testing::ReadText(bench / "plan.json"))["options"]["dense"], true);
  std::istringstream jobs(testing::ReadText(bench / "jobs.txt"));
  int count = 0;
  for (std::string job; std::getline(jobs, job); ++count) EXPECT_THAT(job, HasSubstr(" --dense ")) << job;
  EXPECT_EQ(count, 4);
}

// The demo on a short stretch of its scenario: several runs of each mode, the medians with the frames tracked, a
// sentence on what they show and a verdict on the default, and where to watch a run live.
TEST(CliDemo, PrintsEachModesMedianBesideTheFramesTrackedAndSaysWhatItShows) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  const testing::TempDir scratch;
  const RunResult demo = RunHoidslam(scratch, {"demo", "--frames", "30", "--frame-step", "6", "--runs", "2",
                                               "--jobs", "2", "--out", (scratch / "demo").string()});
  ASSERT_EQ(demo.exit_status, 0) << demo.err;
  EXPECT_THAT(demo.out, HasSubstr("| crowd | "));
  EXPECT_THAT(demo.out, HasSubstr("/30 tracked)"));
  EXPECT_THAT(demo.out, HasSubstr("What you are looking at: in crowd, people walk up to the camera"));
  EXPECT_THAT(demo.out, ::testing::ContainsRegex("Without a filter, .* [0-9.]+ mm with [0-9]+ of 30 frames tracked "
                                                 "\\(median of 2 runs\\)"));
  EXPECT_THAT(demo.out, ::testing::ContainsRegex("The default is (the most accurate|within the spread)|Here the "
                                                 "default is not the most accurate"));
  EXPECT_THAT(demo.out, HasSubstr("Watch it live: "));
  EXPECT_TRUE(fs::exists(scratch / "demo" / "report.html"));
}

}  // namespace
}  // namespace hoidslam::apps
