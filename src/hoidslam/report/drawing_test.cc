#include "hoidslam/report/drawing.h"

#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/report/test_markup.h"

namespace hoidslam::report::drawing_test {
namespace {

using ::testing::HasSubstr;

TEST(ToSvg, WritesEveryShapeInOrderOnAWhiteBackground) {
  Drawing drawing(200, 100, "a <title>");
  drawing.Add(LineShape{{0, 0}, {10, 20}, {.colour = "#112233", .width = 2.0, .dashed = true}});
  drawing.Add(PolylineShape{{{1, 2}, {3, 4}, {5, 6}}, {.colour = "#445566", .width = 3.0}});
  drawing.Add(CircleShape{.centre = {50, 50}, .radius = 4.0, .fill = "#778899", .tooltip = "start"});
  drawing.Add(RectShape{.top_left = {5, 6}, .width = 7, .height = 8, .fill = "#aabbcc"});
  drawing.Add(TextShape{.baseline = {20, 30}, .text = "x & y", .anchor = TextAnchor::kEnd, .angle = 90.0});
  const std::string svg = ToSvg(drawing);
  EXPECT_EQ(testing::UnbalancedTags(svg), "");
  EXPECT_THAT(svg, HasSubstr(R"(viewBox="0 0 200 100")"));
  EXPECT_THAT(svg, HasSubstr("<title>a &lt;title&gt;</title>"));
  EXPECT_THAT(svg, HasSubstr(R"(<rect width="200" height="100" fill="#ffffff"/>)"));
  EXPECT_THAT(svg, HasSubstr(R"(<line x1="0.0" y1="0.0" x2="10.0" y2="20.0" stroke="#112233" stroke-width="2.0" )"
                             R"(stroke-dasharray="6 4"/>)"));
  EXPECT_THAT(svg, HasSubstr(R"(stroke-width="3.0")"));
  EXPECT_THAT(svg, HasSubstr(R"(points="1.0,2.0 3.0,4.0 5.0,6.0")"));
  EXPECT_THAT(svg, HasSubstr(R"(fill="#778899"><title>start</title></circle>)"));
  EXPECT_THAT(svg, HasSubstr(R"(<rect x="5.0" y="6.0" width="7.0" height="8.0" fill="#aabbcc"/>)"));
  EXPECT_THAT(svg, HasSubstr(R"x(text-anchor="end" transform="rotate(-90 20.0 30.0)">x &amp; y</text>)x"));
  EXPECT_LT(svg.find("<line"), svg.find("<polyline"));
  EXPECT_LT(svg.find("<circle"), svg.find("<text"));
}

TEST(Drawing, PlaceMovesEveryShapeOfAnotherDrawing) {
  Drawing panel(50, 50);
  panel.Add(LineShape{{1, 2}, {3, 4}, {.colour = "#000000"}});
  panel.Add(PolylineShape{{{0, 0}, {1, 1}}, {.colour = "#000000"}});
  panel.Add(CircleShape{.centre = {5, 5}, .fill = "#000000"});
  panel.Add(RectShape{.top_left = {6, 7}, .width = 1, .height = 1, .fill = "#000000"});
  panel.Add(TextShape{.baseline = {8, 9}, .text = "t"});
  Drawing figure(100, 50);
  figure.Place(panel, {50, 0});
  const std::string svg = ToSvg(figure);
  EXPECT_THAT(svg, HasSubstr(R"(x1="51.0" y1="2.0" x2="53.0" y2="4.0")"));
  EXPECT_THAT(svg, HasSubstr(R"(points="50.0,0.0 51.0,1.0")"));
  EXPECT_THAT(svg, HasSubstr(R"(cx="55.0" cy="5.0")"));
  EXPECT_THAT(svg, HasSubstr(R"(x="56.0" y="7.0")"));
  EXPECT_THAT(svg, HasSubstr(R"(x="58.0" y="9.0")"));
}

TEST(Drawing, RefusesAnEmptySize) { EXPECT_THROW(Drawing(0, 10), std::invalid_argument); }

}  // namespace
}  // namespace hoidslam::report::drawing_test
