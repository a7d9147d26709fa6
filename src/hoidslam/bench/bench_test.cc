#include "hoidslam/bench/bench.h"

#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::bench {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(ResolveSequenceFolder, ANameThatIsNoFolderHereIsASharedRecording) {
  const testing::TempDir scratch;
  const fs::path shared = scratch / "shared";
  fs::create_directories(shared / "data" / "tum" / "fr1_rpy");
  fs::create_directories(scratch / "local" / "fr1_rpy");
  EXPECT_EQ(ResolveSequenceFolder("fr1_rpy", shared), shared / "data" / "tum" / "fr1_rpy");
  // A folder that exists as given is that folder; a missing path or unknown name stays as given.
  const fs::path local = scratch / "local" / "fr1_rpy";
  EXPECT_EQ(ResolveSequenceFolder(local.string(), shared), local);
  EXPECT_EQ(ResolveSequenceFolder("elsewhere/fr1_rpy", shared), fs::path("elsewhere/fr1_rpy"));
  EXPECT_EQ(ResolveSequenceFolder("fr2_desk", shared), fs::path("fr2_desk"));
}

TEST(WriteBenchPlan, RandomSequencesAreRenderedBySynthRandomAndRunLikeTheScenarios) {
  const testing::TempDir scratch;
  BenchRequest request;
  request.options.runs = 2;
  request.options.modes = {"hoidplus"};
  request.options.area_sweep = request.options.depth_sweep = {};
  request.options.random_duration = 30;
  request.options.textures = "/shared/data/textures";
  request.scenarios = {"carry"};
  request.random = 2;
  request.random_seed = 7;
  request.folder = scratch / "bench";
  request.binary = "/bin/hoidslam";
  const Plan plan = WriteBenchPlan(request);
  ASSERT_EQ(plan.sequences.size(), 3U);
  EXPECT_EQ(plan.sequences[1].name, "random-7");
  EXPECT_EQ(plan.sequences[2].name, "random-8");
  EXPECT_EQ(plan.sequences[2].random_seed, 8U);
  EXPECT_EQ(plan.sequences[2].path, scratch / "bench" / "sequences" / "random-8-d30");
  EXPECT_EQ(plan.runs.size(), 6U);
  const fs::path rendered = scratch / "bench" / "sequences" / "random-7-d30";
  EXPECT_THAT(plan.PrepareCommand(plan.sequences[1]),
              ElementsAre("/bin/hoidslam", "synth", "--random", "7", "--random-duration", "30", "--textures",
                          "/shared/data/textures", "--out", rendered.string()));
  // With the shipped scenarios' settings: run's defaults (TUM fr3), no settings file.
  for (const RunSpec& spec : plan.runs) {
    EXPECT_THAT(plan.RunCommand(spec), ::testing::Not(::testing::Contains("--settings")));
  }
  EXPECT_EQ(plan.RunCommand(plan.runs[2])[2], rendered.string());
  const std::string prepare = testing::ReadText(scratch / "bench" / "prepare.txt");
  EXPECT_THAT(prepare, HasSubstr("synth --random 8 --random-duration 30"));
  EXPECT_THAT(prepare, HasSubstr("synth --scenario carry"));
  const Plan back =
      PlanFromJson(nlohmann::json::parse(testing::ReadText(scratch / "bench" / "plan.json")), "plan.json");
  EXPECT_EQ(back.sequences[2].random_seed, 8U);
  EXPECT_EQ(back.sequences[0].random_seed, std::nullopt);
  EXPECT_EQ(back.PrepareCommand(back.sequences[2]), plan.PrepareCommand(plan.sequences[2]));
}

}  // namespace
}  // namespace hoidslam::bench
