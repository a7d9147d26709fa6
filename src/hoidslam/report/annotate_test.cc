#include "hoidslam/report/annotate.h"

#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace hoidslam::report {
namespace {

TEST(DrawBoxAnnotations, ColoursDynamicRedAndStaticGreenWithoutTouchingTheInput) {
  const cv::Mat black(100, 200, CV_8UC3, cv::Scalar::all(0));
  const std::vector<BoxAnnotation> annotations = {
      {cv::Rect2f(10, 40, 50, 50), "", false},
      {cv::Rect2f(120, 40, 50, 50), "person", true},
  };
  const cv::Mat drawn = DrawBoxAnnotations(black, annotations);
  EXPECT_EQ(cv::countNonZero(black.reshape(1)), 0);
  const cv::Vec3b static_edge = drawn.at<cv::Vec3b>(60, 10);
  const cv::Vec3b dynamic_edge = drawn.at<cv::Vec3b>(60, 120);
  EXPECT_GT(static_edge[1], static_edge[2]);    // green
  EXPECT_GT(dynamic_edge[2], dynamic_edge[1]);  // red
  EXPECT_EQ(drawn.at<cv::Vec3b>(65, 35), cv::Vec3b(0, 0, 0));  // box interiors stay as they were
}

TEST(DrawBoxAnnotations, BoxesPartlyOutsideTheImageAreClipped) {
  const cv::Mat grey(50, 50, CV_8UC3, cv::Scalar::all(128));
  const std::vector<BoxAnnotation> annotations = {{cv::Rect2f(-30, -30, 200, 200), "a long caption text", true}};
  const cv::Mat drawn = DrawBoxAnnotations(grey, annotations);
  EXPECT_EQ(drawn.size(), grey.size());
  EXPECT_NE(cv::norm(drawn, grey, cv::NORM_INF), 0.0);
}

TEST(DrawKeptAndDropped, KeptGreenDroppedRed) {
  cv::Mat image(60, 120, CV_8UC3, cv::Scalar::all(0));
  const std::vector<cv::KeyPoint> keypoints = {cv::KeyPoint(30, 30, 7), cv::KeyPoint(90, 30, 7)};
  DrawKeptAndDropped(image, keypoints, std::vector<std::uint8_t>{1, 0});
  const cv::Vec3b kept = image.at<cv::Vec3b>(30, 33);  // on the ring
  const cv::Vec3b dropped = image.at<cv::Vec3b>(30, 93);
  EXPECT_GT(kept[1], kept[2]);
  EXPECT_GT(dropped[2], dropped[1]);
  EXPECT_EQ(image.at<cv::Vec3b>(5, 60), cv::Vec3b(0, 0, 0));
}

}  // namespace
}  // namespace hoidslam::report
