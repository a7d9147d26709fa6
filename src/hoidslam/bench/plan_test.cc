#include "hoidslam/bench/plan.h"

#include <algorithm>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hoidslam/bench/test_sequences.h"
#include "hoidslam/core/error.h"

namespace hoidslam::bench {
namespace {

using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::vector<std::string> VariantNames(const Plan& plan) {
  std::vector<std::string> names;
  for (const Variant& v : plan.variants) names.push_back(v.Name());
  return names;
}

std::size_t RunsOf(const Plan& plan, const std::string& sequence, const std::string& variant) {
  return static_cast<std::size_t>(std::count_if(plan.runs.begin(), plan.runs.end(), [&](const RunSpec& r) {
    return plan.sequences[r.sequence].name == sequence && plan.variants[r.variant].Name() == variant;
  }));
}

TEST(MakePlan, ModesThenSweepValuesNotAlreadyMeasuredByThePlainRuns) {
  BenchOptions options;
  options.runs = 2;
  const Plan plan = MakePlan(options, {SyntheticSequence("walking_xyz")}, "/bin/hoidslam", "/b");
  EXPECT_THAT(VariantNames(plan),
              ElementsAre("none", "person", "classes", "hoid2d", "hoid3d", "oracle", "hoid2d area=0.2",
                          "hoid2d area=0.3", "hoid2d area=0.5", "hoid3d depth=0.1", "hoid3d depth=0.3",
                          "hoid3d depth=0.5"));
  EXPECT_EQ(plan.runs.size(), 12U * 2U);
  EXPECT_EQ(plan.runs[0].id, "walking_xyz.none.r1");
  EXPECT_EQ(plan.runs[13].id, "walking_xyz.hoid2d-area0.2.r2");
  // The sweep's 0.4 is the plain hoid2d run; 0.3 its own variant.
  EXPECT_EQ(plan.SweepVariant("hoid2d", 0.4, true, plan.sequences[0]), 3U);
  EXPECT_EQ(plan.SweepVariant("hoid2d", 0.3, true, plan.sequences[0]), 7U);
  EXPECT_EQ(plan.SweepVariant("hoid3d", 0.7, false, plan.sequences[0]), std::nullopt);
}

TEST(MakePlan, SweepsCanHaveFewerRuns) {
  BenchOptions options;
  options.runs = 5;
  options.sweep_runs = 2;
  options.modes = {"hoid2d"};
  options.area_sweep = {0.3};
  options.depth_sweep = {};
  const Plan plan = MakePlan(options, {SyntheticSequence("carry")}, "/bin/hoidslam", "/b");
  EXPECT_EQ(RunsOf(plan, "carry", "hoid2d"), 5U);
  EXPECT_EQ(RunsOf(plan, "carry", "hoid2d area=0.3"), 2U);
}

TEST(MakePlan, OracleOnlyWhereMasksExistAndNothingForABrokenSequence) {
  BenchOptions options;
  options.runs = 1;
  options.area_sweep = {};
  options.depth_sweep = {};
  BenchSequence broken = TumSequence("broken");
  broken.problem = "rgb.txt: not found";
  const Plan plan = MakePlan(options, {TumSequence("fr3_walking_xyz"), SyntheticSequence("carry"), broken}, "/bin/hoidslam", "/b");
  EXPECT_EQ(RunsOf(plan, "fr3_walking_xyz", "oracle"), 0U);
  EXPECT_EQ(RunsOf(plan, "fr3_walking_xyz", "hoid2d"), 1U);
  EXPECT_EQ(RunsOf(plan, "carry", "oracle"), 1U);
  EXPECT_EQ(RunsOf(plan, "broken", "none"), 0U);
  EXPECT_EQ(plan.runs.size(), 5U + 6U);
}

TEST(MakePlan, ASettingThatDiffersFromTheSweepValueGetsItsOwnRuns) {
  BenchOptions options;
  options.runs = 1;
  options.modes = {"hoid2d"};
  options.area_sweep = {0.3, 0.4};
  options.depth_sweep = {};
  BenchSequence own = TumSequence("own");
  own.min_interaction_area = 0.3;  // its settings file says 0.3: the plain run measures 0.3, so 0.4 needs runs
  const Plan plan = MakePlan(options, {own}, "/bin/hoidslam", "/b");
  EXPECT_THAT(VariantNames(plan), ElementsAre("hoid2d", "hoid2d area=0.4"));
  EXPECT_EQ(plan.SweepVariant("hoid2d", 0.3, true, plan.sequences[0]), 0U);
  EXPECT_EQ(plan.SweepVariant("hoid2d", 0.4, true, plan.sequences[0]), 1U);
}

TEST(MakePlan, RejectsBadOptionsNamingTheParameter) {
  BenchOptions options;
  options.modes = {"hoid2d", "everything"};
  EXPECT_THROW(
      {
        try {
          MakePlan(options, {}, "/bin/hoidslam", "/b");
        } catch (const core::InputError& e) {
          EXPECT_THAT(e.what(), HasSubstr("--modes"));
          EXPECT_THAT(e.what(), HasSubstr("everything"));
          throw;
        }
      },
      core::InputError);
  options = {};
  options.area_sweep = {0.0};
  EXPECT_THROW(MakePlan(options, {}, "/bin/hoidslam", "/b"), core::InputError);
  options = {};
  options.runs = 0;
  EXPECT_THROW(MakePlan(options, {}, "/bin/hoidslam", "/b"), core::InputError);
}

TEST(MakePlan, HoidPlusPartsAreModesOfTheirOwn) {
  BenchOptions options;
  options.modes = {"hoid2d", "hoidplus", "hoidplus:depth+memory"};
  options.runs = 1;
  options.area_sweep = options.depth_sweep = {};
  const Plan plan = MakePlan(options, {SyntheticSequence("walking_xyz")}, "/bin/hoidslam", "/b");
  ASSERT_EQ(plan.variants.size(), 3U);
  EXPECT_EQ(plan.variants[2].Name(), "hoidplus:depth+memory");
  EXPECT_EQ(plan.variants[2].Slug(), "hoidplus-depth-memory");
  ASSERT_EQ(plan.runs.size(), 3U);
  EXPECT_EQ(plan.runs[2].id, "walking_xyz.hoidplus-depth-memory.r1");
  EXPECT_THAT(plan.RunCommand(plan.runs[2]), Contains("hoidplus:depth+memory"));
  options.modes = {"hoidplus:legs"};
  EXPECT_THROW(MakePlan(options, {}, "/bin/hoidslam", "/b"), core::InputError);
}

TEST(Plan, RunCommandCarriesEverythingTheRunNeeds) {
  BenchOptions options;
  options.runs = 2;
  options.modes = {"hoid3d"};
  options.area_sweep = {};
  options.depth_sweep = {0.3};
  options.frames = 100;
  options.deterministic = true;
  const Plan plan = MakePlan(options, {TumSequence("fr3")}, "/bin/hoidslam", "/b");
  ASSERT_EQ(plan.runs.size(), 4U);
  EXPECT_THAT(plan.RunCommand(plan.runs[0]),
              ElementsAre("/bin/hoidslam", "run", "/data/fr3", "--filter", "hoid3d", "--out", "/b/runs/fr3.hoid3d.r1",
                          "--force", "--settings", "/cfg/TUM3.yaml", "--frames", "100", "--deterministic",
                          "--snapshots", "6"));
  const std::vector<std::string> swept = plan.RunCommand(plan.runs[3]);
  EXPECT_THAT(swept, ::testing::Contains("--depth-threshold"));
  EXPECT_THAT(swept, ::testing::Contains("0.3"));
  EXPECT_EQ(swept.back(), "0");  // snapshots only in the first run
  EXPECT_TRUE(plan.PrepareCommand(plan.sequences[0]).empty());

  options.deterministic = false;
  options.realtime = options.pace = true;
  options.detector_latency_ms = 40;
  const std::vector<std::string> live = MakePlan(options, {TumSequence("fr3")}, "/bin/hoidslam", "/b").RunCommand(plan.runs[0]);
  EXPECT_THAT(std::vector(live.begin() + 10, live.end()),
              ElementsAre("--frames", "100", "--realtime", "--pace", "--detector-latency", "40", "--snapshots", "6"));
}

TEST(Plan, DenseGoesIntoEveryRunCommandAndThePlanFile) {
  BenchOptions options;
  options.runs = 2;
  options.modes = {"none", "hoidplus", "oracle"};
  options.area_sweep = {0.3};
  options.depth_sweep = {};
  options.dense = true;
  const Plan plan = MakePlan(options, {SyntheticSequence("walking_xyz")}, "/bin/hoidslam", "/b");
  ASSERT_EQ(plan.runs.size(), 4U * 2U);  // the sweep's runs too
  for (const RunSpec& spec : plan.runs) EXPECT_THAT(plan.RunCommand(spec), Contains("--dense")) << spec.id;

  nlohmann::json json = PlanToJson(plan);
  EXPECT_EQ(json["options"]["dense"], true);
  const Plan back = PlanFromJson(json, "plan.json");
  EXPECT_TRUE(back.options.dense);
  EXPECT_EQ(back.RunCommand(back.runs[7]), plan.RunCommand(plan.runs[7]));
  // A plan written before dense maps existed: runs without.
  json["options"].erase("dense");
  const Plan older = PlanFromJson(json, "plan.json");
  EXPECT_FALSE(older.options.dense);
  EXPECT_THAT(older.RunCommand(older.runs[0]), ::testing::Not(Contains("--dense")));
}

TEST(Plan, PrepareCommandRendersTheScenario) {
  BenchOptions options;
  options.synth_frames = 300;
  options.synth_frame_step = 2;
  const Plan plan = MakePlan(options, {SyntheticSequence("carry")}, "/bin/hoidslam", "/b");
  EXPECT_THAT(plan.PrepareCommand(plan.sequences[0]),
              ElementsAre("/bin/hoidslam", "synth", "--scenario", "carry", "--out", "/b/sequences/carry", "--frames",
                          "300", "--frame-step", "2"));
}

TEST(Plan, PrepareCommandRendersARandomSequenceWithTheSharedTextures) {
  BenchOptions options;
  options.synth_frames = 300;
  options.random_duration = 45.5;
  options.textures = "/shared/data/textures";
  BenchSequence random = SyntheticSequence("random-3");
  random.scenario.clear();
  random.random_seed = 3;
  const Plan plan = MakePlan(options, {random}, "/bin/hoidslam", "/b");
  EXPECT_TRUE(plan.sequences[0].Rendered());
  EXPECT_THAT(plan.PrepareCommand(plan.sequences[0]),
              ElementsAre("/bin/hoidslam", "synth", "--random", "3", "--random-duration", "45.5", "--textures",
                          "/shared/data/textures", "--out", "/b/sequences/random-3", "--frames", "300"));
  options = {};
  options.random_duration = -1;
  EXPECT_THROW(MakePlan(options, {random}, "/bin/hoidslam", "/b"), core::InputError);
}

TEST(Plan, JsonRoundTripKeepsEveryRunAndCommand) {
  BenchOptions options;
  options.runs = 3;
  options.model = "";
  options.realtime = true;
  options.detector_latency_ms = 80;
  BenchSequence broken = TumSequence("broken");
  broken.problem = "gone";
  const Plan plan = MakePlan(options, {SyntheticSequence("walking_xyz"), TumSequence("fr3"), broken}, "/bin/hoidslam", "/b");
  const Plan back = PlanFromJson(nlohmann::json::parse(PlanToJson(plan).dump()), "plan.json");
  ASSERT_EQ(back.runs.size(), plan.runs.size());
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    EXPECT_EQ(back.RunCommand(back.runs[i]), plan.RunCommand(plan.runs[i]));
    EXPECT_EQ(back.runs[i].id, plan.runs[i].id);
  }
  EXPECT_EQ(back.sequences[2].problem, "gone");
  EXPECT_EQ(VariantNames(back), VariantNames(plan));
}

TEST(PlanFromJson, NamesTheFileWhenItIsNotAPlan) {
  try {
    PlanFromJson(nlohmann::json{{"runs", 3}}, "/b/plan.json");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/b/plan.json"));
  }
}

TEST(ShellCommand, QuotesWhatTheShellWouldSplitOrExpand) {
  EXPECT_EQ(ShellCommand({"/bin/hoidslam", "run", "/a b/seq", "--filter", "hoid2d", "it's", "$HOME", "0.3"}),
            "/bin/hoidslam run '/a b/seq' --filter hoid2d 'it'\\''s' '$HOME' 0.3");
  EXPECT_EQ(ShellCommand({""}), "''");
}

}  // namespace
}  // namespace hoidslam::bench
