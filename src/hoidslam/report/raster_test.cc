#include "hoidslam/report/raster.h"

#include <stdexcept>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace hoidslam::report::raster_test {
namespace {

// Pixels of `image` inside `box` that are not white.
int InkIn(const cv::Mat& image, const cv::Rect& box) {
  int ink = 0;
  for (int y = box.y; y < box.y + box.height; ++y) {
    for (int x = box.x; x < box.x + box.width; ++x) ink += image.at<cv::Vec3b>(y, x) != cv::Vec3b(255, 255, 255);
  }
  return ink;
}

TEST(RenderImage, PaintsShapesWhereTheSvgPutsThemInTheirColours) {
  Drawing drawing(120, 80);
  drawing.Add(RectShape{.top_left = {10, 10}, .width = 20, .height = 10, .fill = "#ff0000"});
  drawing.Add(LineShape{{0, 60}, {119, 60}, {.colour = "#0000ff", .width = 3.0}});
  drawing.Add(CircleShape{.centre = {90, 20}, .radius = 6.0, .fill = "#00ff00"});
  const cv::Mat image = RenderImage(drawing);
  ASSERT_EQ(image.size(), cv::Size(120, 80));
  ASSERT_EQ(image.type(), CV_8UC3);
  EXPECT_EQ(image.at<cv::Vec3b>(15, 20), cv::Vec3b(0, 0, 255));  // BGR: red
  EXPECT_EQ(image.at<cv::Vec3b>(60, 60), cv::Vec3b(255, 0, 0));  // blue
  EXPECT_EQ(image.at<cv::Vec3b>(20, 90), cv::Vec3b(0, 255, 0));  // green
  EXPECT_EQ(image.at<cv::Vec3b>(40, 60), cv::Vec3b(255, 255, 255));  // background
}

TEST(RenderImage, DashedLinesLeaveGaps) {
  Drawing drawing(100, 20);
  drawing.Add(LineShape{{0, 10}, {100, 10}, {.colour = "#000000", .dashed = true}});
  const cv::Mat image = RenderImage(drawing);
  int gaps = 0;
  for (int x = 1; x < 99; ++x) gaps += image.at<cv::Vec3b>(10, x) == cv::Vec3b(255, 255, 255);
  EXPECT_GT(gaps, 12);  // 4 of every 10 pixels are off, less what the anti-aliased ends blur; a solid line leaves none
  EXPECT_LT(gaps, 55);
}

TEST(RenderImage, TextSitsOnItsAnchorLevelOrTurned) {
  Drawing level(200, 200);
  level.Add(TextShape{.baseline = {100, 100}, .text = "ATE over time", .anchor = TextAnchor::kEnd});
  const cv::Mat a = RenderImage(level);
  EXPECT_GT(InkIn(a, {20, 88, 80, 14}), 40);  // left of the anchor, above the baseline
  EXPECT_EQ(InkIn(a, {102, 0, 98, 200}), 0);  // nothing right of it

  Drawing turned(200, 200);
  turned.Add(TextShape{.baseline = {100, 100}, .text = "ATE over time", .anchor = TextAnchor::kStart, .angle = 90.0});
  const cv::Mat b = RenderImage(turned);
  EXPECT_GT(InkIn(b, {88, 20, 14, 80}), 40);  // read upwards from the anchor, left of it
  EXPECT_EQ(InkIn(b, {0, 103, 200, 97}), 0);  // nothing below it
}

TEST(RenderImage, RefusesAColourItCannotRead) {
  Drawing drawing(10, 10);
  drawing.Add(RectShape{.top_left = {0, 0}, .width = 5, .height = 5, .fill = "red"});
  EXPECT_THROW(RenderImage(drawing), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::report::raster_test
