#include "hoidslam/hoid/explain.h"

#include <vector>

#include <gtest/gtest.h>

namespace hoidslam::hoid {
namespace {

core::Detection MakeDetection(const char* label, float score, cv::Rect2f box) {
  core::Detection d;
  d.label = label;
  d.score = score;
  d.box = box;
  return d;
}

TEST(Explain, DescribesAnInteractionWithItsPersonAndRatio) {
  const std::vector<core::Detection> detections = {MakeDetection("person", 0.93F, {0, 0, 100, 200}),
                                                   MakeDetection("cup", 0.81F, {90, 50, 20, 20})};
  const std::vector<Decision> decisions = ClassifyDetections(detections, core::HoidOptions{});
  EXPECT_EQ(DescribeDecision(detections, decisions, 0), "person 0.93 dynamic: person");
  EXPECT_EQ(DescribeDecision(detections, decisions, 1), "cup 0.81 dynamic: interaction with person#0 (50%)");
  EXPECT_EQ(CaptionDecision(detections[1], decisions[1]), "cup 0.81 held 50%");
  EXPECT_EQ(CaptionDecision(detections[0], decisions[0]), "person 0.93");
}

TEST(Explain, DescribesADepthRejectionWithBothDepths) {
  // A tv inside a person's box but 1 m behind the person: the 3D rule keeps it static.
  const std::vector<core::Detection> detections = {MakeDetection("person", 0.9F, {0, 0, 40, 40}),
                                                   MakeDetection("tv", 0.7F, {20, 20, 20, 20})};
  core::HoidOptions options;
  options.mode = core::FilterMode::kHoid3d;
  options.sample_box_size = 4;
  cv::Mat depth(60, 60, CV_32FC1, cv::Scalar(1.5F));
  depth(cv::Rect(20, 20, 20, 20)).setTo(2.5F);
  const std::vector<Decision> decisions = ClassifyDetections(detections, options, depth);
  ASSERT_EQ(decisions[1].reason, Reason::kDepthRejected);
  EXPECT_EQ(DescribeDecision(detections, decisions, 1),
            "tv 0.70 static: depth_rejected with person#0 (100%), depth 2.50 vs 1.50 m");
  EXPECT_EQ(CaptionDecision(detections[1], decisions[1]), "tv 0.70 behind 1.00m");
}

}  // namespace
}  // namespace hoidslam::hoid
