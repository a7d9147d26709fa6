#include "hoidslam/pipeline/exclusion.h"

#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"

namespace hoidslam::pipeline {
namespace {

core::Detection Det(const std::string& label, float x, float y, float w, float h) {
  return {.class_id = -1, .label = label, .score = 0.9F, .box = cv::Rect2f(x, y, w, h)};
}

core::RgbdFrame Frame(const std::string& rgb_path = "rgb/1.000000.png") {
  core::RgbdFrame frame;
  frame.timestamp = 1.0;
  frame.rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  frame.depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(2.0F));
  frame.rgb_path = rgb_path;
  return frame;
}

const std::vector<cv::KeyPoint> kKeypoints = {cv::KeyPoint(10, 10, 31),     // outside every box
                                              cv::KeyPoint(150, 200, 31),   // in the person
                                              cv::KeyPoint(255, 205, 31),   // in the cup the person holds
                                              cv::KeyPoint(500, 100, 31)};  // in a tv nobody touches

const std::vector<core::Detection> kDetections = {Det("person", 100, 100, 150, 300), Det("cup", 220, 190, 40, 40),
                                                  Det("tv", 450, 50, 100, 100)};

TEST(SetFilterMode, AcceptsTheHoidModesAndOracle) {
  ExclusionOptions options;
  SetFilterMode("person", options);
  EXPECT_EQ(options.hoid.mode, core::FilterMode::kPerson);
  EXPECT_FALSE(options.oracle);
  EXPECT_EQ(options.ModeName(), "person");
  SetFilterMode("oracle", options);
  EXPECT_TRUE(options.oracle);
  EXPECT_EQ(options.ModeName(), "oracle");
  EXPECT_FALSE(options.NeedsDetections());
  SetFilterMode("none", options);
  EXPECT_FALSE(options.NeedsDetections());
  SetFilterMode("hoid3d", options);
  EXPECT_TRUE(options.NeedsDetections());
}

TEST(SetFilterMode, HoidPlusTakesItsPartsByName) {
  ExclusionOptions options;
  SetFilterMode("hoidplus", options);
  EXPECT_EQ(options.hoid.mode, core::FilterMode::kHoidPlus);
  EXPECT_EQ(options.ModeName(), "hoidplus");
  EXPECT_TRUE(options.SafetyNet());
  SetFilterMode("hoidplus:memory+depth", options);
  EXPECT_TRUE(options.hoid.plus.depth);
  EXPECT_TRUE(options.hoid.plus.memory);
  EXPECT_FALSE(options.hoid.plus.safety_net);
  EXPECT_FALSE(options.SafetyNet());
  EXPECT_EQ(options.ModeName(), "hoidplus:depth+memory");
  SetFilterMode("hoidplus:net", options);
  EXPECT_EQ(options.ModeName(), "hoidplus:net");
  EXPECT_TRUE(options.SafetyNet());
  // Plain hoidplus keeps the parts the settings switched on.
  SetFilterMode("hoidplus", options);
  EXPECT_EQ(options.ModeName(), "hoidplus:net");
  for (const char* bad : {"hoidplus:", "hoidplus:depth+", "hoidplus:depth+legs"}) {
    EXPECT_THAT([&] { SetFilterMode(bad, options, "--filter"); },
                ::testing::ThrowsMessage<core::InputError>(
                    ::testing::AllOf(::testing::HasSubstr("--filter"), ::testing::HasSubstr("depth, memory and net"))))
        << bad;
  }
}

TEST(KeypointExclusion, HoidPlusKeepsWhatIsBehindThePersonAndRemembersThem) {
  ExclusionOptions options;
  SetFilterMode("hoidplus", options);
  KeypointExclusion exclusion(options, ".");
  core::RgbdFrame frame = Frame();
  frame.depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(4.0F));
  frame.depth(cv::Rect(120, 120, 110, 260)).setTo(2.0F);  // the person, in front of the wall
  const std::vector<cv::KeyPoint> keypoints = {cv::KeyPoint(150, 200, 31), cv::KeyPoint(104, 390, 31)};
  const std::vector<core::Detection> person = {Det("person", 100, 100, 150, 300)};
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  for (int k = 0; k < 2; ++k) {
    frame.timestamp = k / 30.0;
    exclusion.Mark(frame, person, keypoints, cv::Mat(), keep, boxes);
    exclusion.AfterTracking(core::Pose::Identity());
  }
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 1}));  // the person dropped, the wall behind them kept
  frame.timestamp = 2 / 30.0;
  exclusion.Mark(frame, {}, keypoints, cv::Mat(), keep, boxes);  // the detector missed them
  ASSERT_EQ(boxes.detections.size(), 1U);
  EXPECT_EQ(boxes.decisions[0].reason, hoid::Reason::kCarried);
  EXPECT_EQ(keep[0], 0);
  const cv::Mat painted = exclusion.PaintDropped(frame, boxes);
  EXPECT_EQ(painted.at<std::uint8_t>(200, 150), 255);
  EXPECT_EQ(painted.at<std::uint8_t>(390, 104), 0);
}

TEST(SetFilterMode, NamesTheParameterAndTheChoices) {
  ExclusionOptions options;
  try {
    SetFilterMode("everything", options, "--filter");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("--filter"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("oracle"));
  }
}

TEST(KeypointExclusion, Hoid2dDropsThePersonAndTheObjectInHand) {
  ExclusionOptions options;
  SetFilterMode("hoid2d", options);
  KeypointExclusion exclusion(options, ".");
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  exclusion.Mark(Frame(), kDetections, kKeypoints, cv::Mat(), keep, boxes);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{1, 0, 0, 1}));
  ASSERT_EQ(boxes.decisions.size(), 3U);
  EXPECT_TRUE(boxes.decisions[1].dynamic);
  EXPECT_FALSE(boxes.decisions[2].dynamic);
}

TEST(KeypointExclusion, NoneKeepsEverything) {
  ExclusionOptions options;
  SetFilterMode("none", options);
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  KeypointExclusion(options, ".").Mark(Frame(), kDetections, kKeypoints, cv::Mat(), keep, boxes);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{1, 1, 1, 1}));
}

TEST(KeypointExclusion, OracleDropsExactlyTheMaskedKeypointsAndIgnoresBoxes) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "mask");
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(490, 90, 20, 20)).setTo(255);  // only the tv moves, whatever the boxes say
  cv::imwrite((dir / "mask" / "1.000000.png").string(), mask);

  ExclusionOptions options;
  SetFilterMode("oracle", options);
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  const std::vector<hoid::Decision>& decisions = boxes.decisions;
  KeypointExclusion(options, dir.path()).Mark(Frame(), kDetections, kKeypoints, cv::Mat(), keep, boxes);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{1, 1, 1, 0}));
  for (const hoid::Decision& d : decisions) EXPECT_FALSE(d.dynamic);
}

TEST(KeypointExclusion, TheStaticMapLeavesOutWhatTheFilterDropsAndForOracleEveryPerson) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "mask");
  std::filesystem::create_directories(dir / "people");
  cv::Mat moving(480, 640, CV_8UC1, cv::Scalar(0));
  moving(cv::Rect(490, 90, 20, 20)).setTo(255);  // the tv moves
  cv::imwrite((dir / "mask" / "1.000000.png").string(), moving);
  cv::Mat people(480, 640, CV_8UC1, cv::Scalar(0));
  people(cv::Rect(100, 100, 150, 300)).setTo(255);  // a person sits still: static for tracking, not for the map
  cv::imwrite((dir / "people" / "1.000000.png").string(), people);

  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  ExclusionOptions oracle;
  SetFilterMode("oracle", oracle);
  KeypointExclusion by_oracle(oracle, dir.path());
  by_oracle.Mark(Frame(), kDetections, kKeypoints, cv::Mat(), keep, boxes);
  const cv::Mat left_out = by_oracle.StaticMapExclusion(Frame(), boxes, {1.0, 0.15});
  EXPECT_EQ(cv::countNonZero(left_out), 20 * 20 + 150 * 300);
  EXPECT_EQ(left_out.at<std::uint8_t>(200, 150), 255);

  ExclusionOptions hoid2d;
  SetFilterMode("hoid2d", hoid2d);
  KeypointExclusion by_filter(hoid2d, dir.path());
  by_filter.Mark(Frame(), kDetections, kKeypoints, cv::Mat(), keep, boxes);
  const cv::Mat painted = by_filter.PaintDropped(Frame(), boxes);
  EXPECT_EQ(cv::countNonZero(by_filter.StaticMapExclusion(Frame(), boxes, {1.0, 0.15}) != painted), 0);
}

TEST(KeypointExclusion, TheStaticMapLeavesOutLegsFartherBehindATorsoThanTrackingDropsAndKeepsTheWall) {
  core::RgbdFrame frame = Frame();
  frame.depth.setTo(3.0F);                                // a wall
  frame.depth(cv::Rect(100, 100, 150, 200)).setTo(1.0F);  // a torso facing the camera
  frame.depth(cv::Rect(150, 300, 50, 100)).setTo(1.8F);   // the legs, seen from above: farther away
  ExclusionOptions options;
  SetFilterMode("hoidplus", options);
  KeypointExclusion exclusion(options, "");
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  const std::vector<core::Detection> person = {Det("person", 100, 100, 150, 300)};
  exclusion.Mark(frame, person, kKeypoints, cv::Mat(), keep, boxes);

  const cv::Mat tracking = exclusion.PaintDropped(frame, boxes);
  EXPECT_EQ(tracking.at<std::uint8_t>(200, 150), 255);  // the torso
  EXPECT_EQ(tracking.at<std::uint8_t>(350, 175), 0);    // the legs, 0.8 m behind: kept for tracking
  const cv::Mat map = exclusion.StaticMapExclusion(frame, boxes, {1.0, 0.05});
  EXPECT_EQ(map.at<std::uint8_t>(200, 150), 255);
  EXPECT_EQ(map.at<std::uint8_t>(350, 175), 255);  // left out of the map
  EXPECT_EQ(map.at<std::uint8_t>(350, 120), 0);    // the wall behind the person is fused
  // Never less than what tracking drops.
  EXPECT_EQ(cv::countNonZero(exclusion.StaticMapExclusion(frame, boxes, {0.2, 0.0}) != tracking), 0);
}

TEST(KeypointExclusion, TheStaticMapLeavesOutAPersonsEdgeTheBoxCutOffAndKeepsTheWallBesideIt) {
  core::RgbdFrame frame = Frame();
  frame.depth.setTo(3.0F);                                // a wall
  frame.depth(cv::Rect(100, 100, 150, 300)).setTo(1.0F);  // a person
  frame.depth(cv::Rect(88, 350, 8, 50)).setTo(1.7F);      // a chair beside them, 0.7 m behind
  ExclusionOptions options;
  SetFilterMode("hoidplus", options);
  KeypointExclusion exclusion(options, "");
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  const std::vector<core::Detection> cut_off = {Det("person", 115, 100, 135, 300)};  // 15 px of the person outside
  exclusion.Mark(frame, cut_off, kKeypoints, cv::Mat(), keep, boxes);

  const cv::Mat tracking = exclusion.PaintDropped(frame, boxes);
  EXPECT_EQ(tracking.at<std::uint8_t>(200, 150), 255);
  EXPECT_EQ(tracking.at<std::uint8_t>(200, 105), 0);  // the person's edge, outside the box and its 5 %: kept
  const cv::Mat map = exclusion.StaticMapExclusion(frame, boxes, {1.0, 0.15});
  EXPECT_EQ(map.at<std::uint8_t>(200, 105), 255);  // left out of the map
  EXPECT_EQ(map.at<std::uint8_t>(200, 95), 0);     // the wall beside the person, inside the grown box: fused
  EXPECT_EQ(map.at<std::uint8_t>(80, 150), 0);     // and above
  // The chair, inside the grown box and within the metre the map reaches behind the person, but beyond what
  // tracking drops: the box reaches that far, its margin no farther than tracking.
  EXPECT_EQ(map.at<std::uint8_t>(370, 95), 0);
  // The person, all of it, with the 3 pixels the foreground grows by (HOIDplus.edgeMargin), and nothing else.
  EXPECT_EQ(cv::countNonZero(map), (150 + 6) * (300 + 6));
}

TEST(KeypointExclusion, ScoresAnyModeAgainstTheMovingMask) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "mask");
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(140, 190, 20, 20)).setTo(255);  // the person moves, the cup in hand does not
  cv::imwrite((dir / "mask" / "1.000000.png").string(), mask);

  ExclusionOptions options;
  SetFilterMode("hoid2d", options);
  KeypointExclusion exclusion(options, dir.path());
  ASSERT_TRUE(exclusion.CanScore());
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  exclusion.Mark(Frame(), kDetections, kKeypoints, cv::Mat(), keep, boxes);
  const ExclusionCounts counts = exclusion.Score(Frame(), kKeypoints, keep);
  EXPECT_EQ(counts.moving_dropped, 1U);  // the person
  EXPECT_EQ(counts.moving_kept, 0U);
  EXPECT_EQ(counts.static_dropped, 1U);  // the cup
  EXPECT_EQ(counts.static_kept, 2U);
  EXPECT_DOUBLE_EQ(counts.Leaked(), 0.0);
  EXPECT_DOUBLE_EQ(counts.Wasted(), 1.0 / 3.0);

  ExclusionCounts total;
  total += counts;
  total += exclusion.Score(Frame(), kKeypoints, std::vector<std::uint8_t>{1, 1, 1, 1});  // mode none
  EXPECT_DOUBLE_EQ(total.Leaked(), 0.5);
  EXPECT_DOUBLE_EQ(total.Wasted(), 1.0 / 6.0);
}

TEST(KeypointExclusion, SplitsTheWastedKeypointsIntoNoDepthStillPeopleAndTheRest) {
  testing::TempDir dir;
  for (const char* folder : {"mask", "people"}) std::filesystem::create_directories(dir / folder);
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(140, 190, 20, 20)).setTo(255);  // the person at (150, 200) walks
  cv::imwrite((dir / "mask" / "1.000000.png").string(), mask);
  cv::Mat people = mask.clone();
  people(cv::Rect(490, 90, 20, 20)).setTo(255);  // a person who stands still where the tv's box is
  cv::imwrite((dir / "people" / "1.000000.png").string(), people);
  core::RgbdFrame frame = Frame();
  frame.depth.at<float>(205, 255) = 0.0F;  // the cup's keypoint: no depth

  ExclusionOptions options;
  SetFilterMode("hoid2d", options);
  KeypointExclusion exclusion(options, dir.path());
  ASSERT_TRUE(exclusion.ScoresStillPeople());
  const std::vector<cv::KeyPoint> keypoints = {kKeypoints[0], kKeypoints[1], kKeypoints[2], kKeypoints[3],
                                               cv::KeyPoint(120, 120, 31)};  // the wall in the person's box
  const std::vector<std::uint8_t> keep = {1, 0, 0, 0, 0};  // everything in a box dropped
  const ExclusionCounts counts = exclusion.Score(frame, keypoints, keep);
  EXPECT_EQ(counts.moving_dropped, 1U);
  EXPECT_EQ(counts.static_kept, 1U);
  EXPECT_EQ(counts.static_dropped, 3U);
  EXPECT_EQ(counts.static_dropped_without_depth, 1U);    // the cup
  EXPECT_EQ(counts.static_dropped_on_still_people, 1U);  // the person standing still
  ExclusionCounts total;
  total += counts;
  total += counts;
  EXPECT_EQ(total.static_dropped_without_depth, 2U);
  EXPECT_EQ(total.static_dropped_on_still_people, 2U);

  // Without people masks only the keypoints without depth are told apart.
  std::filesystem::remove_all(dir / "people");
  const KeypointExclusion unscored(options, dir.path());
  EXPECT_FALSE(unscored.ScoresStillPeople());
  const ExclusionCounts without = unscored.Score(frame, keypoints, keep);
  EXPECT_EQ(without.static_dropped_without_depth, 1U);
  EXPECT_EQ(without.static_dropped_on_still_people, 0U);
}

TEST(KeypointExclusion, WithoutMasksThereIsNothingToScore) {
  ExclusionOptions options;
  SetFilterMode("hoid2d", options);
  EXPECT_FALSE(KeypointExclusion(options, ".").CanScore());
  EXPECT_DOUBLE_EQ(ExclusionCounts{}.Leaked(), 0.0);
  EXPECT_DOUBLE_EQ(ExclusionCounts{}.Wasted(), 0.0);
}

TEST(KeypointExclusion, OracleWithoutMasksIsAnErrorNamingTheFolder) {
  testing::TempDir dir;
  ExclusionOptions options;
  SetFilterMode("oracle", options);
  try {
    KeypointExclusion exclusion(options, dir.path());
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr((dir / "mask").string()));
  }
}

TEST(KeypointExclusion, OracleNamesAMissingMaskFile) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "mask");
  ExclusionOptions options;
  SetFilterMode("oracle", options);
  KeypointExclusion exclusion(options, dir.path());
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  try {
    exclusion.Mark(Frame("rgb/7.000000.png"), kDetections, kKeypoints, cv::Mat(), keep, boxes);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("7.000000.png"));
  }
}

}  // namespace
}  // namespace hoidslam::pipeline
