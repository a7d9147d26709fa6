#include "hoidslam/report/html_report.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/report/test_markup.h"
#include "support/input_error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::report {
namespace {

namespace fs = std::filesystem;
using ::hoidslam::testing::InputErrorOf;
using ::hoidslam::testing::ReadText;
using ::hoidslam::testing::TempDir;
using ::hoidslam::testing::WriteText;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A stand-in for the viewer's page (web/): what the report inlines, it inlines as it is.
const ViewerBundle kViewer{
    .script = "window.drawn = 1 < 2 && 3 > 2;", .style = ".hoidslam-viewer > h1 { color: red; }", .missing = ""};

// The JSON of the page's embedded data, as the browser reads it.
nlohmann::json EmbeddedData(const std::string& html) {
  const std::string start = R"(<script id="hoidslam-data" type="application/json">)";
  const std::size_t begin = html.find(start);
  if (begin == std::string::npos) return nullptr;
  const std::size_t end = html.find("</script>", begin);
  return nlohmann::json::parse(html.substr(begin + start.size(), end - begin - start.size()));
}

// The camera position of frame i of the hand-written run (frames 0.5 s apart, frame 3 lost).
Eigen::Vector3d Position(int i) { return {0.3 * i, 0.2 * std::sin(i), 0.1 * i * i}; }
double Stamp(int i) { return 100.0 + 0.5 * i; }

// The ground-truth world: the estimate's frame turned 90 degrees about z and moved.
Eigen::Vector3d ToGroundTruth(const Eigen::Vector3d& p) {
  return Eigen::Vector3d(-p.y(), p.x(), p.z()) + Eigen::Vector3d(1, 2, 3);
}

constexpr std::string_view kSummary = R"({"sequence": "tiny", "filter": "hoid2d", "detector": "detections.jsonl",
  "frames": 6, "tracked": 5, "lost": 1, "before_initialization": 0, "keyframes": 2, "map_points": 321,
  "detector_failures": 0, "keypoints_extracted": 6000, "keypoints_dropped": 1200, "interrupted": false,
  "provenance": {"settings": {"values": {"Camera.fx": 500.0, "Camera.fy": 501.0, "Camera.cx": 319.5,
                                         "Camera.cy": 239.5, "Camera.width": 640, "Camera.height": 480}}},
  "median_ms": {"load": 12.5, "extract": 3.4, "detect": 0.0, "filter": 0.006, "track": 3.2, "tracking_total": 6.6},
  "exclusion_quality": {"leaked": 0.25, "wasted": 0.02, "moving_kept": 100, "moving_dropped": 300,
                        "static_kept": 4410, "static_dropped": 90}})";

// The main map of the hand-written run: three points, and two keyframes (frames 0 and 4).
const std::vector<io::ColoredPoint> kMapPoints = {
    {{0.12344, -1.5, 2.0}, {10, 20, 30}}, {{1.0, 0.25, 3.00006}, {255, 0, 128}}, {{-2.0, 0.0, 4.5}, {1, 2, 3}}};
constexpr std::string_view kKeyframes = "100.000000 0 0 0 0 0 0 1\n102.000000 1.2 0.2 1.6 0 0 0 1\n";

// A folder as `hoidslam run` writes it, six frames, with one snapshot; returns the ground-truth file beside it.
fs::path WriteRunFolder(const fs::path& folder) {
  fs::create_directories(folder / "snapshots");
  WriteText(folder / "summary.json", std::string(kSummary));
  std::string frames, trajectory = "# timestamp tx ty tz qx qy qz qw\n", groundtruth;
  for (int i = 0; i < 6; ++i) {
    const bool lost = i == 3;
    const std::string dynamic =
        i == 2 ? R"([{"label": "person", "score": 0.9, "box": [10, 10, 50, 100], "reason": "person"},
                     {"label": "cup", "score": 0.8, "box": [40, 50, 10, 10], "reason": "interaction", "person": 0,
                      "interaction": 0.62}])"
               : "[]";
    std::string line = fmt::format(
        R"({{"frame": {}, "timestamp": {:.6f}, "state": "{}", "method": "{}", "keyframe": {}, )"
        R"("features": {{"extracted": 1000, "dropped": {}, {}"matched": 300, "inliers": {}}}, "dynamic": {}, )"
        R"("exclusion": {{"moving_kept": 10, "moving_dropped": 50, "static_kept": 735, "static_dropped": 15}}, )"
        R"("detections": {{"frame": {}, "age_frames": {}, "age_ms": {}}}, {})"
        R"("ms": {{"load": 12.0, "extract": 3.0, "detect": 0.0, "filter": 0.01, "track": 3.0}}}})",
        i, Stamp(i), lost ? "lost" : "ok", lost ? "none" : "motion_model", i == 0 ? "true" : "false", 200 + i,
        i == 1 ? R"("kept": 990, )" : "",  // a second extraction's; the other frames are as older logs have them
        lost ? 0 : 250, dynamic, i / 2 * 2, i % 2, i % 2 * 33.3, i == 4 ? R"("dropped_before": 1, )" : "");
    std::erase(line, '\n');
    frames += line + "\n";
    if (!lost) {
      const Eigen::Vector3d p = Position(i);
      trajectory += fmt::format("{:.6f} {} {} {} 0 0 0 1\n", Stamp(i), p.x(), p.y(), p.z());
    }
  }
  // Ground truth from 0.5 s before the first frame to 0.5 s after the last, as a recording has.
  for (int i = -1; i <= 6; ++i) {
    const Eigen::Vector3d p = ToGroundTruth(Position(i));
    groundtruth += fmt::format("{:.6f} {} {} {} 0 0 0.7071067811865476 0.7071067811865476\n", Stamp(i), p.x(), p.y(),
                               p.z());
  }
  WriteText(folder / "frames.jsonl", frames);
  WriteText(folder / "trajectory.txt", trajectory);
  io::WritePly(folder / "map.ply", kMapPoints);
  WriteText(folder / "keyframes.txt", std::string(kKeyframes));
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", cv::Mat(24, 32, CV_8UC3, cv::Scalar(30, 200, 30)), jpeg);
  WriteText(folder / "snapshots" / "000002.jpg", std::string(jpeg.begin(), jpeg.end()));
  WriteText(folder / "snapshots" / "notes.txt", "not a snapshot");
  const fs::path groundtruth_file = folder.parent_path() / "groundtruth.txt";
  WriteText(groundtruth_file, groundtruth);
  return groundtruth_file;
}

TEST(Base64Encode, MatchesTheRfc4648TestVectors) {
  EXPECT_EQ(Base64Encode(""), "");
  EXPECT_EQ(Base64Encode("f"), "Zg==");
  EXPECT_EQ(Base64Encode("fo"), "Zm8=");
  EXPECT_EQ(Base64Encode("foo"), "Zm9v");
  EXPECT_EQ(Base64Encode("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64Encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64Encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode(std::string("\xFF\x00\xFE", 3)), "/wD+");  // high bytes and a zero byte
}

TEST(LoadRunReport, ReadsSummaryFrameLogTrajectoryAndSnapshots) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  const RunReport report = LoadRunReport(scratch / "run", {});
  EXPECT_EQ(report.sequence, "tiny");
  EXPECT_EQ(report.filter, "hoid2d");
  EXPECT_EQ(report.frames, 6U);
  EXPECT_EQ(report.tracked, 5U);
  EXPECT_EQ(report.keypoints_dropped, 1200U);
  ASSERT_EQ(report.median_ms.size(), 5U);
  EXPECT_EQ(report.median_ms[0].stage, "load");  // pipeline order, not the file's alphabetical one
  EXPECT_EQ(report.median_ms[4].stage, "track");
  EXPECT_DOUBLE_EQ(report.median_tracking_ms.value(), 6.6);
  ASSERT_TRUE(report.exclusion_quality);
  EXPECT_DOUBLE_EQ(report.exclusion_quality->leaked, 0.25);
  EXPECT_EQ(report.exclusion_quality->counts.static_dropped, 90U);

  ASSERT_EQ(report.frame_log.size(), 6U);
  const FrameRecord& frame = report.frame_log[2];
  EXPECT_EQ(frame.dropped, 202U);
  EXPECT_EQ(frame.kept, 798U);  // without "kept": what the filter left
  EXPECT_EQ(report.frame_log[1].kept, 990U);
  ASSERT_EQ(frame.dynamic.size(), 2U);
  EXPECT_EQ(frame.dynamic[1].label, "cup");
  EXPECT_EQ(frame.dynamic[1].person, 0);
  EXPECT_DOUBLE_EQ(frame.dynamic[1].interaction.value(), 0.62);
  EXPECT_FALSE(frame.dynamic[0].interaction);
  EXPECT_EQ(frame.exclusion->moving_dropped, 50U);
  EXPECT_EQ(report.frame_log[3].state, "lost");

  EXPECT_EQ(report.estimate.size(), 5U);
  ASSERT_EQ(report.snapshots.size(), 1U);  // notes.txt is not one
  EXPECT_EQ(report.snapshots[0].frame, 2U);
  EXPECT_FALSE(report.comparison);
  EXPECT_TRUE(report.not_compared.empty());

  EXPECT_DOUBLE_EQ(report.camera.fx, 500.0);  // the settings summary.json recorded
  EXPECT_DOUBLE_EQ(report.camera.cy, 239.5);
  EXPECT_EQ(report.camera.width, 640);
  ASSERT_TRUE(report.map) << report.no_map;
  ASSERT_EQ(report.map->points.size(), 3U);
  EXPECT_EQ(report.map->points[1].bgr, cv::Vec3b(255, 0, 128));
  ASSERT_EQ(report.map->keyframes.size(), 2U);
  EXPECT_DOUBLE_EQ(report.map->keyframes[1].T_wc.translation().z(), 1.6);
}

TEST(LoadRunReport, WithoutRecordedSettingsTheCameraIsTumFr3s) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  std::string summary(kSummary);
  const std::size_t provenance = summary.find("\"provenance\"");
  summary.erase(provenance, summary.find("\"median_ms\"") - provenance);
  WriteText(scratch / "run" / "summary.json", summary);
  EXPECT_EQ(LoadRunReport(scratch / "run", {}).camera, core::CameraIntrinsics{});
}

TEST(LoadRunReport, AlignsTheEstimateOntoTheGroundTruthAsEvalDoes) {
  const TempDir scratch;
  const fs::path groundtruth = WriteRunFolder(scratch / "run");
  const RunReport report = LoadRunReport(scratch / "run", groundtruth);
  ASSERT_TRUE(report.comparison) << report.not_compared;
  const GroundTruthComparison& c = *report.comparison;
  EXPECT_EQ(c.evaluation.ate.pairs.size(), 5U);
  EXPECT_LT(c.evaluation.ate.error.rmse, 1e-6);
  // Every estimated position lands on the ground truth of its frame.
  ASSERT_EQ(c.aligned_estimate.size(), 5U);
  for (std::size_t k = 0; k < report.estimate.size(); ++k) {
    const int i = static_cast<int>(std::lround((report.estimate[k].timestamp - 100.0) / 0.5));
    EXPECT_LT((c.aligned_estimate[k] - ToGroundTruth(Position(i))).norm(), 1e-6) << i;
  }
  // Only the ground truth over the frames run: not the poses half a second before and after.
  EXPECT_EQ(c.groundtruth.size(), 6U);
}

TEST(LoadRunReport, GroundTruthOfAnotherTimeIsANoteNotAnError) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  WriteText(scratch / "other.txt", "1 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n3 2 0 0 0 0 0 1\n4 3 0 0 0 0 0 1\n");
  const RunReport report = LoadRunReport(scratch / "run", scratch / "other.txt");
  EXPECT_FALSE(report.comparison);
  EXPECT_THAT(report.not_compared, HasSubstr("other.txt"));
  EXPECT_THAT(RenderRunHtml(report, kViewer), HasSubstr("Not compared with ground truth"));
}

TEST(LoadRunReport, NamesTheFileOfEveryProblem) {
  const TempDir scratch;
  const fs::path run = scratch / "run";
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }), HasSubstr(run.string() + ": no such folder"));
  const fs::path groundtruth = WriteRunFolder(run);

  WriteText(scratch / "bad_gt.txt", "1 0 0 0 0 0 0 1\n2 0 0 x 0 0 0 1\n");
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, scratch / "bad_gt.txt"); }), HasSubstr("bad_gt.txt:2:"));
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, scratch / "missing_gt.txt"); }), HasSubstr("missing_gt.txt"));

  const std::string frames = ReadText(run / "frames.jsonl");
  WriteText(run / "frames.jsonl", frames.substr(0, frames.find('\n') + 1) + R"({"frame": 1, "timestamp": 1})" + "\n");
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }), HasSubstr("frames.jsonl:2: 'state' is missing"));
  WriteText(run / "frames.jsonl", "{not json\n");
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }), HasSubstr("frames.jsonl:1: not valid JSON"));
  WriteText(run / "frames.jsonl", frames);

  WriteText(run / "map.ply", "ply\nformat ascii 1.0\nend_header\n");
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }), HasSubstr("map.ply: not a point cloud"));
  io::WritePly(run / "map.ply", kMapPoints);
  WriteText(run / "keyframes.txt", "100 0 0\n");
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }), HasSubstr("keyframes.txt:1:"));
  WriteText(run / "keyframes.txt", std::string(kKeyframes));

  WriteText(run / "snapshots" / "000004.jpg", "GIF89a");
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }), HasSubstr("000004.jpg: is not a JPEG image"));
  fs::remove(run / "snapshots" / "000004.jpg");

  std::string summary(kSummary);
  summary.replace(summary.find("\"frames\": 6"), 11, "\"frames\": \"six\"");
  WriteText(run / "summary.json", summary);
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }),
              HasSubstr("summary.json: 'frames' has the wrong type (string)"));
  fs::remove(run / "summary.json");
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }), HasSubstr("summary.json: not found"));
  EXPECT_THAT(InputErrorOf([&] { RecordedGroundTruth(run); }), HasSubstr("summary.json: not found"));
}

TEST(RecordedGroundTruth, IsThePathTheRunWasEvaluatedAgainst) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  EXPECT_EQ(RecordedGroundTruth(scratch / "run"), fs::path());
  std::string summary(kSummary);
  summary.insert(summary.rfind('}'), R"(, "evaluation": {"groundtruth": {"path": "seq/groundtruth.txt", "poses": 8}})");
  WriteText(scratch / "run" / "summary.json", summary);
  EXPECT_EQ(RecordedGroundTruth(scratch / "run"), fs::path("seq/groundtruth.txt"));
}

TEST(RenderRunHtml, IsOneSelfContainedPageWithEverySection) {
  const TempDir scratch;
  const fs::path groundtruth = WriteRunFolder(scratch / "run");
  const RunReport report = LoadRunReport(scratch / "run", groundtruth);
  const std::string html = RenderRunHtml(report, kViewer);
  EXPECT_TRUE(html.starts_with("<!DOCTYPE html>"));
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
  // Nothing fetched: no script or style sheet from a file, no remote images; the only URL is the SVG namespace name.
  for (const char* outside : {"<script src", "<link", "url(", "@import", "src=\"http", "href="}) {
    EXPECT_THAT(html, Not(HasSubstr(outside))) << outside;
  }
  std::size_t urls = 0;
  for (std::size_t pos = 0; (pos = html.find("http", pos)) != std::string::npos; ++pos) {
    EXPECT_EQ(html.compare(pos, 26, "http://www.w3.org/2000/svg"), 0) << html.substr(pos, 40);
    ++urls;
  }
  EXPECT_GE(urls, 4U);  // trajectory, ATE over time, keypoints, time per stage, exclusion per frame

  EXPECT_THAT(html, HasSubstr("<h1>tiny</h1>"));
  EXPECT_THAT(html, HasSubstr("ATE RMSE"));
  EXPECT_THAT(html, HasSubstr("Trajectory seen from above"));
  EXPECT_THAT(html, HasSubstr("ATE over time"));
  EXPECT_THAT(html, HasSubstr("Keypoints per frame"));
  EXPECT_THAT(html, HasSubstr("Median time per stage"));
  EXPECT_THAT(html, HasSubstr("<h2>Map</h2>"));
  EXPECT_THAT(html, HasSubstr("leaked: 25.0 % kept"));
  EXPECT_THAT(html, HasSubstr("Exclusion errors per frame"));
  EXPECT_THAT(html, HasSubstr("Age of the detections per frame"));  // every other frame's are a frame old
  EXPECT_THAT(html, HasSubstr("1 frame dropped"));
  // The snapshot inline, with a caption from its frame's log line.
  EXPECT_THAT(html, HasSubstr("src=\"data:image/jpeg;base64," + Base64Encode(report.snapshots[0].jpeg) + "\""));
  EXPECT_THAT(html, HasSubstr("<b>frame 2</b> · 1.00 s · ok (motion_model)"));
  EXPECT_THAT(html, HasSubstr("<b>cup</b> 0.80: interaction with person #0 (62 % of its box)"));
  EXPECT_THAT(html, HasSubstr("moving keypoints kept 10 of 60"));
}

TEST(RenderRunHtml, WithoutGroundTruthShowsTheEstimateAndSaysSo) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  fs::remove_all(scratch / "run" / "snapshots");
  const std::string html = RenderRunHtml(LoadRunReport(scratch / "run", {}), kViewer);
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
  EXPECT_THAT(html, HasSubstr("No ground truth given"));
  EXPECT_THAT(html, HasSubstr(">estimate</text>"));
  EXPECT_THAT(html, Not(HasSubstr("ATE over time")));
  EXPECT_THAT(html, Not(HasSubstr("Annotated frames")));
}

// A run on a sequence without ground-truth moving masks, as on every real recording: summary.json's
// exclusion_quality is null and no frame has an exclusion count.
TEST(RenderRunHtml, WithoutMovingMasksSaysExclusionIsNotScored) {
  const TempDir scratch;
  const fs::path run = scratch / "run";
  const fs::path groundtruth = WriteRunFolder(run);
  std::string frames = ReadText(run / "frames.jsonl");
  const std::string counts =
      R"("exclusion": {"moving_kept": 10, "moving_dropped": 50, "static_kept": 735, "static_dropped": 15}, )";
  for (std::size_t at; (at = frames.find(counts)) != std::string::npos;) frames.erase(at, counts.size());
  WriteText(run / "frames.jsonl", frames);
  std::string summary(kSummary);
  const std::size_t quality = summary.find("\"exclusion_quality\"");
  summary.replace(quality, summary.rfind('}') - quality, R"("exclusion_quality": null)");
  WriteText(run / "summary.json", summary);

  const RunReport report = LoadRunReport(run, groundtruth);
  EXPECT_FALSE(report.exclusion_quality);
  EXPECT_FALSE(report.frame_log.at(2).exclusion);
  const std::string html = RenderRunHtml(report, kViewer);
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
  EXPECT_THAT(html, HasSubstr("<h2>Exclusion against the moving pixels</h2>"));
  EXPECT_THAT(html, HasSubstr("no ground-truth masks"));
  EXPECT_THAT(html, Not(HasSubstr("leaked:")));
  EXPECT_THAT(html, Not(HasSubstr("Exclusion errors per frame")));
  EXPECT_THAT(html, Not(HasSubstr("moving keypoints kept")));  // in the snapshot's caption
  EXPECT_THAT(html, HasSubstr("ATE over time"));               // the rest of the page is all there

  // Left out altogether, as a folder of an older hoidslam has it: the same page.
  const std::size_t comma = summary.rfind(',', quality);
  summary.erase(comma, summary.rfind('}') - comma);
  WriteText(run / "summary.json", summary);
  EXPECT_EQ(RenderRunHtml(LoadRunReport(run, groundtruth), kViewer), html);

  // Anything but an object or null is still an error naming the file and the member.
  summary.insert(summary.rfind('}'), R"(, "exclusion_quality": 0.5)");
  WriteText(run / "summary.json", summary);
  EXPECT_THAT(InputErrorOf([&] { LoadRunReport(run, {}); }),
              HasSubstr("summary.json: 'exclusion_quality' must be an object, not number"));
}

TEST(RenderRunHtml, InlinesTheViewersPageWithTheMapOfTheRunFolder) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  const std::string html = RenderRunHtml(LoadRunReport(scratch / "run", {}), kViewer);
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
  // The page's parts in the order it needs them: its style, its element, its data, then its script.
  const std::size_t style = html.find("<style>" + kViewer.style + "</style>");
  const std::size_t root = html.find(R"(<div id="hoidslam-viewer"></div>)");
  const std::size_t data = html.find(R"(<script id="hoidslam-data" type="application/json">)");
  const std::size_t script = html.find("<script>" + kViewer.script + "</script>");
  ASSERT_NE(script, std::string::npos);
  EXPECT_LT(style, root);
  EXPECT_LT(root, data);
  EXPECT_LT(data, script);

  const nlohmann::json embedded = EmbeddedData(html);
  const nlohmann::json& hello = embedded.at("hello");
  EXPECT_EQ(hello.at("sequence"), "tiny");
  EXPECT_EQ(hello.at("total_frames"), 6);
  EXPECT_EQ(hello.at("controllable"), false);
  EXPECT_EQ(hello.at("camera"), (nlohmann::json{{"fx", 500.0}, {"fy", 501.0}, {"cx", 319.5}, {"cy", 239.5},
                                                {"width", 640}, {"height", 480}}));
  EXPECT_FALSE(embedded.contains("frame"));  // the page shows the map alone
  const nlohmann::json& map = embedded.at("map");
  EXPECT_EQ(map.at("full"), true);
  EXPECT_EQ(map.at("main_map"), 0);
  EXPECT_EQ(map.at("maps"), (nlohmann::json{{{"id", 0}, {"keyframes", 2}, {"points", 3}}}));
  // Every point of map.ply by its place in the file, to 0.1 mm, in RGB.
  const nlohmann::json& points = map.at("points");
  EXPECT_EQ(points.at("ids"), (nlohmann::json{0, 1, 2}));
  EXPECT_EQ(points.at("map"), (nlohmann::json{0, 0, 0}));
  const std::vector<double> xyz = points.at("xyz");
  const std::vector<double> expected_xyz = {0.1234, -1.5, 2.0, 1.0, 0.25, 3.0001, -2.0, 0.0, 4.5};
  ASSERT_EQ(xyz.size(), expected_xyz.size());
  for (std::size_t i = 0; i < xyz.size(); ++i) EXPECT_NEAR(xyz[i], expected_xyz[i], 1e-9) << i;
  EXPECT_EQ(points.at("rgb"), (nlohmann::json{30, 20, 10, 128, 0, 255, 3, 2, 1}));
  // Every keyframe of keyframes.txt, its pose as the page takes it.
  const nlohmann::json& keyframes = map.at("keyframes");
  ASSERT_EQ(keyframes.size(), 2U);
  EXPECT_EQ(keyframes[1].at("id"), 1);
  EXPECT_EQ(keyframes[1].at("map"), 0);
  EXPECT_EQ(keyframes[1].at("T_wc"), (nlohmann::json{1, 0, 0, 1.2, 0, 1, 0, 0.2, 0, 0, 1, 1.6, 0, 0, 0, 1}));
}

TEST(RenderRunHtml, EmbedsTheDenseMapWhenTheCallerGivesIt) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  RunReport report = LoadRunReport(scratch / "run", {});
  EXPECT_FALSE(report.dense_mesh.has_value()) << "made small by the caller, not read here";
  const std::string without = RenderRunHtml(report, kViewer);
  EXPECT_FALSE(EmbeddedData(without).contains("dense"));
  EXPECT_THAT(without, Not(HasSubstr("dense map")));

  io::TriangleMesh mesh;
  mesh.vertices = {{0.0F, 0.0F, 1.0F}, {1.0F, 0.0F, 1.0F}, {0.0F, 1.5F, 1.0F}, {1.0F, 1.0F, 2.0F}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  mesh.rgb = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {1, 2, 3}};
  report.dense_mesh = mesh;
  const std::string html = RenderRunHtml(report, kViewer);
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
  EXPECT_THAT(html, HasSubstr("The dense map of mesh.ply with it, made small enough to show: 2 triangles"));
  const nlohmann::json dense = EmbeddedData(html).at("dense");
  EXPECT_EQ(dense.at("vertices"), 4);
  EXPECT_EQ(dense.at("triangles"), 2);
  // The arrays' bytes as they lie in memory: little-endian float32, uint8 and uint32.
  const auto bytes = [](const auto& values) {
    return Base64Encode(std::string_view(reinterpret_cast<const char*>(values.data()),
                                         values.size() * sizeof(values[0])));
  };
  const std::vector<float> positions = {0, 0, 1, 1, 0, 1, 0, 1.5F, 1, 1, 1, 2};
  const std::vector<std::uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 1, 2, 3};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 1, 3, 2};
  EXPECT_EQ(dense.at("positions"), bytes(positions));
  EXPECT_EQ(dense.at("rgb"), bytes(rgb));
  EXPECT_EQ(dense.at("indices"), bytes(indices));

  mesh.rgb.clear();
  report.dense_mesh = mesh;
  EXPECT_EQ(EmbeddedData(RenderRunHtml(report, kViewer)).at("dense").at("rgb"), "");
}

TEST(RenderRunHtml, EscapesTheEmbeddedDataForItsScriptElement) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  RunReport report = LoadRunReport(scratch / "run", {});
  report.sequence = "a</script><!--<script>b";
  const std::string html = RenderRunHtml(report, kViewer);
  // The data element ends where the report ends it, and reads back as it was.
  EXPECT_THAT(html, Not(HasSubstr("a</script>")));
  EXPECT_THAT(html, Not(HasSubstr("<!--")));
  EXPECT_EQ(EmbeddedData(html).at("hello").at("sequence"), report.sequence);
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
}

TEST(RenderRunHtml, SaysWhyThereIsNoMapView) {
  const TempDir scratch;
  WriteRunFolder(scratch / "run");
  const RunReport report = LoadRunReport(scratch / "run", {});
  const ViewerBundle none{.script = "", .style = "", .missing = "the viewer's page is not there (x)"};
  const std::string without_page = RenderRunHtml(report, none);
  EXPECT_EQ(report::testing::UnbalancedTags(without_page), "");
  EXPECT_THAT(without_page, HasSubstr("<h2>Map</h2>\n<p class=\"note\">No 3D view of the map: the viewer&#39;s page"));
  EXPECT_THAT(without_page, Not(HasSubstr("<script")));
  EXPECT_THAT(without_page, HasSubstr("Keypoints per frame"));  // the rest of the report is all there

  fs::remove(scratch / "run" / "keyframes.txt");
  const std::string without_map = RenderRunHtml(LoadRunReport(scratch / "run", {}), kViewer);
  EXPECT_THAT(without_map, HasSubstr("No 3D view of the map: the run folder has no keyframes.txt."));
  EXPECT_THAT(without_map, Not(HasSubstr("<script")));
}

TEST(LoadViewerBundle, ReadsTheScriptAndStyleOrSaysWhyNot) {
  const TempDir scratch;
  EXPECT_THAT(LoadViewerBundle(scratch / "web").missing,
              HasSubstr("the viewer's page is not there (" + (scratch / "web" / "viewer.js").string()));
  fs::create_directories(scratch / "web");
  WriteText(scratch / "web" / "viewer.js", kViewer.script);
  EXPECT_THAT(LoadViewerBundle(scratch / "web").missing, HasSubstr("viewer.css"));
  WriteText(scratch / "web" / "viewer.css", kViewer.style);
  const ViewerBundle bundle = LoadViewerBundle(scratch / "web");
  EXPECT_EQ(bundle.missing, "");
  EXPECT_EQ(bundle.script, kViewer.script);
  EXPECT_EQ(bundle.style, kViewer.style);

  // A script that would end its element early is not inlined.
  WriteText(scratch / "web" / "viewer.js", "const tag = '</SCRIPT>';");
  const ViewerBundle unsafe = LoadViewerBundle(scratch / "web");
  EXPECT_THAT(unsafe.missing, HasSubstr("viewer.js holds \"</script\" and cannot be inlined"));
  EXPECT_EQ(unsafe.script, "");
}

TEST(WriteRunReport, WritesThePageOrNothing) {
  const TempDir scratch;
  const fs::path groundtruth = WriteRunFolder(scratch / "run");
  WriteRunReport(scratch / "run", groundtruth, scratch / "report.html");
  EXPECT_THAT(ReadText(scratch / "report.html"), HasSubstr("</html>"));
  EXPECT_THROW(WriteRunReport(scratch / "run", groundtruth, scratch / "no_folder" / "report.html"), core::InputError);
  EXPECT_THROW(WriteRunReport(scratch / "nothing", {}, scratch / "empty.html"), core::InputError);
  EXPECT_FALSE(fs::exists(scratch / "empty.html"));
}

TEST(TableHtml, EscapesCellsAndAlignsNumbersRight) {
  Table table;
  table.title = "ATE <m>";
  table.note = "median of 5";
  table.header = {"sequence", "hoid2d"};
  table.rows = {{"walking_xyz", "0.0035"}, {"a & b", "failed"}};
  const std::string html = TableHtml(table);
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
  EXPECT_THAT(html, HasSubstr("<caption>ATE &lt;m&gt;</caption>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">0.0035</td>"));
  EXPECT_THAT(html, HasSubstr("<td>a &amp; b</td><td>failed</td>"));
  EXPECT_THAT(html, HasSubstr("median of 5"));
}

TEST(RenderBenchHtml, HoldsTheIntroAndEverySection) {
  Table table;
  table.header = {"mode", "ATE"};
  table.rows = {{"hoid2d", "0.0035"}};
  const BenchReportSection section{"Accuracy", "First paragraph.\n\nSecond <one>.", {table},
                                   {AteBarChartSvg({"walking_xyz"}, {"hoid2d", "none"}, {{0.0035, 0.18}})},
                                   "<p id=\"extra\">after the figures</p>"};
  const std::string html = RenderBenchHtml("hoidslam bench", {"5 runs per mode", "2 cores"}, {section});
  EXPECT_EQ(report::testing::UnbalancedTags(html), "");
  EXPECT_THAT(html, HasSubstr("<h1>hoidslam bench</h1>"));
  EXPECT_THAT(html, HasSubstr("<p id=\"extra\">after the figures</p>"));
  EXPECT_THAT(html, HasSubstr("<li>2 cores</li>"));
  EXPECT_THAT(html, HasSubstr("<h2>Accuracy</h2>"));
  EXPECT_THAT(html, HasSubstr("<p>First paragraph.</p>"));
  EXPECT_THAT(html, HasSubstr("<p>Second &lt;one&gt;.</p>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">0.0035</td>"));
  EXPECT_THAT(html, HasSubstr("ATE RMSE per sequence and mode"));
}

TEST(AteBarChartSvg, MarksMissingRunsAndUsesALogAxisForWideRanges) {
  const std::string wide =
      AteBarChartSvg({"walking_xyz", "carry"}, {"hoid2d", "none"}, {{0.0035, 0.18}, {0.0076, kNaN}});
  EXPECT_EQ(report::testing::UnbalancedTags(wide), "");
  EXPECT_THAT(wide, HasSubstr("log scale"));
  EXPECT_THAT(wide, HasSubstr(">×</text>"));
  EXPECT_THAT(wide, HasSubstr(">carry</text>"));
  const std::string narrow = AteBarChartSvg({"walking_xyz"}, {"hoid2d", "oracle"}, {{0.0035, 0.0030}});
  EXPECT_THAT(narrow, Not(HasSubstr("log scale")));
  EXPECT_THROW(AteBarChartSvg({"walking_xyz"}, {"hoid2d"}, {{0.1, 0.2}}), std::invalid_argument);
  EXPECT_THROW(AteBarChartSvg({"walking_xyz", "carry"}, {"hoid2d"}, {{0.1}}), std::invalid_argument);
}

TEST(TrajectoryOverlaySvg, DrawsEveryRunOverOneGroundTruth) {
  const TempDir scratch;
  const fs::path groundtruth = WriteRunFolder(scratch / "a" / "run");
  WriteRunFolder(scratch / "b" / "run");
  std::vector<RunReport> runs = {LoadRunReport(scratch / "a" / "run", groundtruth),
                                 LoadRunReport(scratch / "b" / "run", groundtruth),
                                 LoadRunReport(scratch / "b" / "run", {})};
  const std::vector<std::string> labels = {"hoid2d", "none", "failed"};
  const std::string svg = TrajectoryOverlaySvg(runs, labels);
  EXPECT_EQ(report::testing::UnbalancedTags(svg), "");
  EXPECT_THAT(svg, HasSubstr(">ground truth</text>"));
  EXPECT_THAT(svg, HasSubstr(">hoid2d</text>"));
  EXPECT_THAT(svg, HasSubstr(">none</text>"));
  EXPECT_THAT(svg, HasSubstr(">failed (no aligned trajectory)</text>"));
  EXPECT_THAT(TrajectoryOverlaySvg(std::span(runs).first(1)), HasSubstr(">hoid2d</text>"));  // the filter's name

  const std::vector<std::string> too_few = {"one"};
  EXPECT_THROW(TrajectoryOverlaySvg(runs, too_few), std::invalid_argument);
  runs[1] = LoadRunReport(scratch / "b" / "run", scratch / "b" / "groundtruth.txt");
  EXPECT_THROW(TrajectoryOverlaySvg(runs, labels), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::report
