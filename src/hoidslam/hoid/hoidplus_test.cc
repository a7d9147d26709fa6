#include "hoidslam/hoid/hoidplus.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "hoidslam/core/error.h"

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::hoid::hoidplus_test {
namespace {

using core::Detection;

constexpr double kDt = 1.0 / 30.0;

Detection Det(const std::string& label, float x, float y, float w, float h) {
  return Detection{.class_id = -1, .label = label, .score = 0.9F, .box = cv::Rect2f(x, y, w, h)};
}

core::HoidOptions Options(bool depth, bool memory) {
  core::HoidOptions options;
  options.mode = core::FilterMode::kHoidPlus;
  options.plus.depth = depth;
  options.plus.memory = memory;
  return options;
}

// A room: the wall at 4 m, each detection's box painted at the depth given.
cv::Mat Room(const std::vector<std::pair<cv::Rect, float>>& things) {
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(4.0F));
  for (const auto& [box, z] : things) depth(box).setTo(z);
  return depth;
}

// One frame through the filter with no keypoints; returns the judged boxes.
JudgedBoxes Judge(HoidPlusFilter& filter, double t, const std::vector<Detection>& detections, const cv::Mat& depth) {
  JudgedBoxes boxes;
  std::vector<std::uint8_t> keep;
  filter.Filter(t, depth, detections, {}, cv::Mat(), boxes, keep);
  return boxes;
}

TEST(HoidPlusFilter, WithoutMemoryJudgesEachFrameByTheHoidRule) {
  HoidPlusFilter filter(Options(false, false), {});
  const std::vector<Detection> detections = {Det("person", 100, 50, 200, 400), Det("cup", 150, 200, 30, 40),
                                             Det("tv", 400, 100, 100, 80)};
  const JudgedBoxes boxes = Judge(filter, 0.0, detections, cv::Mat());
  ASSERT_EQ(boxes.detections.size(), 3U);
  EXPECT_EQ(boxes.decisions[0].reason, Reason::kPerson);
  EXPECT_EQ(boxes.decisions[1].reason, Reason::kInteraction);
  EXPECT_EQ(boxes.decisions[2].reason, Reason::kNoInteraction);
  EXPECT_EQ(boxes.context[0].track, 0U);
  // The next frame without the person: nothing remembers them.
  EXPECT_TRUE(Judge(filter, kDt, {}, cv::Mat()).detections.empty());
}

TEST(HoidPlusFilter, DepthConfirmsAnObjectInHandAndRejectsOneOnTheWallBehind) {
  HoidPlusFilter filter(Options(true, false), {});
  const std::vector<Detection> detections = {Det("person", 100, 50, 200, 400), Det("cup", 150, 200, 30, 40),
                                             Det("tv", 120, 60, 60, 40)};
  // The person at 2 m; the cup in their hand just in front; the tv on the wall behind, seen past their shoulder.
  const cv::Mat depth = Room({{cv::Rect(130, 90, 150, 360), 2.0F}, {cv::Rect(150, 200, 30, 40), 1.8F},
                              {cv::Rect(120, 60, 60, 40), 3.9F}});
  const JudgedBoxes boxes = Judge(filter, 0.0, detections, depth);
  EXPECT_EQ(boxes.decisions[1].reason, Reason::kDepthConfirmed);
  EXPECT_TRUE(boxes.decisions[1].dynamic);
  EXPECT_EQ(boxes.decisions[2].reason, Reason::kDepthRejected);
  EXPECT_FALSE(boxes.decisions[2].dynamic);
  EXPECT_NEAR(boxes.decisions[2].depth_difference, 1.9F, 0.05F);
  // Without depth the 2D verdict stands.
  const JudgedBoxes blind = Judge(filter, kDt, detections, Room({{cv::Rect(0, 0, 640, 480), 0.0F}}));
  EXPECT_EQ(blind.decisions[1].reason, Reason::kDepthUnavailable);
  EXPECT_TRUE(blind.decisions[1].dynamic);
}

// A detector that calls a desk by a seated person a laptop (fr1_rpy with YOLOX-Nano: a 450 × 464 px "laptop" at
// 0.9 m, 0.8 m across): no person handles a laptop that size, so it is not dropped, and memory does not hold it.
TEST(HoidPlusFilter, AnObjectTooLargeForItsClassIsNotHandled) {
  HoidPlusFilter filter(Options(true, true), {});
  // The person at 1.2 m; a "laptop" box over most of the image at 0.9 m; a real laptop in their hands at 1 m.
  const std::vector<Detection> detections = {Det("person", 200, 40, 220, 420), Det("laptop", 100, 30, 450, 440),
                                             Det("laptop", 260, 250, 110, 70)};
  const cv::Mat depth = Room({{cv::Rect(100, 30, 450, 440), 0.9F}, {cv::Rect(200, 40, 220, 420), 1.2F},
                              {cv::Rect(260, 250, 110, 70), 1.0F}});
  for (int frame = 0; frame < 3; ++frame) {
    const JudgedBoxes boxes = Judge(filter, frame * kDt, detections, depth);
    ASSERT_EQ(boxes.detections.size(), 3U);
    EXPECT_EQ(boxes.decisions[1].reason, Reason::kTooLargeToHandle) << frame;
    EXPECT_FALSE(boxes.decisions[1].dynamic);
    EXPECT_GT(boxes.decisions[1].extent, 0.7F);  // 450 px at its foreground's depth; a laptop is at most 0.6 m
    EXPECT_LT(boxes.decisions[2].extent, 0.3F);
    EXPECT_EQ(boxes.decisions[2].reason, Reason::kDepthConfirmed) << frame;  // 0.2 m across: in hand
  }
  // Switched off, the 2D rule and depth decide alone.
  core::HoidOptions unchecked = Options(true, true);
  unchecked.plus.size_check = false;
  HoidPlusFilter lenient(unchecked, {});
  EXPECT_TRUE(Judge(lenient, 0.0, detections, depth).decisions[1].dynamic);
}

TEST(HoidPlusFilter, KeepsTheBackgroundOfAPersonsBoxAndDropsThePerson) {
  HoidPlusFilter filter(Options(true, false), {});
  const cv::Mat depth = Room({{cv::Rect(150, 100, 100, 350), 2.0F}});
  const std::vector<cv::KeyPoint> keypoints = {cv::KeyPoint(200, 200, 31), cv::KeyPoint(110, 200, 31),
                                               cv::KeyPoint(500, 200, 31)};
  JudgedBoxes boxes;
  std::vector<std::uint8_t> keep;
  filter.Filter(0.0, depth, std::vector{Det("person", 100, 80, 200, 390)}, keypoints, cv::Mat(), boxes, keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 1, 1}));
  ASSERT_TRUE(boxes.context[0].foreground);
  EXPECT_NEAR(boxes.context[0].foreground->median, 2.0F, 0.01F);
}

TEST(HoidPlusFilter, AConfirmedPersonTheDetectorMissesStaysExcludedForAWhile) {
  core::HoidOptions options = Options(false, true);
  options.plus.max_missed_seconds = 0.2;
  HoidPlusFilter filter(options, {});
  const Detection person = Det("person", 100, 50, 200, 400);
  Judge(filter, 0.0, {person}, cv::Mat());
  Judge(filter, kDt, {person}, cv::Mat());  // seen twice: confirmed
  double t = 2 * kDt;
  for (int missed = 1; t <= 2 * kDt + 0.2 - kDt + 1e-9; ++missed, t += kDt) {
    const JudgedBoxes boxes = Judge(filter, t, {}, cv::Mat());
    ASSERT_EQ(boxes.detections.size(), 1U) << missed;
    EXPECT_TRUE(boxes.decisions[0].dynamic);
    EXPECT_EQ(boxes.decisions[0].reason, Reason::kCarried);
    EXPECT_EQ(boxes.context[0].missed_frames, missed);
    EXPECT_EQ(boxes.context[0].carry, Carry::kVelocity);  // no descriptors given
    EXPECT_EQ(boxes.detections[0].label, "person");
  }
  EXPECT_TRUE(Judge(filter, t + kDt, {}, cv::Mat()).detections.empty());  // gone after max_missed_seconds
}

TEST(HoidPlusFilter, ASingleSightingIsNotCarried) {
  HoidPlusFilter filter(Options(false, true), {});
  Judge(filter, 0.0, {Det("person", 100, 50, 200, 400)}, cv::Mat());  // perhaps a false positive
  EXPECT_TRUE(Judge(filter, kDt, {}, cv::Mat()).detections.empty());
}

TEST(HoidPlusFilter, AMissedBoxIsCarriedByItsKeypointsMotion) {
  HoidPlusFilter filter(Options(false, true), {});
  // Keypoints on the person with distinct descriptors; between frames everything moves 12 px right, 4 px down.
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors(40, 32, CV_8UC1);
  cv::RNG rng(3);
  rng.fill(descriptors, cv::RNG::UNIFORM, 0, 256);
  for (int i = 0; i < 40; ++i) keypoints.emplace_back(120.0F + 4.0F * i, 100.0F + 7.0F * i, 31.0F);
  const auto moved = [&](int frames) {
    std::vector<cv::KeyPoint> out = keypoints;
    for (cv::KeyPoint& k : out) k.pt += cv::Point2f(12.0F * frames, 4.0F * frames);
    return out;
  };
  JudgedBoxes boxes;
  std::vector<std::uint8_t> keep;
  const Detection person = Det("person", 100, 50, 200, 400);
  filter.Filter(0.0, cv::Mat(), std::vector{person}, moved(0), descriptors, boxes, keep);
  Detection next = person;
  next.box.x += 12;
  next.box.y += 4;
  filter.Filter(kDt, cv::Mat(), std::vector{next}, moved(1), descriptors, boxes, keep);
  filter.Filter(2 * kDt, cv::Mat(), std::vector<Detection>{}, moved(2), descriptors, boxes, keep);
  ASSERT_EQ(boxes.detections.size(), 1U);
  EXPECT_EQ(boxes.context[0].carry, Carry::kKeypoints);
  EXPECT_FLOAT_EQ(boxes.detections[0].box.x, 124.0F);
  EXPECT_FLOAT_EQ(boxes.detections[0].box.y, 58.0F);
  EXPECT_EQ(keep.size(), 40U);
  for (const std::uint8_t k : keep) EXPECT_EQ(k, 0);  // the carried box still drops the person's keypoints
}

TEST(HoidPlusFilter, AConfusedClassIsOutvotedByTheTrack) {
  HoidPlusFilter filter(Options(false, true), {});
  const Detection person = Det("person", 100, 50, 200, 400);
  Judge(filter, 0.0, {person}, cv::Mat());
  Judge(filter, kDt, {person}, cv::Mat());
  Detection confused = person;
  confused.label = "chair";
  const JudgedBoxes boxes = Judge(filter, 2 * kDt, {confused}, cv::Mat());
  EXPECT_EQ(boxes.detections[0].label, "person");
  EXPECT_EQ(boxes.decisions[0].reason, Reason::kPerson);
  // A box of another class that overlaps less is a new track with its own label.
  const JudgedBoxes other = Judge(filter, 3 * kDt, {person, Det("chair", 250, 300, 100, 150)}, cv::Mat());
  EXPECT_EQ(other.detections[1].label, "chair");
  EXPECT_NE(other.context[1].track, other.context[0].track);
}

// A cup on a desk: a person reaches it, and the cup is put down elsewhere or back where it stood.
class HandledObject : public ::testing::Test {
 protected:
  HandledObject() : filter_(Options(true, true), {}) {}

  Decision Step(bool person_here, const cv::Rect& cup) {
    std::vector<Detection> detections = {Det("cup", static_cast<float>(cup.x), static_cast<float>(cup.y),
                                             static_cast<float>(cup.width), static_cast<float>(cup.height))};
    std::vector<std::pair<cv::Rect, float>> things = {{cup, 2.0F}};
    if (person_here) {
      detections.push_back(Det("person", static_cast<float>(cup.x - 50), 50, 150, 400));
      things.insert(things.begin(), {cv::Rect(cup.x - 40, 60, 130, 380), 2.1F});
    }
    const JudgedBoxes boxes = Judge(filter_, t_, detections, Room(things));
    filter_.Localize(core::Pose::Identity());  // the camera stands still
    t_ += kDt;
    return boxes.decisions[0];
  }

  HoidPlusFilter filter_;
  double t_ = 0.0;
};

TEST_F(HandledObject, StaysDynamicAfterTheHandUntilSeenStillWhereItWasPut) {
  const cv::Rect desk(300, 250, 30, 30), shelf(420, 250, 30, 30);
  for (int i = 0; i < 45; ++i) EXPECT_FALSE(Step(false, desk).dynamic);  // 1.5 s on the desk
  EXPECT_EQ(Step(true, desk).reason, Reason::kDepthConfirmed);
  EXPECT_TRUE(Step(true, shelf).dynamic);
  // Put down on the shelf: dynamic until it has stood still there for stillSeconds (1 s = 30 frames).
  int frames_dynamic = 0;
  Decision d;
  while ((d = Step(false, shelf)).dynamic && frames_dynamic < 100) {
    EXPECT_EQ(d.reason, Reason::kRecentlyHandled);
    ++frames_dynamic;
  }
  EXPECT_EQ(d.reason, Reason::kSeenStill);
  EXPECT_GE(frames_dynamic, 29);
  EXPECT_LE(frames_dynamic, 32);
}

TEST_F(HandledObject, AnObjectAPersonOnlyPassedIsReleasedAtOnce) {
  const cv::Rect desk(300, 250, 30, 30);
  for (int i = 0; i < 45; ++i) Step(false, desk);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(Step(true, desk).dynamic);  // the HOID rule, as long as it holds
  EXPECT_TRUE(Step(false, desk).dynamic);  // its place after the pass is not measured yet
  EXPECT_EQ(Step(false, desk).reason, Reason::kSeenStill);
}

TEST(HoidPlusFilter, RejectsBadInput) {
  core::HoidOptions options = Options(true, true);
  options.plus.valley = 0.0;
  EXPECT_THROW(HoidPlusFilter(options, {}), core::InputError);
  HoidPlusFilter filter(Options(true, true), {});
  JudgedBoxes boxes;
  std::vector<std::uint8_t> keep;
  EXPECT_THROW(filter.Filter(0.0, cv::Mat(480, 640, CV_16UC1), {}, {}, cv::Mat(), boxes, keep), std::invalid_argument);
  const std::vector<cv::KeyPoint> one = {cv::KeyPoint(1, 1, 31)};
  EXPECT_THROW(filter.Filter(0.0, cv::Mat(), {}, one, cv::Mat(2, 32, CV_8UC1), boxes, keep), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::hoid::hoidplus_test
