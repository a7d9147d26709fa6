#include "hoidslam/report/trajectory_plot.h"

#include <random>
#include <regex>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/eval/evaluation.h"
#include "hoidslam/eval/test_trajectories.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/report/test_markup.h"
#include "support/input_error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::report::trajectory_plot_test {
namespace {

namespace fs = std::filesystem;
using ::hoidslam::testing::InputErrorOf;
using ::hoidslam::testing::ReadText;
using ::hoidslam::testing::TempDir;
using ::hoidslam::testing::WriteText;
using ::testing::HasSubstr;
using ::testing::Not;

// The ground truth and two estimates of it: seen from another world frame, with noise of `noise` metres.
struct Files {
  fs::path groundtruth, a, b;
};

core::Trajectory Noisy(core::Trajectory trajectory, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, noise);
  for (core::StampedPose& pose : trajectory) {
    pose.T_wc.translation() += Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  }
  return trajectory;
}

Files WriteFiles(const TempDir& dir) {
  const core::Trajectory groundtruth = eval::test_data::MakeLissajousTrajectory(300, 30.0);
  std::mt19937 rng(7);
  const Files files{dir / "groundtruth.txt", dir / "a.txt", dir / "b.txt"};
  io::WriteTumTrajectory(files.groundtruth, groundtruth);
  io::WriteTumTrajectory(files.a, Noisy(eval::test_data::Transformed(groundtruth, eval::test_data::RandomPose(rng)),
                                        0.01, 1));
  io::WriteTumTrajectory(files.b, Noisy(eval::test_data::Transformed(groundtruth, eval::test_data::RandomPose(rng)),
                                        0.05, 2));
  return files;
}

std::vector<EstimateSource> Sources(const Files& files) { return {{"a", files.a}, {"b & co", files.b}}; }

TEST(LoadTrajectoryPlot, EachEstimateHasTheAteEvalComputes) {
  const TempDir dir;
  const Files files = WriteFiles(dir);
  const eval::AteOptions options{.association = {.max_difference = 0.01}};
  const TrajectoryPlot plot = LoadTrajectoryPlot(files.groundtruth, Sources(files), options);
  ASSERT_EQ(plot.estimates.size(), 2U);
  for (const PlottedEstimate& estimate : plot.estimates) {
    const eval::Evaluation evaluation =
        eval::EvaluateTrajectoryFiles(files.groundtruth, estimate.path, {.ate = options});
    ASSERT_TRUE(estimate.ate);
    EXPECT_EQ(estimate.ate->error.count, evaluation.ate.error.count);
    EXPECT_EQ(estimate.ate->error.rmse, evaluation.ate.error.rmse);
    EXPECT_EQ(estimate.ate->error.median, evaluation.ate.error.median);
    EXPECT_EQ(estimate.ate->error.max, evaluation.ate.error.max);
    EXPECT_EQ(estimate.trajectory.size(), evaluation.estimate_poses);
  }
  EXPECT_LT(plot.estimates[0].ate->error.rmse, plot.estimates[1].ate->error.rmse);  // the noisier one is worse
}

TEST(TrajectoryPlotHtml, IsOneSelfContainedPageWithTheNumbersEvalPrints) {
  const TempDir dir;
  const Files files = WriteFiles(dir);
  const TrajectoryPlot plot = LoadTrajectoryPlot(files.groundtruth, Sources(files), {});
  const std::string html = TrajectoryPlotHtml(plot);
  EXPECT_EQ(testing::UnbalancedTags(html), "");
  // Nothing fetched: the one URL is the SVG namespace.
  const std::regex url(R"(https?://(?!www\.w3\.org/2000/svg))");
  EXPECT_FALSE(std::regex_search(html, url));
  EXPECT_THAT(html, Not(HasSubstr(" src=")));
  for (const PlottedEstimate& estimate : plot.estimates) {
    const eval::ErrorStatistics& e = estimate.ate->error;
    EXPECT_THAT(html, HasSubstr(fmt::format(
                          R"(<td class="num">{}</td><td class="num">{:.6f}</td><td class="num">{:.6f}</td>)"
                          R"(<td class="num">{:.6f}</td><td class="num">{:.6f}</td><td class="num">{:.6f}</td>)"
                          R"(<td class="num">{:.6f}</td></tr>)",
                          e.count, e.rmse, e.mean, e.median, e.std, e.min, e.max)));
  }
  EXPECT_THAT(html, HasSubstr("<td>b &amp; co</td>"));
  EXPECT_THAT(html, HasSubstr("ATE over time"));
  EXPECT_THAT(html, HasSubstr("a: ATE along the path"));
  EXPECT_THAT(html, HasSubstr(">ATE (m)</text>"));  // the colour bar's label
}

TEST(TrajectoryFigure, HasAPanelForThePathsTheErrorsAndEachEstimate) {
  const TempDir dir;
  const Files files = WriteFiles(dir);
  const Drawing figure = TrajectoryFigure(LoadTrajectoryPlot(files.groundtruth, Sources(files), {}));
  EXPECT_EQ(figure.width(), 2 * kPlotPanelWidth);
  EXPECT_EQ(figure.height(), 2 * kPlotPanelHeight);
  const std::vector<EstimateSource> one = {{"a", files.a}};
  const Drawing single = TrajectoryFigure(LoadTrajectoryPlot(files.groundtruth, one, {}));
  EXPECT_EQ(single.width(), 2 * kPlotPanelWidth);
  EXPECT_EQ(single.height(), 2 * kPlotPanelHeight);  // paths, errors; then the error along the path
}

TEST(TrajectoryPlot, WithoutGroundTruthDrawsThePathsAsEstimated) {
  const TempDir dir;
  const Files files = WriteFiles(dir);
  const TrajectoryPlot plot = LoadTrajectoryPlot({}, Sources(files), {});
  EXPECT_FALSE(plot.estimates[0].ate);
  const Drawing figure = TrajectoryFigure(plot);
  EXPECT_EQ(figure.width(), kPlotPanelWidth);
  EXPECT_EQ(figure.height(), kPlotPanelHeight);
  const std::string html = TrajectoryPlotHtml(plot);
  EXPECT_THAT(html, HasSubstr("no ground truth"));
  EXPECT_THAT(html, Not(HasSubstr("ATE RMSE")));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">300</td>"));  // the poses of each estimate
}

TEST(WriteTrajectoryPlot, WritesEachFileByItsExtension) {
  const TempDir dir;
  const Files files = WriteFiles(dir);
  const TrajectoryPlot plot = LoadTrajectoryPlot(files.groundtruth, Sources(files), {});
  const std::vector<fs::path> outputs = {dir / "plot.html", dir / "plot.PNG", dir / "plot.svg"};
  CheckPlotFiles(outputs, "--out");
  WriteTrajectoryPlot(plot, outputs, "--out");
  EXPECT_THAT(ReadText(outputs[0]), HasSubstr("<!DOCTYPE html>"));
  const cv::Mat png = cv::imread(outputs[1].string());
  EXPECT_EQ(png.size(), cv::Size(2 * kPlotPanelWidth, 2 * kPlotPanelHeight));
  EXPECT_TRUE(ReadText(outputs[2]).starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 6);  // nothing left over
}

TEST(TrajectoryPlot, BadInputIsNamed) {
  const TempDir dir;
  const Files files = WriteFiles(dir);
  EXPECT_THAT(InputErrorOf([&] { LoadTrajectoryPlot(files.groundtruth, {}, {}); }), HasSubstr("--est"));
  const std::vector<EstimateSource> twins = {{"a", files.a}, {"a", files.b}};
  EXPECT_THAT(InputErrorOf([&] { LoadTrajectoryPlot(files.groundtruth, twins, {}); }), HasSubstr("--name"));
  const eval::AteOptions no_difference{.association = {.max_difference = 0}};
  EXPECT_THAT(InputErrorOf([&] { LoadTrajectoryPlot(files.groundtruth, Sources(files), no_difference); }),
              HasSubstr("--max-difference"));
  WriteText(dir / "bad.txt", "0.0 1 2 3 0 0 0 1\n0.1 1 2 three 0 0 0 1\n");
  const std::vector<EstimateSource> bad = {{"bad", dir / "bad.txt"}};
  EXPECT_THAT(InputErrorOf([&] { LoadTrajectoryPlot(files.groundtruth, bad, {}); }), HasSubstr("bad.txt:2"));
  // Stamps an hour later match no ground-truth pose: both files are named.
  const std::vector<EstimateSource> later = {{"later", dir / "later.txt"}};
  io::WriteTumTrajectory(later[0].path, eval::test_data::MakeLissajousTrajectory(50, 30.0, 3600.0));
  const std::string message = InputErrorOf([&] { LoadTrajectoryPlot(files.groundtruth, later, {}); });
  EXPECT_THAT(message, HasSubstr("later.txt"));
  EXPECT_THAT(message, HasSubstr("groundtruth.txt"));
  const std::vector<fs::path> pdf = {dir / "plot.pdf"};
  EXPECT_THAT(InputErrorOf([&] { CheckPlotFiles(pdf, "--out"); }), HasSubstr("--out"));
  const std::vector<fs::path> nowhere = {dir / "no" / "such" / "plot.png"};
  EXPECT_THAT(InputErrorOf([&] { CheckPlotFiles(nowhere, "--plot"); }), HasSubstr("--plot"));
}

TEST(RunFolderEstimate, IsTheTrajectoryNamedAfterTheFolder) {
  const TempDir dir;
  fs::create_directories(dir / "hoidplus-run");
  EXPECT_THAT(InputErrorOf([&] { RunFolderEstimate(dir / "hoidplus-run"); }), HasSubstr("trajectory.txt"));
  WriteText(dir / "hoidplus-run" / "trajectory.txt", "");
  const EstimateSource source = RunFolderEstimate(dir / "hoidplus-run/");
  EXPECT_EQ(source.name, "hoidplus-run");
  EXPECT_EQ(source.path, dir / "hoidplus-run/" / "trajectory.txt");
  EXPECT_THAT(InputErrorOf([&] { RunFolderEstimate(dir / "none"); }), HasSubstr("none"));
}

TEST(GroundTruthOfRuns, IsTheOneTheRunsWereEvaluatedAgainst) {
  const TempDir dir;
  const Files files = WriteFiles(dir);
  const auto run = [&](const std::string& name, const std::string& summary) {
    fs::create_directories(dir / name);
    WriteText(dir / name / "summary.json", summary);
    return dir / name;
  };
  const auto evaluated_against = [](const fs::path& groundtruth) {
    return fmt::format(R"({{"evaluation": {{"groundtruth": {{"path": "{}"}}}}}})", groundtruth.string());
  };
  const std::vector<fs::path> runs = {run("none", "{}"), run("first", evaluated_against(files.groundtruth)),
                                      run("second", evaluated_against(files.groundtruth))};
  EXPECT_EQ(GroundTruthOfRuns(runs, "--gt"), files.groundtruth);
  const std::vector<fs::path> gone = {run("gone", evaluated_against(dir / "moved.txt"))};
  EXPECT_EQ(GroundTruthOfRuns(gone, "--gt"), fs::path());
  const std::vector<fs::path> different = {runs[1], run("other", evaluated_against(files.a))};
  EXPECT_THAT(InputErrorOf([&] { GroundTruthOfRuns(different, "--gt"); }), HasSubstr("--gt"));
}

}  // namespace
}  // namespace hoidslam::report::trajectory_plot_test
