#include "hoidslam/viewer/frame_snapshot.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace hoidslam::viewer {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// A frame with three keypoints (the middle one dropped), a person and the cup in their hands.
struct TrackedFrame {
  core::RgbdFrame frame;
  pipeline::FrameOutcome outcome;

  TrackedFrame() {
    frame.timestamp = 12.5;
    frame.rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(40, 80, 120));
    outcome.features.keypoints = {cv::KeyPoint(10.04F, 20.0F, 7.0F), cv::KeyPoint(300.0F, 200.0F, 7.0F),
                                  cv::KeyPoint(600.0F, 400.0F, 7.0F)};
    outcome.keep = {1, 0, 1};
    outcome.boxes.detections = {{0, "person", 0.9F, cv::Rect2f(250, 100, 150, 300)},
                                {41, "cup", 0.8F, cv::Rect2f(290, 180, 20, 30)}};
    hoid::Decision person{.dynamic = true, .reason = hoid::Reason::kPerson};
    hoid::Decision cup{.dynamic = true, .reason = hoid::Reason::kInteraction, .person_index = 0,
                       .interaction_ratio = 0.72F};
    outcome.boxes.decisions = {person, cup};
    core::Pose T_cw = core::Pose::Identity();
    T_cw.translation() = Eigen::Vector3d(0.0, 0.0, -1.0);
    outcome.result.T_cw = T_cw;
    outcome.entry = {{"frame", 7},
                     {"state", "ok"},
                     {"method", "motion_model"},
                     {"map", 0},
                     {"keyframe", true},
                     {"features", {{"extracted", 3}, {"kept", 2}, {"dropped", 1}, {"matched", 2}, {"inliers", 2}}},
                     {"ms", {{"extract", 4.1}, {"track", 2.5}}}};
  }
};

TEST(FrameEventJson, CarriesWhatThePageDrawsAndTheLogsCounts) {
  const TrackedFrame tracked;
  const FrameSnapshot snapshot = SnapshotOf(7, tracked.frame, tracked.outcome);
  const nlohmann::json event = nlohmann::json::parse(FrameEventJson(snapshot, 29.96, 0.5, 80));
  EXPECT_EQ(event["index"], 7);
  EXPECT_EQ(event["state"], "ok");
  EXPECT_EQ(event["method"], "motion_model");
  EXPECT_EQ(event["kept"], 2);
  EXPECT_EQ(event["dropped"], 1);
  EXPECT_EQ(event["keypoints"], nlohmann::json::parse("[10.0, 20.0, 300.0, 200.0, 600.0, 400.0]"));
  EXPECT_EQ(event["keep"], nlohmann::json::parse("[1, 0, 1]"));
  EXPECT_EQ(event["T_wc"][11], 1.0);  // the camera stands 1 m along z: T_wc inverts T_cw
  EXPECT_EQ(event["width"], 640);
  EXPECT_THAT(event["image"].get<std::string>(), StartsWith("data:image/jpeg;base64,/9j/"));  // a JPEG's first bytes
  ASSERT_EQ(event["boxes"].size(), 2U);
  EXPECT_EQ(event["boxes"][1]["label"], "cup");
  EXPECT_TRUE(event["boxes"][1]["dynamic"]);
  EXPECT_THAT(event["boxes"][1]["caption"].get<std::string>(), HasSubstr("held 72%"));
  EXPECT_THAT(event["boxes"][1]["reason"].get<std::string>(), HasSubstr("person#0"));
  EXPECT_TRUE(event["box_age"].is_null());
  EXPECT_EQ(event["times"]["extract"], 4.1);
  EXPECT_EQ(event["fps"], 30.0);
}

TEST(FrameEventJson, ALostFrameHasNoPoseAndSaysWhy) {
  TrackedFrame tracked;
  tracked.outcome.result.T_cw.reset();
  tracked.outcome.entry["state"] = "lost";
  tracked.outcome.entry["failure"] = "pose_rejected";
  tracked.outcome.entry["detections"] = {{"age_frames", 2}, {"age_ms", 66.7}};
  const nlohmann::json event =
      nlohmann::json::parse(FrameEventJson(SnapshotOf(8, tracked.frame, tracked.outcome), 0.0, 1.0, 80));
  EXPECT_TRUE(event["T_wc"].is_null());
  EXPECT_EQ(event["failure"], "pose_rejected");
  EXPECT_EQ(event["box_age"]["frames"], 2);
}

}  // namespace
}  // namespace hoidslam::viewer
