// End-to-end tests of `hoidslam run --dense`: the dense outputs of a run a user opens elsewhere, the dense map in the
// viewer and the report, and bad options refused before the run. Threaded tests: the dense mapper prepares keyframes
// in its own thread while tracking goes.
#include <algorithm>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "cli_test_support.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::apps {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

std::size_t DataLineCount(const fs::path& file) {
  const std::string text = testing::ReadText(file);
  std::size_t lines = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    if (end > start && text[start] != '#') ++lines;
    start = end + 1;
  }
  return lines;
}

TEST(CliDense, ARunWritesTheStaticWorldAsAMeshACloudAndOccupancyMaps) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", ThinnedUnderSanitizers({45, 2}));
  const fs::path run = scratch / "run";
  const RunResult ran = RunHoidslam(scratch, {"run", sequence.string(), "--dense", "--out", run.string()});
  ASSERT_EQ(ran.exit_status, 0) << ran.err;
  EXPECT_THAT(ran.out, HasSubstr("mesh.ply, cloud.ply, occupancy.bt, occupancy.pgm, occupancy.yaml"));
  EXPECT_THAT(ran.out, HasSubstr("dense: "));
  EXPECT_THAT(ran.err, ::testing::Not(HasSubstr("Writing"))) << "no library chatter on stderr";

  const nlohmann::json dense = Summary(run).at("dense");
  EXPECT_TRUE(dense.at("written").get<bool>());
  // Every keyframe of the final map was handed over and fused.
  EXPECT_EQ(dense.at("keyframes").get<std::size_t>(), DataLineCount(run / "keyframes.txt"));
  EXPECT_EQ(dense.at("keyframes_without_images"), 0);
  EXPECT_GT(dense.at("mesh").at("triangles").get<std::size_t>(), 10000U);
  // The office's desks, walls and floor the camera sees in three seconds: a few square metres, not a few hundred.
  EXPECT_GT(dense.at("mesh").at("area_m2").get<double>(), 2.0);
  EXPECT_LT(dense.at("mesh").at("area_m2").get<double>(), 40.0);
  EXPECT_TRUE(dense.at("floor_found").get<bool>());
  EXPECT_EQ(dense.at("options").at("voxel_size"), 0.01);

  // The 2D grid as map_server reads it: a trinary image and the YAML naming it with its resolution.
  const std::string yaml = testing::ReadText(run / "occupancy.yaml");
  EXPECT_THAT(yaml, HasSubstr("image: occupancy.pgm"));
  EXPECT_THAT(yaml, HasSubstr("resolution: 0.05"));
  EXPECT_THAT(yaml, HasSubstr("mode: trinary"));
  const cv::Mat grid = cv::imread((run / "occupancy.pgm").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(grid.type(), CV_8UC1);
  EXPECT_GT(cv::countNonZero(grid == 0), 20) << "occupied cells: the desks and walls";
  EXPECT_GT(cv::countNonZero(grid == 254), 20) << "free cells between the camera and them";
}

// The dense map in a browser, live and in the report: web/tests/viewer_test.mjs runs `run --dense --view
// --view-keep` and checks that the page draws the live preview as it grows, then the dense map once built, within
// the budget, and that its legend's box hides and shows it; then it opens the run's report.html, which must draw as
// many triangles as it embeds.
TEST(CliDense, TheViewerAndTheReportShowTheDenseMap) {
  const testing::TempDir scratch;
  // Long enough a run for the preview to be shown (every second) after the page has opened.
  const fs::path sequence = Render(scratch, "walking_xyz", ThinnedUnderSanitizers({120, 2}));
  const fs::path run = scratch / "run";
  const RunResult live = RunPageTest(
      scratch, {"--hoidslam", HOIDSLAM_BINARY, "--out", run.string(), "--live-dense", "--", sequence.string(), "--dense"});
  EXPECT_EQ(live.exit_status, 0) << live.out << live.err;
  EXPECT_THAT(live.out, HasSubstr("ok: the page drew dense maps of "));
  EXPECT_THAT(live.out, HasSubstr("ok: stat-dense = "));
  EXPECT_THAT(live.out, HasSubstr("ok: the legend's box hides and shows the dense map"));

  const std::string html = testing::ReadText(run / "report.html");
  EXPECT_THAT(html, HasSubstr("The dense map of mesh.ply with it"));
  const RunResult report = RunPageTest(scratch, {"--report", (run / "report.html").string(), "--out", run.string()});
  EXPECT_EQ(report.exit_status, 0) << report.out << report.err;
  EXPECT_THAT(report.out, HasSubstr("ok: stat-dense against the embedded dense map"));
  EXPECT_THAT(report.out, HasSubstr("report test passed"));
}

TEST(CliDense, ModeNoneIsCheckedForPeopleInTheBoxesOfTheSequencesDetectionsAndKeepsWhatWasSeenThroughWhenAsked) {
  // Mode none judges no boxes, yet the sequence's detections.jsonl gives its keyframes theirs for the check, and the
  // people it fused are found there (the people come in at frame 98). How the filter's maps fare: DenseMapper's
  // tests and bench --dense.
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", {36, 4});
  const fs::path run = scratch / "run";
  const RunResult ran =
      RunHoidslam(scratch, {"run", sequence.string(), "--dense", "--filter", "none", "--out", run.string()});
  ASSERT_EQ(ran.exit_status, 0) << ran.err;
  EXPECT_THAT(ran.out, HasSubstr("people kept: "));
  const nlohmann::json people = Summary(run).at("dense").at("people");
  ASSERT_TRUE(people.is_object());
  EXPECT_GT(people.at("boxes").get<std::size_t>(), 0U);
  EXPECT_GT(people.at("share").get<double>(), 0.3);
  // Where later keyframes saw through a person fused earlier, the person is left out of the mesh, and kept when asked.
  EXPECT_GT(Summary(run).at("dense").at("mesh").at("seen_through_vertices").get<std::size_t>(), 0U);

  const fs::path kept = scratch / "kept";
  const RunResult keeping = RunHoidslam(scratch, {"run", sequence.string(), "--dense", "--filter", "none",
                                                  "--dense-keep-seen-through", "--out", kept.string()});
  ASSERT_EQ(keeping.exit_status, 0) << keeping.err;
  const nlohmann::json dense = Summary(kept).at("dense");
  EXPECT_EQ(dense.at("options").at("keep_seen_through"), true);
  EXPECT_EQ(dense.at("mesh").at("seen_through_vertices"), 0);
}

TEST(CliDense, BadOptionsAreRefusedBeforeTheRun) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", {3, 1});
  const auto run = [&](std::vector<std::string> options) {
    std::vector<std::string> args = {"run", sequence.string(), "--out", (scratch / "run").string()};
    args.insert(args.end(), options.begin(), options.end());
    return RunHoidslam(scratch, args);
  };
  ExpectOneErrorLine(run({"--dense", "--dense-voxel", "0"}), "--dense-voxel");
  ExpectOneErrorLine(run({"--dense", "--dense-voxel", "0.001"}), "--dense-memory-mb");  // 1 mm: ~100 GB a room
  ExpectOneErrorLine(run({"--dense", "--occupancy-band", "1.8:0.1"}), "--occupancy-band");
  ExpectOneErrorLine(run({"--dense", "--occupancy-band", "low:high"}), "--occupancy-band");
  ExpectOneErrorLine(run({"--dense", "--dense-truncation", "0.01"}), "--dense-truncation");
  const RunResult without = run({"--dense-voxel", "0.02"});
  EXPECT_EQ(without.exit_status, 1);
  EXPECT_THAT(without.err, HasSubstr("--dense"));
  EXPECT_FALSE(fs::exists(scratch / "run")) << "nothing written for a run that did not start";
}

}  // namespace
}  // namespace hoidslam::apps
