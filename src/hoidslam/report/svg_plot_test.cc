#include "hoidslam/report/svg_plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/report/test_markup.h"

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::report::svg_plot_test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The SVG is one balanced element, and no number in it is NaN or infinite.
void ExpectWellFormed(const std::string& svg) {
  EXPECT_TRUE(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\"")) << svg.substr(0, 80);
  EXPECT_TRUE(svg.ends_with("</svg>"));
  EXPECT_EQ(testing::UnbalancedTags(svg), "");
  std::string lower = svg;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  EXPECT_THAT(lower, Not(HasSubstr("nan")));
  EXPECT_THAT(lower, Not(HasSubstr("inf")));
}

// The pixel points of the `index`-th polyline.
std::vector<std::pair<double, double>> PolylinePoints(const std::string& svg, std::size_t index) {
  static const std::regex kPolyline(R"rx(<polyline[^>]* points="([^"]*)")rx");
  auto it = std::sregex_iterator(svg.begin(), svg.end(), kPolyline);
  std::advance(it, index);
  std::vector<std::pair<double, double>> points;
  std::istringstream in((*it)[1].str());
  double x = 0, y = 0;
  char comma = 0;
  while (in >> x >> comma >> y) points.emplace_back(x, y);
  return points;
}

// The heights of the bars filled with `colour`, left to right (bars have a tooltip, legend swatches not).
std::vector<double> BarHeights(const std::string& svg, std::string_view colour) {
  const std::regex rect(R"rx(<rect x="[^"]*" y="[^"]*" width="[^"]*" height="([^"]*)" fill=")rx" +
                        std::string(colour) + "\"><title>");
  std::vector<double> heights;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), rect); it != std::sregex_iterator(); ++it) {
    heights.push_back(std::stod((*it)[1].str()));
  }
  return heights;
}

TEST(FormatSignificant, KeepsTheDigitsAskedForWithoutExponentOrTrailingZeros) {
  EXPECT_EQ(FormatSignificant(0.0035, 3), "0.0035");
  EXPECT_EQ(FormatSignificant(3.4449, 3), "3.44");
  EXPECT_EQ(FormatSignificant(1250.0, 3), "1250");
  EXPECT_EQ(FormatSignificant(9.9996, 3), "10");
  EXPECT_EQ(FormatSignificant(-0.5, 2), "-0.5");
  EXPECT_EQ(FormatSignificant(0.0, 3), "0");
  EXPECT_EQ(FormatSignificant(kNaN, 3), "–");
}

TEST(EscapeXml, EscapesTheFiveSpecialCharacters) {
  EXPECT_EQ(EscapeXml("a<b & \"c\" 'd'>"), "a&lt;b &amp; &quot;c&quot; &#39;d&#39;&gt;");
  EXPECT_EQ(EscapeXml("plain"), "plain");
}

TEST(LineChart, HasAxesLabelsLegendAndOneLinePerSeries) {
  const std::vector<LineSeries> series = {{"hoid2d", {0, 1, 2, 3}, {0.01, 0.02, 0.015, 0.03}, ""},
                                          {"<none & co>", {0, 1, 2, 3}, {0.1, 0.2, 0.4, 0.8}, "#123456"}};
  const std::string svg = LineChart(series, {.title = "ATE over time", .x_label = "time (s)", .y_label = "error (m)"});
  ExpectWellFormed(svg);
  EXPECT_THAT(svg, HasSubstr("<title>ATE over time</title>"));
  EXPECT_THAT(svg, HasSubstr(">time (s)</text>"));
  EXPECT_THAT(svg, HasSubstr(">error (m)</text>"));
  EXPECT_THAT(svg, HasSubstr(">hoid2d</text>"));
  EXPECT_THAT(svg, HasSubstr(">&lt;none &amp; co&gt;</text>"));  // escaped, and the markup stays balanced
  EXPECT_THAT(svg, HasSubstr("stroke=\"#123456\""));
  EXPECT_THAT(svg, HasSubstr(std::string("stroke=\"") + std::string(PaletteColour(0)) + "\""));
  EXPECT_EQ(PolylinePoints(svg, 0).size(), 4U);
  EXPECT_EQ(PolylinePoints(svg, 1).size(), 4U);
  // Round ticks: 0.8 is the top of the second series and a tick of its own.
  EXPECT_THAT(svg, HasSubstr(">0.8</text>"));
}

TEST(LineChart, LaterPointsAreDrawnToTheRightAndHigherValuesHigher) {
  const std::vector<LineSeries> series = {{"", {0, 10}, {1, 5}, ""}};
  const auto points = PolylinePoints(LineChart(series, {}), 0);
  ASSERT_EQ(points.size(), 2U);
  EXPECT_GT(points[1].first, points[0].first);
  EXPECT_LT(points[1].second, points[0].second);  // SVG y grows downwards
}

TEST(LineChart, NaNBreaksTheLineAndALonePointIsADot) {
  const std::vector<LineSeries> series = {{"a", {0, 1, 2, 3, 4}, {1, 2, kNaN, 3, 4}, ""},
                                          {"b", {0, 1, 2}, {kNaN, 7, kNaN}, ""}};
  const std::string svg = LineChart(series, {});
  ExpectWellFormed(svg);
  EXPECT_EQ(PolylinePoints(svg, 0).size(), 2U);
  EXPECT_EQ(PolylinePoints(svg, 1).size(), 2U);
  EXPECT_THAT(svg, HasSubstr("<circle"));  // the single finite point of b
}

TEST(LineChart, DegenerateInputGivesAValidChart) {
  ExpectWellFormed(LineChart({}, {.title = "nothing"}));
  const std::vector<LineSeries> one = {{"one", {5}, {2}, ""}};
  ExpectWellFormed(LineChart(one, {}));
  const std::vector<LineSeries> flat = {{"flat", {1, 1, 1}, {5, 5, 5}, ""}};
  for (const bool from_zero : {true, false}) {
    const std::string svg = LineChart(flat, {.y_from_zero = from_zero});
    ExpectWellFormed(svg);
    EXPECT_THAT(svg, HasSubstr(">5")) << from_zero;  // the value is inside the axis range
  }
  const std::vector<LineSeries> zeros = {{"zeros", {0, 1}, {0, 0}, ""}};
  ExpectWellFormed(LineChart(zeros, {}));
  const std::vector<LineSeries> log_with_zero = {{"log", {0, 1, 2}, {0, 0.01, 1}, ""}};
  ExpectWellFormed(LineChart(log_with_zero, {.log_y = true}));
}

TEST(LineChart, RejectsSeriesOfUnequalLength) {
  const std::vector<LineSeries> bad = {{"bad", {0, 1}, {0}, ""}};
  EXPECT_THROW(LineChart(bad, {}), std::invalid_argument);
}

TEST(LargestExtentAxes, PicksTheTwoAxesAlongWhichThePathExtendsMost) {
  const std::vector<Eigen::Vector3d> xz = {{0, 0, 0}, {3, 0.1, 1}, {1, 0.2, 4}};
  EXPECT_EQ(LargestExtentAxes(xz), (std::array<int, 2>{0, 2}));
  const std::vector<Eigen::Vector3d> yz = {{0, 0, 0}, {0.1, 2, 1}};
  EXPECT_EQ(LargestExtentAxes(yz), (std::array<int, 2>{1, 2}));
  const std::vector<Eigen::Vector3d> flat = {{0, 0, 0}, {1, 1, 0}};
  EXPECT_EQ(LargestExtentAxes(flat), (std::array<int, 2>{0, 1}));
  const std::vector<Eigen::Vector3d> one = {{1, 2, 3}};
  EXPECT_EQ(LargestExtentAxes(one), (std::array<int, 2>{0, 1}));
}

TEST(PathPlot, OneMetreIsAsLongOnBothAxesWhateverTheChartShape) {
  // A 2 m x 1 m rectangle in the x-y plane.
  const std::vector<Path3d> paths = {{"ground truth", {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}}, ""}};
  for (const auto& [width, height] : {std::pair{700, 300}, std::pair{300, 700}, std::pair{400, 400}}) {
    const std::string svg = PathPlot(paths, {.width = width, .height = height});
    ExpectWellFormed(svg);
    const auto p = PolylinePoints(svg, 0);
    ASSERT_EQ(p.size(), 4U);
    const double two_metres = p[1].first - p[0].first;
    const double one_metre = p[1].second - p[2].second;  // world y up is SVG y down
    EXPECT_GT(one_metre, 10.0) << width << "x" << height;
    EXPECT_NEAR(two_metres, 2.0 * one_metre, 0.25) << width << "x" << height;
    EXPECT_NEAR(p[1].second, p[0].second, 0.05);  // a line along x stays horizontal
  }
}

TEST(PathPlot, LabelsTheWorldAxesShownAndDrawsEveryPath) {
  const std::vector<Path3d> paths = {
      {"ground truth", {{0, 1.5, 0}, {1, 1.5, 2}, {2, 1.6, 1}}, "#444444"},
      {"estimate & co", {{0, 1.5, 0.1}, {1, 1.5, 2.1}, {2, 1.6, 1.1}}, "", 2.0, true},
      {"failed run", {}, ""}};
  const std::string svg = PathPlot(paths, {.title = "from above"});
  ExpectWellFormed(svg);
  EXPECT_THAT(svg, HasSubstr(">world x (m)</text>"));
  EXPECT_THAT(svg, HasSubstr(">world z (m)</text>"));
  EXPECT_THAT(svg, HasSubstr(">estimate &amp; co</text>"));
  EXPECT_THAT(svg, HasSubstr(">failed run</text>"));  // in the legend although it has no points
  EXPECT_THAT(svg, HasSubstr("stroke-dasharray"));
  EXPECT_EQ(PolylinePoints(svg, 1).size(), 3U);
}

TEST(PathPlot, DegenerateInputGivesAValidChart) {
  ExpectWellFormed(PathPlot({}, {}));
  const std::vector<Path3d> one_point = {{"still", {{1, 2, 3}}, ""}};
  const std::string svg = PathPlot(one_point, {});
  ExpectWellFormed(svg);
  EXPECT_THAT(svg, HasSubstr("<circle"));
  const std::vector<Path3d> same_point = {{"still", {{1, 2, 3}, {1, 2, 3}, {1, 2, 3}}, ""}};
  ExpectWellFormed(PathPlot(same_point, {}));
  const std::vector<Path3d> with_nan = {{"gap", {{0, 0, 0}, {kNaN, 0, 0}, {1, 1, 0}}, ""}};
  ExpectWellFormed(PathPlot(with_nan, {}));
}

TEST(BarChart, GroupedBarsAreAsTallAsTheirValues) {
  const std::vector<std::string> categories = {"walking_xyz", "carry"};
  const std::vector<BarSeries> series = {{"hoid2d", {1.0, 2.0}, ""}, {"none", {4.0, kNaN}, ""}};
  const std::string svg = BarChart(categories, series, {.chart = {.title = "ATE", .y_label = "m"}});
  ExpectWellFormed(svg);
  const std::vector<double> hoid = BarHeights(svg, PaletteColour(0));
  ASSERT_EQ(hoid.size(), 2U);
  EXPECT_NEAR(hoid[1], 2.0 * hoid[0], 0.2);
  const std::vector<double> none = BarHeights(svg, PaletteColour(1));
  ASSERT_EQ(none.size(), 1U);  // the NaN is a mark, not a bar
  EXPECT_NEAR(none[0], 4.0 * hoid[0], 0.3);
  EXPECT_THAT(svg, HasSubstr(">×</text>"));
  EXPECT_THAT(svg, HasSubstr(">walking_xyz</text>"));
  EXPECT_THAT(svg, HasSubstr(">none</text>"));
  EXPECT_THAT(svg, HasSubstr(">4</text>"));  // value label
}

TEST(BarChart, StackedBarsAddUp) {
  const std::vector<std::string> categories = {"hoid2d"};
  const std::vector<BarSeries> series = {{"extract", {1.0}, ""}, {"track", {3.0}, ""}};
  const std::string svg = BarChart(categories, series, {.layout = BarLayout::kStacked});
  ExpectWellFormed(svg);
  const std::vector<double> extract = BarHeights(svg, PaletteColour(0));
  const std::vector<double> track = BarHeights(svg, PaletteColour(1));
  ASSERT_EQ(extract.size(), 1U);
  ASSERT_EQ(track.size(), 1U);
  EXPECT_NEAR(track[0], 3.0 * extract[0], 0.2);
  EXPECT_THAT(svg, HasSubstr(">4</text>"));  // the total above the stack
}

TEST(BarChart, LogScaleShowsDecades) {
  const std::vector<std::string> categories = {"a", "b"};
  const std::vector<BarSeries> series = {{"x", {0.003, 0.7}, ""}};
  const std::string svg = BarChart(categories, series, {.chart = {.log_y = true}});
  ExpectWellFormed(svg);
  for (const char* tick : {">0.001</text>", ">0.01</text>", ">0.1</text>", ">1</text>"}) {
    EXPECT_THAT(svg, HasSubstr(tick));
  }
  const std::vector<double> heights = BarHeights(svg, PaletteColour(0));
  ASSERT_EQ(heights.size(), 2U);
  EXPECT_GT(heights[1], heights[0]);
}

TEST(BarChart, LongCategoryNamesAreSlanted) {
  const std::vector<std::string> categories = {"walking_halfsphere", "walking_rpy_static", "sitting_static_x"};
  const std::vector<BarSeries> series = {{"", {1, 2, 3}, ""}};
  const std::string svg = BarChart(categories, series, {.chart = {.width = 300}});
  ExpectWellFormed(svg);
  EXPECT_THAT(svg, HasSubstr("rotate(-30"));
}

TEST(BarChart, DegenerateInputGivesAValidChart) {
  ExpectWellFormed(BarChart({}, {}, {}));
  const std::vector<std::string> categories = {"a", "b"};
  const std::vector<BarSeries> missing = {{"failed", {kNaN, kNaN}, ""}};
  ExpectWellFormed(BarChart(categories, missing, {}));
  ExpectWellFormed(BarChart(categories, missing, {.chart = {.log_y = true}}));
  const std::vector<BarSeries> zeros = {{"zero", {0, 0}, ""}};
  ExpectWellFormed(BarChart(categories, zeros, {}));
  ExpectWellFormed(BarChart(categories, zeros, {.layout = BarLayout::kStacked}));
}

TEST(BarChart, RejectsSeriesWithTheWrongNumberOfValues) {
  const std::vector<std::string> categories = {"a", "b"};
  const std::vector<BarSeries> bad = {{"bad", {1.0}, ""}};
  EXPECT_THROW(BarChart(categories, bad, {}), std::invalid_argument);
}

TEST(SequentialColour, RunsFromDarkBlueToYellowAndClampsOutside) {
  EXPECT_EQ(SequentialColour(0.0), "#440154");
  EXPECT_EQ(SequentialColour(1.0), "#fde725");
  EXPECT_EQ(SequentialColour(-3.0), SequentialColour(0.0));
  EXPECT_EQ(SequentialColour(7.0), SequentialColour(1.0));
  EXPECT_EQ(SequentialColour(kNaN), SequentialColour(0.0));
  // Brighter all the way: the sum of the channels grows.
  const auto brightness = [](const std::string& colour) {
    return std::stoi(colour.substr(1, 2), nullptr, 16) + std::stoi(colour.substr(3, 2), nullptr, 16) +
           std::stoi(colour.substr(5, 2), nullptr, 16);
  };
  for (int i = 1; i <= 10; ++i) {
    EXPECT_GT(brightness(SequentialColour(i / 10.0)), brightness(SequentialColour((i - 1) / 10.0))) << i;
  }
}

TEST(ValuePathPlot, ColoursEachStepByItsValueOnTheScaleWithAColourBar) {
  const std::vector<Path3d> references = {{"ground truth", {{0, 0, 0}, {1, 0, 0}, {2, 1, 0}}, "#bbbbbb", 1.5, true}};
  const ValuePath path{"estimate", {{0, 0.1, 0}, {1, 0.1, 0}, {2, 1.1, 0}}, {0.0, 0.0, 0.2}};
  const std::string svg =
      ToSvg(ValuePathPlotDrawing(references, path, {.low = 0.0, .high = 0.2, .label = "ATE (m)"}, {.title = "errors"}));
  ExpectWellFormed(svg);
  EXPECT_EQ(PolylinePoints(svg, 1).size(), 2U);  // after the reference: one line a step
  EXPECT_THAT(svg, HasSubstr("stroke=\"" + SequentialColour(0.0) + "\" stroke-width=\"3.0\""));  // value 0
  EXPECT_THAT(svg, HasSubstr("stroke=\"" + SequentialColour(1.0) + "\" stroke-width=\"3.0\""));  // value 0.2
  EXPECT_THAT(svg, HasSubstr(">ATE (m)</text>"));
  EXPECT_THAT(svg, HasSubstr(">0.20</text>"));  // the colour bar's top tick
  EXPECT_THAT(svg, HasSubstr(">estimate</text>"));
  const ValuePath uneven{"bad", {{0, 0, 0}}, {}};
  EXPECT_THROW(ValuePathPlotDrawing(references, uneven, {}, {}), std::invalid_argument);
  EXPECT_THROW(ValuePathPlotDrawing(references, path, {.low = 1.0, .high = 1.0}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::report::svg_plot_test
