#include "hoidslam/detect/yolo_decode.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::detect {
namespace {

using ::testing::HasSubstr;

// A 64×64 input has 8×8 + 4×4 + 2×2 = 84 anchor points; the tensors below use two classes.
const cv::Size kInput(64, 64);
constexpr int kAnchors = 84;

cv::Mat ZeroTensor(int rows, int cols) {
  const int sizes[] = {1, rows, cols};
  return cv::Mat(3, sizes, CV_32F, cv::Scalar(0));
}

void ExpectBox(const cv::Rect2f& box, float x, float y, float w, float h) {
  EXPECT_NEAR(box.x, x, 1e-4);
  EXPECT_NEAR(box.y, y, 1e-4);
  EXPECT_NEAR(box.width, w, 1e-4);
  EXPECT_NEAR(box.height, h, 1e-4);
}

TEST(YoloLayout, ParsesEveryNameAndNamesTheParameterOnError) {
  for (const char* name : {"auto", "yolox", "yolov5", "yolov8"}) {
    EXPECT_EQ(ToString(ParseYoloLayout(name, "Detector.layout")), name);
  }
  EXPECT_EQ(ParseYoloLayout("yolo11", "Detector.layout"), YoloLayout::kYolov8);
  try {
    ParseYoloLayout("yolov3", "Detector.layout");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("Detector.layout"));
    EXPECT_THAT(e.what(), HasSubstr("yolov3"));
  }
}

TEST(AnchorPointCount, SumsTheThreeStrides) {
  EXPECT_EQ(AnchorPointCount({416, 416}), 3549);
  EXPECT_EQ(AnchorPointCount({640, 640}), 8400);
  EXPECT_EQ(AnchorPointCount(kInput), kAnchors);
  EXPECT_EQ(AnchorPointCount({640, 384}), 80 * 48 + 40 * 24 + 20 * 12);
}

TEST(MatchOutputShape, RecognisesEachLayoutAndItsClassCount) {
  const auto yolox = MatchOutputShape({1, 3549, 85}, {416, 416}, YoloLayout::kAuto);
  ASSERT_TRUE(yolox);
  EXPECT_EQ(yolox->layout, YoloLayout::kYolox);
  EXPECT_EQ(yolox->num_classes, 80);

  const auto yolov5 = MatchOutputShape({1, 25200, 85}, {640, 640}, YoloLayout::kAuto);
  ASSERT_TRUE(yolov5);
  EXPECT_EQ(yolov5->layout, YoloLayout::kYolov5);
  EXPECT_EQ(yolov5->num_classes, 80);

  const auto yolov8 = MatchOutputShape({1, 84, 8400}, {640, 640}, YoloLayout::kAuto);
  ASSERT_TRUE(yolov8);
  EXPECT_EQ(yolov8->layout, YoloLayout::kYolov8);
  EXPECT_EQ(yolov8->num_classes, 80);
}

TEST(MatchOutputShape, RejectsUnknownShapesAndOtherLayoutsThanTheRequestedOne) {
  EXPECT_FALSE(MatchOutputShape({1, 7, 9}, {416, 416}, YoloLayout::kAuto));
  EXPECT_FALSE(MatchOutputShape({1, 3, 416, 416}, {416, 416}, YoloLayout::kAuto));
  EXPECT_FALSE(MatchOutputShape({2, 3549, 85}, {416, 416}, YoloLayout::kAuto));
  EXPECT_FALSE(MatchOutputShape({1, 8400, 85}, {416, 416}, YoloLayout::kAuto));  // a 640 model at 416
  EXPECT_FALSE(MatchOutputShape({1, 3549, 85}, {416, 416}, YoloLayout::kYolov8));
  EXPECT_TRUE(MatchOutputShape({1, 3549, 85}, {416, 416}, YoloLayout::kYolox));
}

TEST(ExpectedShapes, ListsTheShapesForTheInputSize) {
  const std::string all = ExpectedShapes({416, 416}, YoloLayout::kAuto);
  EXPECT_THAT(all, HasSubstr("1×3549×(5+C) for YOLOX"));
  EXPECT_THAT(all, HasSubstr("1×10647×(5+C) for YOLOv5"));
  EXPECT_THAT(all, HasSubstr("1×(4+C)×3549 for YOLOv8"));
  EXPECT_THAT(ExpectedShapes({416, 416}, YoloLayout::kYolov5), ::testing::Not(HasSubstr("YOLOX")));
  EXPECT_EQ(ShapeToString({1, 7, 9}), "1×7×9");
}

TEST(DecodeOutput, YoloxDecodesGridOffsetsAndLogSizes) {
  cv::Mat tensor = ZeroTensor(kAnchors, 5 + 2);
  // Stride 16 (after the 64 stride-8 points), grid x = 1, y = 2 in its 4×4 grid.
  float* row = tensor.ptr<float>() + (64 + 2 * 4 + 1) * 7;
  const float values[] = {0.5F, 0.25F, std::log(2.0F), 0.0F, 0.9F, 0.2F, 0.8F};
  std::copy(std::begin(values), std::end(values), row);
  // A weak point that the threshold removes.
  float* weak = tensor.ptr<float>() + 3 * 7;
  weak[4] = 0.3F;
  weak[5] = 0.5F;

  const auto candidates = DecodeOutput(tensor, {YoloLayout::kYolox, 2}, kInput, 0.25F);
  ASSERT_EQ(candidates.size(), 1U);
  // cx = (0.5 + 1) * 16 = 24, cy = (0.25 + 2) * 16 = 36, w = 2 * 16, h = 1 * 16.
  ExpectBox(candidates[0].box, 8.0F, 28.0F, 32.0F, 16.0F);
  EXPECT_EQ(candidates[0].class_id, 1);
  EXPECT_NEAR(candidates[0].score, 0.9F * 0.8F, 1e-6);
}

TEST(DecodeOutput, Yolov5MultipliesObjectnessAndClassScore) {
  cv::Mat tensor = ZeroTensor(3 * kAnchors, 5 + 2);
  float* row = tensor.ptr<float>() + 10 * 7;
  const float values[] = {30.0F, 20.0F, 10.0F, 8.0F, 0.5F, 0.9F, 0.1F};
  std::copy(std::begin(values), std::end(values), row);

  const auto candidates = DecodeOutput(tensor, {YoloLayout::kYolov5, 2}, kInput, 0.25F);
  ASSERT_EQ(candidates.size(), 1U);
  ExpectBox(candidates[0].box, 25.0F, 16.0F, 10.0F, 8.0F);
  EXPECT_EQ(candidates[0].class_id, 0);
  EXPECT_NEAR(candidates[0].score, 0.45F, 1e-6);
}

TEST(DecodeOutput, Yolov8ReadsColumnsWithoutObjectness) {
  cv::Mat tensor = ZeroTensor(4 + 2, kAnchors);
  float* data = tensor.ptr<float>();
  const int column = 5;
  const float values[] = {40.0F, 12.0F, 20.0F, 4.0F, 0.1F, 0.6F};
  for (int k = 0; k < 6; ++k) data[k * kAnchors + column] = values[k];

  const auto candidates = DecodeOutput(tensor, {YoloLayout::kYolov8, 2}, kInput, 0.25F);
  ASSERT_EQ(candidates.size(), 1U);
  ExpectBox(candidates[0].box, 30.0F, 10.0F, 20.0F, 4.0F);
  EXPECT_EQ(candidates[0].class_id, 1);
  EXPECT_NEAR(candidates[0].score, 0.6F, 1e-6);
}

TEST(DecodeOutput, DropsNanScores) {
  cv::Mat tensor = ZeroTensor(3 * kAnchors, 5 + 2);
  float* row = tensor.ptr<float>();
  const float values[] = {30.0F, 20.0F, 10.0F, 8.0F, std::nanf(""), 0.9F, 0.1F};
  std::copy(std::begin(values), std::end(values), row);
  EXPECT_TRUE(DecodeOutput(tensor, {YoloLayout::kYolov5, 2}, kInput, 0.25F).empty());
}

TEST(DecodeOutput, RejectsATensorOfAnotherFormat) {
  EXPECT_THROW(DecodeOutput(ZeroTensor(7, 9), {YoloLayout::kYolox, 2}, kInput, 0.25F), core::Error);
  EXPECT_THROW(DecodeOutput(ZeroTensor(kAnchors, 7), {YoloLayout::kYolox, 3}, kInput, 0.25F), core::Error);
}

TEST(Letterbox, TopLeftPlacementPadsRightAndBelowWithGrey) {
  const cv::Mat image(480, 640, CV_8UC3, cv::Scalar(10, 20, 30));
  LetterboxTransform transform;
  const cv::Mat boxed = Letterbox(image, {416, 416}, LetterboxPlacement::kTopLeft, transform);
  ASSERT_EQ(boxed.size(), cv::Size(416, 416));
  EXPECT_FLOAT_EQ(transform.scale, 0.65F);
  EXPECT_EQ(transform.offset, cv::Point2f(0, 0));
  EXPECT_EQ(boxed.at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(boxed.at<cv::Vec3b>(311, 415), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(boxed.at<cv::Vec3b>(312, 0), cv::Vec3b(114, 114, 114));
}

TEST(Letterbox, CentrePlacementSplitsThePaddingAndToImageUndoesIt) {
  const cv::Mat image(480, 640, CV_8UC3, cv::Scalar(10, 20, 30));
  LetterboxTransform transform;
  const cv::Mat boxed = Letterbox(image, {416, 416}, LetterboxPlacement::kCentre, transform);
  EXPECT_EQ(transform.offset, cv::Point2f(0, 52));
  EXPECT_EQ(boxed.at<cv::Vec3b>(51, 200), cv::Vec3b(114, 114, 114));
  EXPECT_EQ(boxed.at<cv::Vec3b>(52, 200), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(boxed.at<cv::Vec3b>(363, 200), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(boxed.at<cv::Vec3b>(364, 200), cv::Vec3b(114, 114, 114));
  // The image box (100, 200, 40, 80) sits at (65, 52 + 130, 26, 52) in the network input.
  ExpectBox(transform.ToImage({65.0F, 182.0F, 26.0F, 52.0F}), 100.0F, 200.0F, 40.0F, 80.0F);
}

TEST(Letterbox, ImageFarThinnerThanTheInputKeepsAtLeastOnePixel) {
  const cv::Mat sliver(2000, 1, CV_8UC3, cv::Scalar(10, 20, 30));
  LetterboxTransform transform;
  const cv::Mat boxed = Letterbox(sliver, {416, 416}, LetterboxPlacement::kTopLeft, transform);
  EXPECT_EQ(boxed.at<cv::Vec3b>(100, 0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(boxed.at<cv::Vec3b>(100, 1), cv::Vec3b(114, 114, 114));
}

TEST(ClassWiseNms, SuppressesOverlapsWithinAClassOnly) {
  const std::vector<Candidate> candidates = {
      {{0, 0, 100, 100}, 0, 0.6F},  // overlaps the next one (IoU 0.90): suppressed
      {{5, 5, 95, 95}, 0, 0.9F},
      {{0, 0, 100, 100}, 1, 0.5F},    // same place, another class: kept
      {{200, 200, 50, 50}, 0, 0.7F},  // same class, elsewhere: kept
  };
  EXPECT_THAT(ClassWiseNms(candidates, 0.45F), ::testing::ElementsAre(1U, 3U, 2U));
  EXPECT_THAT(ClassWiseNms(candidates, 0.95F), ::testing::ElementsAre(1U, 3U, 0U, 2U));
  EXPECT_TRUE(ClassWiseNms({}, 0.45F).empty());
}

}  // namespace
}  // namespace hoidslam::detect
