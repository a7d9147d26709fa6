// End-to-end tests of what run, report, masks and bench write on sequences as users have them: a real recording
// has no ground-truth masks of the moving pixels (mask/), no people masks (people/) and, with a detector model,
// no detections file. Every file a command names is there and complete, and nothing is a warning.
#include <algorithm>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_test_support.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::apps::outputs_cli_test {
namespace {

namespace fs = std::filesystem;
using ::hoidslam::testing::ReadText;
using ::testing::HasSubstr;
using ::testing::Not;

// Runs hoidslam, expects it to succeed without a warning, and returns what it printed.
RunResult Succeed(const testing::TempDir& scratch, const std::vector<std::string>& args) {
  const RunResult result = RunHoidslam(scratch, args);
  EXPECT_EQ(result.exit_status, 0) << args.front() << ": " << result.err;
  EXPECT_THAT(result.err, Not(HasSubstr("warning"))) << args.front();
  return result;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The names listed by the closing line `wrote <folder>/ (a, b, ...)` of a command's output, checked to name
// `folder`; a folder's name ends in '/'.
std::vector<std::string> NamesWritten(const std::string& output, const fs::path& folder) {
  const std::vector<std::string> lines = Lines(output);
  const auto closing = std::find_if(lines.rbegin(), lines.rend(), [](const std::string& l) {
    return l.starts_with("wrote ");
  });
  if (closing == lines.rend()) {
    ADD_FAILURE() << "no closing 'wrote' line in:\n" << output;
    return {};
  }
  const std::string prefix = "wrote " + folder.string() + "/ (";
  EXPECT_THAT(*closing, ::testing::StartsWith(prefix));
  EXPECT_TRUE(closing->ends_with(")")) << *closing;
  std::vector<std::string> names;
  std::istringstream list(closing->substr(prefix.size(), closing->size() - prefix.size() - 1));
  for (std::string name; std::getline(list >> std::ws, name, ',');) names.push_back(name);
  return names;
}

// The entries of `folder`, a folder's name ending in '/'.
std::set<std::string> Entries(const fs::path& folder) {
  std::set<std::string> entries;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    entries.insert(entry.path().filename().string() + (entry.is_directory() ? "/" : ""));
  }
  return entries;
}

// Non-empty lines that are not comments.
std::vector<std::string> DataLines(const fs::path& file) {
  std::vector<std::string> lines;
  for (const std::string& line : Lines(ReadText(file))) {
    if (!line.empty() && !line.starts_with("#")) lines.push_back(line);
  }
  return lines;
}

// A TUM trajectory file of `poses` lines `timestamp tx ty tz qx qy qz qw`.
void ExpectTrajectory(const fs::path& file, std::size_t poses) {
  const std::vector<std::string> lines = DataLines(file);
  EXPECT_EQ(lines.size(), poses) << file;
  for (const std::string& line : lines) {
    std::istringstream in(line);
    double value = 0.0;
    int values = 0;
    while (in >> value) ++values;
    EXPECT_TRUE(in.eof() && values == 8) << file << ": " << line;
  }
}

// A binary PLY of `points` vertices, each three floats and three bytes of colour, and nothing after them.
void ExpectMap(const fs::path& file, std::size_t points) {
  const std::string ply = ReadText(file);
  const std::string end = "end_header\n";
  const std::size_t body = ply.find(end);
  ASSERT_NE(body, std::string::npos) << file;
  EXPECT_THAT(ply.substr(0, body), HasSubstr("\nelement vertex " + std::to_string(points) + "\n"));
  EXPECT_EQ(ply.size() - body - end.size(), points * 15) << file;
}

// A page written to the end.
void ExpectPage(const fs::path& html) {
  const std::string page = ReadText(html);
  EXPECT_TRUE(page.starts_with("<!DOCTYPE html>")) << html;
  EXPECT_TRUE(page.ends_with("</html>\n")) << html;
}

// A folder of `hoidslam run` on a sequence without ground-truth masks, as `output` (what run printed) names it.
void ExpectCompleteRun(const fs::path& folder, const std::string& output) {
  const std::vector<std::string> written = NamesWritten(output, folder);
  EXPECT_EQ(std::set<std::string>(written.begin(), written.end()), Entries(folder));
  EXPECT_THAT(written, ::testing::IsSupersetOf({"trajectory.txt", "keyframes.txt", "map.ply", "frames.jsonl",
                                               "summary.json", "report.html"}));

  const nlohmann::json summary = Summary(folder);
  EXPECT_TRUE(summary.at("exclusion_quality").is_null());
  const std::vector<std::string> frames = Lines(ReadText(folder / "frames.jsonl"));
  ASSERT_EQ(frames.size(), summary.at("frames").get<std::size_t>());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const nlohmann::json frame = nlohmann::json::parse(frames[i]);
    EXPECT_EQ(frame.at("frame"), i);
    EXPECT_TRUE(frame.at("features").is_object());
    EXPECT_FALSE(frame.contains("exclusion")) << frames[i];
  }
  ExpectTrajectory(folder / "trajectory.txt", summary.at("tracked").get<std::size_t>());
  ExpectTrajectory(folder / "keyframes.txt", summary.at("keyframes").get<std::size_t>());
  ExpectMap(folder / "map.ply", summary.at("map_points").get<std::size_t>());
  if (fs::is_directory(folder / "snapshots")) {
    for (const fs::directory_entry& snapshot : fs::directory_iterator(folder / "snapshots")) {
      const std::string jpeg = ReadText(snapshot.path());
      EXPECT_TRUE(jpeg.starts_with("\xFF\xD8\xFF") && jpeg.ends_with("\xFF\xD9")) << snapshot.path();
    }
  }
  ExpectPage(folder / "report.html");
  EXPECT_THAT(ReadText(folder / "report.html"), HasSubstr("no ground-truth masks"));
}

// A mask folder of `frames` masks of 640 × 480, listed in masks.txt, and nothing else.
void ExpectCompleteMasks(const fs::path& folder, std::size_t frames) {
  const std::vector<std::string> listed = DataLines(folder / "masks.txt");
  ASSERT_EQ(listed.size(), frames);
  std::set<std::string> expected = {"masks.txt"};
  for (const std::string& line : listed) {
    const std::string file = line.substr(line.find(' ') + 1);
    expected.insert(file);
    const cv::Mat mask = cv::imread((folder / file).string(), cv::IMREAD_UNCHANGED);
    EXPECT_EQ(mask.type(), CV_8UC1) << file;
    EXPECT_EQ(mask.size(), cv::Size(640, 480)) << file;
  }
  EXPECT_EQ(Entries(folder), expected);
}

// A bench folder as `output` (what bench printed) names it: every run finished, complete and without a warning,
// no exclusion-quality tables and a page that says why.
nlohmann::json ExpectCompleteBench(const fs::path& folder, const std::string& output, std::size_t runs) {
  std::vector<std::string> written = NamesWritten(output, folder);
  EXPECT_THAT(written, ::testing::ElementsAre("tables.md", "tables/*.csv", "results.json", "report.html", "runs/"));
  std::replace(written.begin(), written.end(), std::string("tables/*.csv"), std::string("tables/"));
  for (const std::string& name : written) EXPECT_TRUE(fs::exists(folder / name)) << name;
  EXPECT_TRUE(fs::exists(folder / "tables" / "ate.csv"));

  const nlohmann::json results = nlohmann::json::parse(ReadText(folder / "results.json"));
  EXPECT_EQ(results.at("runs").size(), runs);
  for (const nlohmann::json& run : results.at("runs")) {
    EXPECT_EQ(run.at("status"), "ok") << run.dump();
    EXPECT_TRUE(run.at("leaked").is_null()) << run.dump();
    const fs::path run_folder = folder / "runs" / run.at("id").get<std::string>();
    const std::string log = ReadText(run_folder.string() + ".log");
    EXPECT_THAT(log, Not(HasSubstr("warning"))) << run_folder;
    ExpectCompleteRun(run_folder, log);
  }
  for (const nlohmann::json& table : results.at("tables")) {
    EXPECT_NE(table.at("name"), "leaked");
    EXPECT_NE(table.at("name"), "wasted");
  }
  ExpectPage(folder / "report.html");
  const std::string page = ReadText(folder / "report.html");
  EXPECT_THAT(page, HasSubstr("<h2>Exclusion quality</h2>"));
  EXPECT_THAT(page, HasSubstr("Not scored: none of the sequences has ground-truth masks"));
  EXPECT_THAT(page, HasSubstr("<h2>Annotated frames</h2>"));
  return results;
}

const nlohmann::json& AteRow(const nlohmann::json& results) {
  for (const nlohmann::json& table : results.at("tables")) {
    if (table.at("name") == "ate") return table.at("rows").at(0);
  }
  throw std::runtime_error("no ate table");
}

// The real TUM fr3/walking_xyz frames of the shared data, with the detector model, through every command.
TEST(CliOutputs, ARealTumRecordingGetsCompleteOutputsAndAReportThatOpensInABrowser) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(pair, "data/tum/fr3_walking_xyz_pair");
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  const testing::TempDir scratch;
  // The folder as a TUM download is named (bench picks TUM3.yaml by it), without its groundtruth.txt: two frames
  // 3 s apart give at most two poses, and ATE needs three, so their evaluation could only warn.
  const fs::path sequence = scratch / "rgbd_dataset_freiburg3_walking_xyz";
  fs::create_directories(sequence);
  for (const char* entry : {"rgb", "depth", "rgb.txt", "depth.txt", "associations.txt"}) {
    fs::copy(pair / entry, sequence / entry, fs::copy_options::recursive);
  }

  const fs::path run = scratch / "run";
  const RunResult ran = Succeed(scratch, {"run", sequence.string(), "--settings", HOIDSLAM_CONFIG_DIR "/TUM3.yaml",
                                         "--model", model.string(), "--out", run.string()});
  ExpectCompleteRun(run, ran.out);
  EXPECT_EQ(Summary(run).at("detector"), "yolox_nano.onnx");
  EXPECT_GT(Summary(run).at("keypoints_dropped").get<int>(), 0);  // the people in these frames

  fs::remove(run / "report.html");
  const RunResult reported = Succeed(scratch, {"report", run.string()});
  EXPECT_EQ(reported.out, "wrote " + (run / "report.html").string() + " (no ground truth)\n");
  ExpectCompleteRun(run, ran.out);

  const fs::path masks = scratch / "masks";
  const RunResult masked = Succeed(scratch, {"masks", sequence.string(), "--model", model.string(), "--out",
                                             masks.string()});
  EXPECT_THAT(masked.out, HasSubstr("rgbd_dataset_freiburg3_walking_xyz: 2 masks (hoidplus, format hoidslam)"));
  ExpectCompleteMasks(masks, 2);

  const fs::path bench = scratch / "bench";
  const RunResult benched =
      Succeed(scratch, {"bench", sequence.string(), "--model", model.string(), "--modes", "none,hoid2d", "--runs",
                        "1", "--area-sweep", "none", "--depth-sweep", "none", "--jobs", "2", "--out", bench.string()});
  const nlohmann::json results = ExpectCompleteBench(bench, benched.out, 2);
  // No ground truth: nothing to score ATE against either.
  EXPECT_EQ(AteRow(results), (nlohmann::json{"rgbd_dataset_freiburg3_walking_xyz", "–", "–"}));

  // The run's page in a real browser: a rendered page, not a blank.
  const cv::Mat shot = ChromiumScreenshot(scratch, run / "report.html", {1280, 1600});
  ASSERT_FALSE(shot.empty());
  cv::Scalar mean, deviation;
  cv::meanStdDev(shot, mean, deviation);
  EXPECT_GT(deviation[0], 20.0);
}

// A synthetic sequence with its ground-truth masks taken away: ground truth of the camera and a detections file,
// as a recording whose boxes were detected beforehand.
TEST(CliOutputs, ASyntheticSequenceWithoutMasksGetsCompleteOutputs) {
  const testing::TempDir scratch;
  const fs::path sequence = Render(scratch, "walking_xyz", ThinnedUnderSanitizers({24, 3}));
  const std::size_t frames = DataLines(sequence / "rgb.txt").size();

  // Without people masks only: exclusion quality is scored, on still people it is not.
  fs::remove_all(sequence / "people");
  const fs::path scored = scratch / "scored";
  Succeed(scratch, {"run", sequence.string(), "--no-final-adjustment", "--out", scored.string()});
  EXPECT_EQ(Summary(scored).at("final_adjustment_ms"), 0.0);
  EXPECT_TRUE(Summary(scored).at("exclusion_quality").at("leaked").is_number());
  EXPECT_TRUE(Summary(scored).at("exclusion_quality").at("static_dropped_on_still_people").is_null());
  EXPECT_THAT(ReadText(scored / "report.html"), HasSubstr("leaked:"));

  fs::remove_all(sequence / "mask");
  const fs::path run = scratch / "run";
  const RunResult ran = Succeed(scratch, {"run", sequence.string(), "--snapshots", "0", "--out", run.string()});
  ExpectCompleteRun(run, ran.out);
  EXPECT_FALSE(fs::exists(run / "snapshots"));  // and so not named by the closing line
  EXPECT_EQ(Summary(run).at("frames"), frames);
  EXPECT_GT(Summary(run).at("final_adjustment_ms").get<double>(), 0.0);  // the map is adjusted at the end by default
  EXPECT_TRUE(Summary(run).at("evaluation").is_object());
  EXPECT_EQ(Summary(run).at("evaluation").at("relocalizations").at("false"), 0);  // every frame tracked in turn
  // A walk of a few seconds comes back to nothing and closes no loop: neither share is a number, let alone 100 %.
  const nlohmann::json loop_recall = Summary(run).at("evaluation").at("loop_recall");
  EXPECT_EQ(loop_recall.at("events"), 0);
  EXPECT_TRUE(loop_recall.at("recall").is_null());
  EXPECT_TRUE(loop_recall.at("precision").is_null());
  EXPECT_EQ(loop_recall.at("options").at("min_separation_s"), 10.0);
  EXPECT_THAT(ran.out, HasSubstr("loop recall: undefined, no return to an earlier place; precision undefined, no "
                                 "loops to judge"));

  const RunResult reported = Succeed(scratch, {"report", run.string()});
  EXPECT_THAT(reported.out, HasSubstr("(ground truth " + (sequence / "groundtruth.txt").string() + ")"));
  ExpectCompleteRun(run, ran.out);
  EXPECT_THAT(ReadText(run / "report.html"), HasSubstr("ATE over time"));

  const fs::path masks = scratch / "masks";
  Succeed(scratch, {"masks", sequence.string(), "--format", "stella", "--out", masks.string()});
  ExpectCompleteMasks(masks, frames);

  // oracle is planned only where there are masks: here its column is not applicable.
  const fs::path bench = scratch / "bench";
  const RunResult benched = Succeed(scratch, {"bench", sequence.string(), "--modes", "none,hoid2d,oracle", "--runs",
                                              "1", "--area-sweep", "none", "--depth-sweep", "none", "--jobs", "2",
                                              "--out", bench.string()});
  const nlohmann::json results = ExpectCompleteBench(bench, benched.out, 2);
  const nlohmann::json& ate = AteRow(results);
  ASSERT_EQ(ate.size(), 4U);
  // The ATE with the frames tracked beside it.
  const std::string cell = "0\\.[0-9]{4} \\([0-9]+/" + std::to_string(frames) + " tracked\\)";
  EXPECT_THAT(ate[1].get<std::string>(), ::testing::MatchesRegex(cell));
  EXPECT_THAT(ate[2].get<std::string>(), ::testing::MatchesRegex(cell));
  EXPECT_EQ(ate[3], "–");
  EXPECT_THAT(ReadText(bench / "report.html"), HasSubstr("<h2>Trajectories</h2>"));
}

}  // namespace
}  // namespace hoidslam::apps::outputs_cli_test
