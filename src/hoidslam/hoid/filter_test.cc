#include "hoidslam/hoid/filter.h"

#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::hoid {
namespace {

using core::Detection;
using core::FilterMode;

Detection Det(const std::string& label, float x, float y, float w, float h) {
  return Detection{.class_id = -1, .label = label, .score = 0.9F, .box = cv::Rect2f(x, y, w, h)};
}

core::HoidOptions Options(FilterMode mode) {
  core::HoidOptions options;
  options.mode = mode;
  return options;
}

// A 640×480 depth image at `background` metres with `value` painted over `region`.
cv::Mat DepthImage(float background) { return cv::Mat(480, 640, CV_32FC1, cv::Scalar(background)); }
void Paint(cv::Mat& depth, const cv::Rect& region, float value) { depth(region).setTo(cv::Scalar(value)); }

// ---- 2D rule: the paper's Figure 4 cases --------------------------------------------------------------

TEST(Hoid2d, ObjectFullyInsidePersonIsDynamic) {
  const std::vector<Detection> dets = {Det("person", 100, 50, 200, 400), Det("cup", 150, 200, 30, 40)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid2d));
  ASSERT_EQ(d.size(), 2U);
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kPerson);
  EXPECT_TRUE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kInteraction);
  EXPECT_EQ(d[1].person_index, 0);
  EXPECT_FLOAT_EQ(d[1].interaction_ratio, 1.0F);
  EXPECT_TRUE(std::isnan(d[1].depth));  // depth is a hoid3d matter
}

TEST(Hoid2d, OverlapAboveThresholdIsDynamic) {
  // Cup 20×10 at x 90..110; person from x 100: half of the cup (0.5 > 0.4).
  const std::vector<Detection> dets = {Det("cup", 90, 100, 20, 10), Det("person", 100, 0, 100, 300)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid2d));
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kInteraction);
  EXPECT_EQ(d[0].person_index, 1);
  EXPECT_FLOAT_EQ(d[0].interaction_ratio, 0.5F);
}

TEST(Hoid2d, OverlapBelowThresholdIsStaticAndReportsTheOverlap) {
  // Chair 10×10 at x 100..110; person from x 107: 30 px² of 100 (0.3 < 0.4).
  const std::vector<Detection> dets = {Det("person", 107, 0, 100, 300), Det("chair", 100, 100, 10, 10)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid2d));
  EXPECT_FALSE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kNoInteraction);
  EXPECT_EQ(d[1].person_index, 0);
  EXPECT_FLOAT_EQ(d[1].interaction_ratio, 0.3F);
}

TEST(Hoid2d, RatioExactlyAtThresholdCountsAsInteracting) {
  // Object 10×10 at x 100..110; person from x 106 → 4×10 = 40 px² of 100: exactly 0.4.
  const std::vector<Detection> at = {Det("book", 100, 100, 10, 10), Det("person", 106, 0, 100, 300)};
  const std::vector<Decision> d = ClassifyDetections(at, Options(FilterMode::kHoid2d));
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kInteraction);
  EXPECT_FLOAT_EQ(d[0].interaction_ratio, 0.4F);

  // One pixel row less (36 px² of 100) is below it.
  const std::vector<Detection> below = {Det("book", 100, 100, 10, 10), Det("person", 106, 101, 100, 300)};
  const std::vector<Decision> b = ClassifyDetections(below, Options(FilterMode::kHoid2d));
  EXPECT_FALSE(b[0].dynamic);
  EXPECT_FLOAT_EQ(b[0].interaction_ratio, 0.36F);

  // Other thresholds the paper swept are exact too: 30 px² of 100 against 0.3.
  core::HoidOptions options = Options(FilterMode::kHoid2d);
  options.min_interaction_area = 0.3;
  const std::vector<Detection> at03 = {Det("book", 100, 100, 10, 10), Det("person", 107, 0, 100, 300)};
  EXPECT_TRUE(ClassifyDetections(at03, options)[0].dynamic);
}

TEST(Hoid2d, SeveralPersonsPickTheLargestRatio) {
  // Laptop 10×10 at 100..110: person 1 covers 5 columns (0.5), person 3 covers 8 (0.8), person 4 none.
  const std::vector<Detection> dets = {Det("laptop", 100, 100, 10, 10), Det("person", 105, 0, 100, 300),
                                       Det("tv", 300, 300, 50, 50), Det("person", 0, 0, 108, 300),
                                       Det("person", 400, 0, 100, 300)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid2d));
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].person_index, 3);
  EXPECT_FLOAT_EQ(d[0].interaction_ratio, 0.8F);
  EXPECT_FALSE(d[2].dynamic);  // the tv touches nobody
  EXPECT_EQ(d[2].reason, Reason::kNoInteraction);
  EXPECT_EQ(d[2].person_index, -1);
  EXPECT_EQ(d[2].interaction_ratio, 0.0F);
  for (int p : {1, 3, 4}) EXPECT_EQ(d[static_cast<std::size_t>(p)].reason, Reason::kPerson);
}

TEST(Hoid2d, EqualRatiosReportTheFirstPerson) {
  const std::vector<Detection> dets = {Det("person", 200, 0, 100, 300), Det("cup", 10, 10, 10, 10),
                                       Det("person", 0, 0, 100, 300), Det("person", 5, 5, 50, 50)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid2d));
  EXPECT_EQ(d[1].person_index, 2);
  EXPECT_FLOAT_EQ(d[1].interaction_ratio, 1.0F);
}

TEST(Hoid2d, ObjectWithoutPersonsIsStatic) {
  const std::vector<Detection> dets = {Det("cup", 10, 10, 20, 20), Det("mouse", 12, 12, 5, 5)};
  for (const Decision& d : ClassifyDetections(dets, Options(FilterMode::kHoid2d))) {
    EXPECT_FALSE(d.dynamic);
    EXPECT_EQ(d.reason, Reason::kNoInteraction);
    EXPECT_EQ(d.person_index, -1);
  }
}

TEST(Hoid2d, ClassesOutsideTheDynamicListAreNeverDynamic) {
  const std::vector<Detection> dets = {Det("person", 0, 0, 300, 300), Det("bus", 10, 10, 50, 50)};
  for (FilterMode mode : {FilterMode::kPerson, FilterMode::kClasses, FilterMode::kHoid2d, FilterMode::kHoid3d}) {
    const std::vector<Decision> d = ClassifyDetections(dets, Options(mode), DepthImage(2.0F));
    EXPECT_FALSE(d[1].dynamic) << ToString(mode);
    EXPECT_EQ(d[1].reason, Reason::kNotPotentiallyDynamic) << ToString(mode);
  }
}

TEST(Hoid2d, ClassListsComeFromTheOptions) {
  core::HoidOptions options = Options(FilterMode::kHoid2d);
  options.person_class = "human";
  options.dynamic_classes = {"cup"};
  const std::vector<Detection> dets = {Det("human", 0, 0, 300, 300), Det("cup", 10, 10, 50, 50),
                                       Det("chair", 10, 10, 50, 50), Det("person", 20, 20, 5, 5)};
  const std::vector<Decision> d = ClassifyDetections(dets, options);
  EXPECT_EQ(d[0].reason, Reason::kPerson);
  EXPECT_EQ(d[1].reason, Reason::kInteraction);
  EXPECT_EQ(d[2].reason, Reason::kNotPotentiallyDynamic);
  EXPECT_EQ(d[3].reason, Reason::kNotPotentiallyDynamic);  // "person" is just another label now
}

TEST(Hoid2d, ZeroAreaBoxesNeverInteract) {
  const std::vector<Detection> dets = {Det("person", 0, 0, 300, 300), Det("cup", 50, 50, 0, 10),
                                       Det("cup", 50, 50, 10, 0), Det("cup", 60, 60, -5, 10),
                                       Det("bottle", 400, 400, 10, 10), Det("person", 402, 402, 0, 0)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid2d));
  for (std::size_t i : {1U, 2U, 3U, 4U}) {
    EXPECT_FALSE(d[i].dynamic) << i;
    EXPECT_EQ(d[i].reason, Reason::kNoInteraction) << i;
    EXPECT_EQ(d[i].person_index, -1) << i;
    EXPECT_EQ(d[i].interaction_ratio, 0.0F) << i;
  }
  EXPECT_EQ(d[5].reason, Reason::kPerson);  // a degenerate person box is still a person
}

// ---- the other modes -----------------------------------------------------------------------------------

TEST(Modes, NoneKeepsEverything) {
  const std::vector<Detection> dets = {Det("person", 0, 0, 300, 300), Det("cup", 10, 10, 20, 20),
                                       Det("bus", 10, 10, 20, 20)};
  for (const Decision& d : ClassifyDetections(dets, Options(FilterMode::kNone))) {
    EXPECT_FALSE(d.dynamic);
    EXPECT_EQ(d.reason, Reason::kModeKeepsAll);
  }
}

TEST(Modes, PersonDropsOnlyPersons) {
  const std::vector<Detection> dets = {Det("person", 0, 0, 300, 300), Det("cup", 10, 10, 20, 20)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kPerson));
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kPerson);
  EXPECT_FALSE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kPersonsOnly);
}

TEST(Modes, ClassesDropEveryPotentiallyDynamicObjectWithoutLookingAtPersons) {
  const std::vector<Detection> dets = {Det("tv", 500, 10, 100, 80), Det("person", 0, 0, 100, 300)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kClasses));
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kClassPrior);
  EXPECT_EQ(d[0].person_index, -1);
  EXPECT_TRUE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kPerson);
}

// ---- 3D rule -------------------------------------------------------------------------------------------

// Person box 200×400 at (100, 40): centre (200, 240). Cup 40×40 at (180, 200): centre (200, 220), fully inside.
const cv::Rect2f kPersonBox(100, 40, 200, 400);
const cv::Rect2f kCupBox(180, 200, 40, 40);
// The 20×20 sample boxes at those centres.
const cv::Rect kPersonSample(190, 230, 20, 20);
const cv::Rect kCupSample(190, 210, 20, 20);

std::vector<Detection> PersonHoldingCup() {
  return {Det("person", kPersonBox.x, kPersonBox.y, kPersonBox.width, kPersonBox.height),
          Det("cup", kCupBox.x, kCupBox.y, kCupBox.width, kCupBox.height)};
}

TEST(Hoid3d, DepthsWithinThresholdConfirm) {
  cv::Mat depth = DepthImage(3.0F);
  Paint(depth, kPersonSample, 1.5F);
  Paint(depth, kCupSample, 1.4F);
  const std::vector<Decision> d = ClassifyDetections(PersonHoldingCup(), Options(FilterMode::kHoid3d), depth);
  EXPECT_TRUE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kDepthConfirmed);
  EXPECT_EQ(d[1].person_index, 0);
  EXPECT_FLOAT_EQ(d[1].depth, 1.4F);
  EXPECT_FLOAT_EQ(d[1].person_depth, 1.5F);
  EXPECT_NEAR(d[1].depth_difference, 0.1F, 1e-6F);
  EXPECT_FLOAT_EQ(d[0].depth, 1.5F);  // the person's own sample
}

TEST(Hoid3d, ObjectOneMetreBehindThePersonIsRejected) {
  // A person standing in front of a monitor: the boxes overlap in the image, the monitor is 1 m further away.
  const std::vector<Detection> dets = {Det("person", 100, 40, 200, 400), Det("tv", 150, 100, 200, 150)};
  cv::Mat depth = DepthImage(2.5F);
  Paint(depth, kPersonSample, 1.5F);
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid3d), depth);
  EXPECT_FALSE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kDepthRejected);
  EXPECT_EQ(d[1].person_index, 0);
  EXPECT_FLOAT_EQ(d[1].depth_difference, 1.0F);
  // The same scene in hoid2d drops the monitor.
  EXPECT_EQ(ClassifyDetections(dets, Options(FilterMode::kHoid2d))[1].reason, Reason::kInteraction);
}

TEST(Hoid3d, DifferenceEqualToThresholdDoesNotAgree) {
  core::HoidOptions options = Options(FilterMode::kHoid3d);
  options.depth_threshold = 0.25;  // exact in binary, as are the depths
  cv::Mat depth = DepthImage(1.0F);
  Paint(depth, kCupSample, 1.25F);
  EXPECT_EQ(ClassifyDetections(PersonHoldingCup(), options, depth)[1].reason, Reason::kDepthRejected);
  Paint(depth, kCupSample, 1.125F);
  EXPECT_EQ(ClassifyDetections(PersonHoldingCup(), options, depth)[1].reason, Reason::kDepthConfirmed);
}

TEST(Hoid3d, ZeroDepthInTheObjectBoxKeepsTheObjectDynamic) {
  cv::Mat depth = DepthImage(1.5F);
  Paint(depth, kCupSample, 0.0F);
  const std::vector<Decision> d = ClassifyDetections(PersonHoldingCup(), Options(FilterMode::kHoid3d), depth);
  EXPECT_TRUE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kDepthUnavailable);
  EXPECT_EQ(d[1].person_index, 0);
  EXPECT_TRUE(std::isnan(d[1].depth));
  EXPECT_FLOAT_EQ(d[1].person_depth, 1.5F);
  EXPECT_TRUE(std::isnan(d[1].depth_difference));
}

TEST(Hoid3d, ZeroDepthInThePersonBoxKeepsTheObjectDynamic) {
  cv::Mat depth = DepthImage(1.5F);
  Paint(depth, kPersonSample, 0.0F);
  const std::vector<Decision> d = ClassifyDetections(PersonHoldingCup(), Options(FilterMode::kHoid3d), depth);
  EXPECT_TRUE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kDepthUnavailable);
  EXPECT_FLOAT_EQ(d[1].depth, 1.5F);
  EXPECT_TRUE(std::isnan(d[1].person_depth));
}

TEST(Hoid3d, NoDepthImageKeepsThe2dVerdict) {
  const std::vector<Decision> d = ClassifyDetections(PersonHoldingCup(), Options(FilterMode::kHoid3d));
  EXPECT_TRUE(d[1].dynamic);
  EXPECT_EQ(d[1].reason, Reason::kDepthUnavailable);
}

TEST(Hoid3d, ObjectsFailingThe2dRuleAreNotSampled) {
  const std::vector<Detection> dets = {Det("person", 0, 0, 100, 300), Det("cup", 400, 400, 20, 20)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid3d), DepthImage(1.0F));
  EXPECT_EQ(d[1].reason, Reason::kNoInteraction);
  EXPECT_TRUE(std::isnan(d[1].depth));
  EXPECT_TRUE(std::isnan(d[0].depth));
}

// Cup 10×10 at (100, 100), centre (105, 105). Person 1 covers 8 columns (0.8), person 2 covers 5 (0.5).
std::vector<Detection> CupBetweenTwoPersons() {
  return {Det("cup", 100, 100, 10, 10), Det("person", 0, 0, 108, 300), Det("person", 105, 0, 200, 300)};
}
// Centres: person 1 (54, 150), person 2 (205, 150).
const cv::Rect kPerson1Sample(44, 140, 20, 20);
const cv::Rect kPerson2Sample(195, 140, 20, 20);

TEST(Hoid3d, AnyInteractingPersonWhoseDepthAgreesMakesItDynamic) {
  cv::Mat depth = DepthImage(1.0F);       // the cup's depth
  Paint(depth, kPerson1Sample, 2.0F);     // best ratio, a metre behind
  Paint(depth, kPerson2Sample, 1.1F);     // lower ratio, holding it
  const std::vector<Decision> d = ClassifyDetections(CupBetweenTwoPersons(), Options(FilterMode::kHoid3d), depth);
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kDepthConfirmed);
  EXPECT_EQ(d[0].person_index, 2);
  EXPECT_FLOAT_EQ(d[0].interaction_ratio, 0.5F);
  EXPECT_FLOAT_EQ(d[0].person_depth, 1.1F);
}

TEST(Hoid3d, ARejectingPersonDoesNotOverrideAnUncomparableOne) {
  cv::Mat depth = DepthImage(1.0F);
  Paint(depth, kPerson1Sample, 2.0F);
  Paint(depth, kPerson2Sample, 0.0F);
  std::vector<Decision> d = ClassifyDetections(CupBetweenTwoPersons(), Options(FilterMode::kHoid3d), depth);
  EXPECT_TRUE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kDepthUnavailable);
  EXPECT_EQ(d[0].person_index, 2);

  // Both valid and both far: rejected, reported against the best-ratio person.
  Paint(depth, kPerson2Sample, 3.0F);
  d = ClassifyDetections(CupBetweenTwoPersons(), Options(FilterMode::kHoid3d), depth);
  EXPECT_FALSE(d[0].dynamic);
  EXPECT_EQ(d[0].reason, Reason::kDepthRejected);
  EXPECT_EQ(d[0].person_index, 1);
  EXPECT_FLOAT_EQ(d[0].interaction_ratio, 0.8F);
  EXPECT_FLOAT_EQ(d[0].depth_difference, 1.0F);
}

TEST(Hoid3d, SharedPersonIsSampledForEveryObject) {
  cv::Mat depth = DepthImage(3.0F);
  Paint(depth, kPersonSample, 1.5F);
  Paint(depth, kCupSample, 1.4F);
  std::vector<Detection> dets = PersonHoldingCup();
  dets.push_back(Det("bottle", 120, 300, 20, 40));  // centre (130, 320): background, 1.5 m behind
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid3d), depth);
  EXPECT_EQ(d[1].reason, Reason::kDepthConfirmed);
  EXPECT_EQ(d[2].reason, Reason::kDepthRejected);
  EXPECT_FLOAT_EQ(d[2].person_depth, 1.5F);
}

// ---- input checks and buffer reuse ---------------------------------------------------------------------

TEST(ClassifyDetections, RejectsBadOptionsAndDepthType) {
  core::HoidOptions options = Options(FilterMode::kHoid2d);
  options.min_interaction_area = 0.0;
  EXPECT_THROW(ClassifyDetections(PersonHoldingCup(), options), core::InputError);
  const cv::Mat depth16(480, 640, CV_16UC1, cv::Scalar(1000));
  EXPECT_THROW(ClassifyDetections(PersonHoldingCup(), Options(FilterMode::kHoid3d), depth16), std::invalid_argument);
}

TEST(ClassifyDetections, ReusedVectorIsResizedAndReset) {
  cv::Mat depth = DepthImage(1.5F);
  std::vector<Decision> d(7);
  ClassifyDetections(PersonHoldingCup(), Options(FilterMode::kHoid3d), depth, d);
  ASSERT_EQ(d.size(), 2U);
  EXPECT_FALSE(std::isnan(d[1].depth));
  const std::vector<Detection> one = {Det("cup", 0, 0, 5, 5)};
  ClassifyDetections(one, Options(FilterMode::kHoid2d), depth, d);
  ASSERT_EQ(d.size(), 1U);
  EXPECT_EQ(d[0].reason, Reason::kNoInteraction);
  EXPECT_TRUE(std::isnan(d[0].depth));
  ClassifyDetections({}, Options(FilterMode::kHoid3d), depth, d);
  EXPECT_TRUE(d.empty());
}

TEST(Reason, EveryReasonHasItsOwnName) {
  std::set<std::string_view> names;
  for (Reason r : {Reason::kPerson, Reason::kModeKeepsAll, Reason::kNotPotentiallyDynamic, Reason::kPersonsOnly,
                   Reason::kClassPrior, Reason::kNoInteraction, Reason::kInteraction, Reason::kDepthConfirmed,
                   Reason::kDepthRejected, Reason::kDepthUnavailable}) {
    EXPECT_NE(ToString(r), "unknown");
    names.insert(ToString(r));
  }
  EXPECT_EQ(names.size(), 10U);
  EXPECT_EQ(ToString(Reason::kDepthUnavailable), "depth_unavailable");
}

// ---- depth sampling ------------------------------------------------------------------------------------

TEST(SampleDepth, MedianIgnoresInvalidPixels) {
  cv::Mat depth = DepthImage(0.0F);
  // 2×2 box at centre (11, 11) covers pixels 10..11 × 10..11; three valid values and one zero.
  depth.at<float>(10, 10) = 2.0F;
  depth.at<float>(10, 11) = 1.0F;
  depth.at<float>(11, 10) = 7.0F;
  EXPECT_FLOAT_EQ(SampleDepth(depth, {11.0F, 11.0F}, 2), 2.0F);
  depth.at<float>(11, 11) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FLOAT_EQ(SampleDepth(depth, {11.0F, 11.0F}, 2), 2.0F);
  depth.at<float>(11, 11) = std::numeric_limits<float>::infinity();
  EXPECT_FLOAT_EQ(SampleDepth(depth, {11.0F, 11.0F}, 2), 2.0F);
  depth.at<float>(11, 11) = -1.0F;
  EXPECT_FLOAT_EQ(SampleDepth(depth, {11.0F, 11.0F}, 2), 2.0F);
  // An even count averages the two middle values.
  depth.at<float>(11, 11) = 4.0F;
  EXPECT_FLOAT_EQ(SampleDepth(depth, {11.0F, 11.0F}, 2), 3.0F);
}

TEST(SampleDepth, MostlyInvalidBoxStillUsesItsValidPixels) {
  cv::Mat depth = DepthImage(0.0F);
  depth.at<float>(105, 103) = 1.75F;
  EXPECT_FLOAT_EQ(SampleDepth(depth, {100.0F, 100.0F}, 20), 1.75F);
  EXPECT_TRUE(std::isnan(SampleDepth(depth, {200.0F, 200.0F}, 20)));
}

TEST(SampleDepth, BoxCoversTheExpectedPixels) {
  // Every pixel holds a distinct depth, so a 1×1 box names the pixel it read.
  cv::Mat depth(480, 640, CV_32FC1);
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) depth.at<float>(y, x) = 1.0F + static_cast<float>(x) + 1000.0F * y;
  }
  EXPECT_FLOAT_EQ(SampleDepth(depth, {10.5F, 20.5F}, 1), depth.at<float>(20, 10));
  // 3×3 around pixel (10, 20): the median of a linear ramp is its centre.
  EXPECT_FLOAT_EQ(SampleDepth(depth, {10.5F, 20.5F}, 3), depth.at<float>(20, 10));
}

TEST(SampleDepth, BoxIsClippedAtTheImageBorder) {
  cv::Mat depth = DepthImage(5.0F);
  Paint(depth, cv::Rect(0, 0, 10, 10), 1.0F);  // the only part of a 20×20 box at the corner that is inside
  EXPECT_FLOAT_EQ(SampleDepth(depth, {0.0F, 0.0F}, 20), 1.0F);
  Paint(depth, cv::Rect(630, 470, 10, 10), 2.0F);
  EXPECT_FLOAT_EQ(SampleDepth(depth, {640.0F, 480.0F}, 20), 2.0F);
  EXPECT_TRUE(std::isnan(SampleDepth(depth, {-50.0F, 10.0F}, 20)));
  EXPECT_TRUE(std::isnan(SampleDepth(depth, {10.0F, 1e30F}, 20)));
  EXPECT_TRUE(std::isnan(SampleDepth(depth, {std::nanf(""), 10.0F}, 20)));
  EXPECT_TRUE(std::isnan(SampleDepth(cv::Mat(), {10.0F, 10.0F}, 20)));
}

TEST(SampleDepth, LargeBoxesWork) {
  cv::Mat depth = DepthImage(2.0F);
  Paint(depth, cv::Rect(0, 0, 640, 100), 0.0F);
  EXPECT_FLOAT_EQ(SampleDepth(depth, {320.0F, 240.0F}, 1000), 2.0F);
  EXPECT_THROW(SampleDepth(depth, {320.0F, 240.0F}, 0), std::invalid_argument);
}

TEST(Hoid3d, ObjectAtTheImageBorderSamplesItsVisiblePart) {
  // Cup box partly outside the image on the left; its centre (2, 250) leaves 12 of the 20 sample columns inside.
  const std::vector<Detection> dets = {Det("person", -50, 100, 120, 300), Det("cup", -8, 240, 20, 20)};
  cv::Mat depth = DepthImage(1.0F);
  Paint(depth, cv::Rect(0, 240, 12, 20), 1.05F);
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid3d), depth);
  EXPECT_EQ(d[1].reason, Reason::kDepthConfirmed);
  EXPECT_FLOAT_EQ(d[1].depth, 1.05F);
}

// ---- keypoint masking ----------------------------------------------------------------------------------

TEST(MarkKeypointsToKeep, BoxesAreHalfOpen) {
  const std::vector<Detection> dets = {Det("person", 10, 20, 30, 40)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kPerson));
  const std::vector<cv::Point2f> pts = {{10, 20},     {39.99F, 59.99F}, {25, 40},  {40, 30},
                                        {10, 60},     {9.99F, 30},      {25, 19.99F}, {500, 400}};
  std::vector<std::uint8_t> keep(3, 7);
  MarkKeypointsToKeep(pts, dets, d, keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 0, 0, 1, 1, 1, 1, 1}));
}

TEST(MarkKeypointsToKeep, OnlyDynamicBoxesDrop) {
  const std::vector<Detection> dets = {Det("person", 0, 0, 50, 50), Det("tv", 100, 100, 50, 50),
                                       Det("cup", 40, 40, 20, 20)};  // 0.25 inside the person: static
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kHoid2d));
  ASSERT_FALSE(d[2].dynamic);
  const std::vector<cv::KeyPoint> kps = {cv::KeyPoint(5, 5, 31), cv::KeyPoint(120, 120, 31),
                                         cv::KeyPoint(55, 55, 31), cv::KeyPoint(45, 45, 31)};
  std::vector<std::uint8_t> keep;
  MarkKeypointsToKeep(kps, dets, d, keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 1, 1, 0}));
  MarkKeypointsToKeep(kps, dets, ClassifyDetections(dets, Options(FilterMode::kNone)), keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{1, 1, 1, 1}));
}

TEST(MarkKeypointsToKeep, MatchesRectContainsOnManyPoints) {
  // More keypoints than one internal chunk, at random and on edges, with overlapping dynamic boxes.
  const std::vector<Detection> dets = {Det("person", 100.5F, 50.25F, 120.75F, 300.0F), Det("chair", 150, 60, 200, 100),
                                       Det("person", 400, 10, 100, 400), Det("bus", 0, 0, 640, 480)};
  const std::vector<Decision> d = ClassifyDetections(dets, Options(FilterMode::kClasses));
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(-10.0F, 650.0F);
  std::uniform_real_distribution<float> uy(-10.0F, 490.0F);
  std::vector<cv::KeyPoint> kps;
  std::vector<cv::Point2f> pts;
  for (int i = 0; i < 1000; ++i) {
    const cv::Point2f p = i % 10 == 0 ? cv::Point2f(400.0F + static_cast<float>(i % 3) * 50.0F, 10.0F + i % 410)
                                      : cv::Point2f(ux(rng), uy(rng));
    pts.push_back(p);
    kps.emplace_back(p, 31.0F);
  }
  std::vector<std::uint8_t> keep_kps;
  std::vector<std::uint8_t> keep_pts;
  MarkKeypointsToKeep(kps, dets, d, keep_kps);
  MarkKeypointsToKeep(pts, dets, d, keep_pts);
  ASSERT_EQ(keep_kps.size(), 1000U);
  EXPECT_EQ(keep_kps, keep_pts);
  int dropped = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    bool inside = false;
    for (std::size_t j = 0; j < dets.size(); ++j) inside |= d[j].dynamic && dets[j].box.contains(pts[i]);
    EXPECT_EQ(keep_pts[i], inside ? 0 : 1) << i;
    dropped += inside ? 1 : 0;
  }
  EXPECT_GT(dropped, 100);
  EXPECT_LT(dropped, 900);
}

TEST(MarkKeypointsToKeep, EmptyInputsAndMismatchedDecisions) {
  const std::vector<Detection> dets = {Det("person", 0, 0, 50, 50)};
  std::vector<std::uint8_t> keep(5, 0);
  MarkKeypointsToKeep(std::span<const cv::Point2f>(), dets, ClassifyDetections(dets, Options(FilterMode::kPerson)),
                      keep);
  EXPECT_TRUE(keep.empty());
  const std::vector<cv::Point2f> pts = {{5, 5}};
  MarkKeypointsToKeep(pts, {}, {}, keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{1}));
  EXPECT_THROW(MarkKeypointsToKeep(pts, dets, {}, keep), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::hoid
