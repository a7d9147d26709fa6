// End-to-end tests of `hoidslam plot` and `hoidslam eval --plot`: the page's ATE is the one `eval` prints, the PNG
// is a picture of the same figure, and bad input is named with nothing written.
#include <fstream>
#include <regex>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_test_support.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::apps::plot_cli_test {
namespace {

namespace fs = std::filesystem;
using ::hoidslam::testing::ReadText;
using ::hoidslam::testing::WriteText;
using ::testing::HasSubstr;

// Every `step`-th pose of a TUM file, seen from another world frame (turned about z, moved) and pushed off its
// path by a slow wave `wobble` metres high: an estimate that needs aligning and has an error that varies.
void WritePerturbedCopy(const fs::path& groundtruth, const fs::path& out, int step, double wobble) {
  std::ifstream in(groundtruth);
  std::ofstream estimate(out);
  std::string line;
  int index = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || index++ % step != 0) continue;
    std::istringstream fields(line);
    double t = 0, x = 0, y = 0, z = 0;
    std::string quaternion;
    fields >> t >> x >> y >> z;
    std::getline(fields, quaternion);
    x += wobble * std::sin(3.0 * t);
    z += wobble * std::cos(2.0 * t);
    const double c = std::cos(0.5), s = std::sin(0.5);
    estimate << fmt::format("{:.6f} {:.6f} {:.6f} {:.6f}{}\n", t, c * x - s * y + 2.0, s * x + c * y - 1.0, z + 0.3,
                            quaternion);
  }
}

// The ATE row `hoidslam eval` prints: rmse, mean, median, std, min, max and pairs, as printed.
std::vector<std::string> EvalAteRow(const std::string& out) {
  const std::regex row(R"(ATE \(m\)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\d+))");
  std::smatch match;
  if (!std::regex_search(out, match, row)) return {};
  return {match[1], match[2], match[3], match[4], match[5], match[6], match[7]};
}

// The same figures from the page's table row of `name`, in the same order.
std::vector<std::string> PageAteRow(const std::string& html, const std::string& name) {
  const std::string number = R"(<td class="num">([^<]*)</td>)";
  const std::regex row("<tr><td>" + name + "</td><td>[^<]*</td>" + number + number + number + number + number +
                       number + number + number);
  std::smatch match;
  if (!std::regex_search(html, match, row)) return {};
  // Columns: poses, pairs, rmse, mean, median, std, min, max.
  return {match[3], match[4], match[5], match[6], match[7], match[8], match[2]};
}

// Distinct colours and the share of pixels that are not the white background.
std::pair<std::size_t, double> ColoursAndInk(const cv::Mat& image) {
  std::set<int> colours;
  std::size_t ink = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      colours.insert(p[0] << 16 | p[1] << 8 | p[2]);
      ink += p != cv::Vec3b(255, 255, 255);
    }
  }
  return {colours.size(), static_cast<double>(ink) / static_cast<double>(image.total())};
}

TEST(CliPlot, TwoEstimatesOverTheGroundTruthGiveThePageWithEvalsNumbersAndAPng) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(groundtruth, "data/tum/fr1_rpy/groundtruth.txt");
  const testing::TempDir scratch;
  WritePerturbedCopy(groundtruth, scratch / "close.txt", 3, 0.005);
  WritePerturbedCopy(groundtruth, scratch / "wobbly.txt", 4, 0.03);
  const RunResult plot = RunHoidslam(
      scratch, {"plot", "--gt", groundtruth.string(), "--est", (scratch / "close.txt").string(), "--est",
                (scratch / "wobbly.txt").string(), "--out", (scratch / "plot.html").string(), "--out",
                (scratch / "plot.png").string()});
  ASSERT_EQ(plot.exit_status, 0) << plot.err;
  const std::string html = ReadText(scratch / "plot.html");
  for (const std::string name : {"close", "wobbly"}) {
    const RunResult eval = RunHoidslam(
        scratch, {"eval", "--gt", groundtruth.string(), "--est", (scratch / (name + ".txt")).string()});
    ASSERT_EQ(eval.exit_status, 0) << eval.err;
    const std::vector<std::string> expected = EvalAteRow(eval.out);
    ASSERT_EQ(expected.size(), 7U) << eval.out;
    EXPECT_EQ(PageAteRow(html, name), expected) << name;
    EXPECT_THAT(plot.out, HasSubstr(fmt::format("{}: ATE RMSE {} m over {} pairs", name, expected[0], expected[6])));
  }
  EXPECT_THAT(html, HasSubstr("wobbly: ATE along the path"));

  const cv::Mat png = cv::imread((scratch / "plot.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.size(), cv::Size(1120, 840));  // four panels of 560 x 420, two to a row
  const auto [colours, ink] = ColoursAndInk(png);
  EXPECT_GT(colours, 200U);  // the palette, the colour scale and their anti-aliased blends with white
  EXPECT_GT(ink, 0.05);
}

TEST(CliPlot, EvalPlotWritesThePageOfItsEstimateAndAPngByExtension) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(groundtruth, "data/tum/fr1_rpy/groundtruth.txt");
  const testing::TempDir scratch;
  WritePerturbedCopy(groundtruth, scratch / "estimate.txt", 3, 0.01);
  const RunResult eval =
      RunHoidslam(scratch, {"eval", "--gt", groundtruth.string(), "--est", (scratch / "estimate.txt").string(),
                            "--plot", (scratch / "e.html").string(), "--plot", (scratch / "e.png").string()});
  ASSERT_EQ(eval.exit_status, 0) << eval.err;
  EXPECT_EQ(PageAteRow(ReadText(scratch / "e.html"), "estimate"), EvalAteRow(eval.out));
  const cv::Mat png = cv::imread((scratch / "e.png").string(), cv::IMREAD_COLOR);
  EXPECT_EQ(png.size(), cv::Size(1120, 840));  // paths, errors, then the path coloured by its error
}

TEST(CliPlot, ARunFolderIsNamedAfterItAndBringsItsGroundTruth) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(groundtruth, "data/tum/fr1_rpy/groundtruth.txt");
  const testing::TempDir scratch;
  fs::create_directories(scratch / "hoidplus");
  WritePerturbedCopy(groundtruth, scratch / "hoidplus" / "trajectory.txt", 3, 0.01);
  WriteText(scratch / "hoidplus" / "summary.json",
            fmt::format(R"({{"evaluation": {{"groundtruth": {{"path": "{}"}}}}}})", groundtruth.string()));
  const RunResult plot = RunHoidslam(
      scratch, {"plot", "--run", (scratch / "hoidplus").string(), "--out", (scratch / "run.svg").string()});
  ASSERT_EQ(plot.exit_status, 0) << plot.err;
  EXPECT_THAT(plot.out, HasSubstr("hoidplus: ATE RMSE"));
  EXPECT_THAT(ReadText(scratch / "run.svg"), HasSubstr(">hoidplus: ATE along the path</text>"));

  // Without any ground truth: the path alone.
  WriteText(scratch / "hoidplus" / "summary.json", "{}");
  const RunResult alone = RunHoidslam(
      scratch, {"plot", "--run", (scratch / "hoidplus").string(), "--out", (scratch / "alone.png").string()});
  ASSERT_EQ(alone.exit_status, 0) << alone.err;
  EXPECT_THAT(alone.out, HasSubstr("no ground truth"));
  EXPECT_EQ(cv::imread((scratch / "alone.png").string()).size(), cv::Size(560, 420));
}

TEST(CliPlot, BadInputIsNamedAndNothingIsWritten) {
  const testing::TempDir scratch;
  WriteText(scratch / "gt.txt", "1.0 0 0 0 0 0 0 1\n1.1 1 0 0 0 0 0 1\n1.2 1 1 0 0 0 0 1\n1.3 0 1 0 0 0 0 1\n");
  WriteText(scratch / "bad.txt", "1.0 0 0 0 0 0 0 1\n1.1 1 0 zero 0 0 0 1\n");
  WriteText(scratch / "later.txt", "9.0 0 0 0 0 0 0 1\n9.1 1 0 0 0 0 0 1\n9.2 1 1 0 0 0 0 1\n");
  const std::string gt = (scratch / "gt.txt").string();
  const std::string html = (scratch / "plot.html").string();
  const auto plot = [&](std::vector<std::string> args) {
    args.insert(args.begin(), "plot");
    return RunHoidslam(scratch, args);
  };
  ExpectOneErrorLine(plot({"--gt", gt, "--est", (scratch / "missing.txt").string(), "--out", html}), "missing.txt");
  ExpectOneErrorLine(plot({"--gt", gt, "--est", (scratch / "bad.txt").string(), "--out", html}), "bad.txt:2");
  const RunResult later = plot({"--gt", gt, "--est", (scratch / "later.txt").string(), "--out", html});
  ExpectOneErrorLine(later, "later.txt");
  EXPECT_THAT(later.err, HasSubstr("gt.txt"));
  ExpectOneErrorLine(plot({"--gt", gt, "--est", gt, "--out", (scratch / "plot.pdf").string()}), "--out");
  ExpectOneErrorLine(plot({"--gt", gt, "--est", gt, "--est", gt, "--name", "one", "--out", html}), "--name");
  ExpectOneErrorLine(plot({"--gt", gt, "--out", html}), "--est");
  ExpectOneErrorLine(plot({"--gt", gt, "--est", gt, "--max-difference", "0", "--out", html}), "--max-difference");
  ExpectOneErrorLine(plot({"--run", (scratch / "no-run").string(), "--out", html}), "no-run");
  ExpectOneErrorLine(plot({"--gt", gt, "--est", gt}), "--out");
  ExpectOneErrorLine(RunHoidslam(scratch, {"eval", "--gt", gt, "--est", gt, "--plot", (scratch / "e.jpg").string()}),
                     "--plot");
  EXPECT_FALSE(fs::exists(scratch / "plot.html"));
  // Only the inputs (and the captured output of the last run) are left: no plot, no temporary file.
  std::vector<std::string> left;
  for (const fs::directory_entry& entry : fs::directory_iterator(scratch.path())) {
    left.push_back(entry.path().filename().string());
  }
  EXPECT_THAT(left, ::testing::UnorderedElementsAre("gt.txt", "bad.txt", "later.txt", "stdout.txt", "stderr.txt"));
}

}  // namespace
}  // namespace hoidslam::apps::plot_cli_test
