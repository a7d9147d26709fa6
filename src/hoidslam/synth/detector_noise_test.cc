#include "hoidslam/synth/detector_noise.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/office.h"

namespace hoidslam::synth {
namespace {

std::vector<core::Detection> Truth() {
  return {{0, "person", 1.0F, {100, 50, 200, 400}},
          {41, "cup", 1.0F, {400, 300, 30, 40}},
          {62, "tv", 1.0F, {300, 100, 150, 100}}};
}

TEST(DetectorNoise, NoNoiseGivesTheTruth) {
  const DetectorNoiseOptions none;
  EXPECT_FALSE(none.Any());
  EXPECT_EQ(none.Describe(), "synthetic ground truth");
  const auto out = ApplyDetectorNoise(Truth(), none, 5, 640, 480);
  ASSERT_EQ(out.size(), 3U);
  EXPECT_EQ(out[1].box, Truth()[1].box);
  EXPECT_EQ(out[1].score, 1.0F);
}

TEST(DetectorNoise, IsDeterministicPerSeed) {
  DetectorNoiseOptions o;
  o.box_jitter = 0.1;
  o.false_positive_rate = 1.5;
  const auto a = ApplyDetectorNoise(Truth(), o, 11, 640, 480);
  const auto b = ApplyDetectorNoise(Truth(), o, 11, 640, 480);
  const auto c = ApplyDetectorNoise(Truth(), o, 12, 640, 480);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].box, b[i].box);
  EXPECT_NE(a[0].box, c[0].box);
}

TEST(DetectorNoise, MissingEverythingLeavesOnlyFalsePositives) {
  DetectorNoiseOptions o;
  o.miss_rate = 1.0;
  EXPECT_TRUE(ApplyDetectorNoise(Truth(), o, 1, 640, 480).empty());
  o.false_positive_rate = 2.0;
  const auto out = ApplyDetectorNoise(Truth(), o, 1, 640, 480);
  ASSERT_EQ(out.size(), 2U);
  for (const auto& d : out) {
    EXPECT_EQ(d.class_id, CocoClassId(d.label));
    EXPECT_GE(d.score, 0.3F);
    EXPECT_LE(d.score, 0.8F);
  }
}

TEST(DetectorNoise, RatesMatchOnAverage) {
  constexpr int kFrames = 4000;
  auto mean_count = [&](const DetectorNoiseOptions& o) {
    std::size_t total = 0;
    for (int frame = 0; frame < kFrames; ++frame) {
      total += ApplyDetectorNoise(Truth(), o, static_cast<std::uint64_t>(frame), 640, 480).size();
    }
    return static_cast<double>(total) / kFrames;
  };
  DetectorNoiseOptions misses;
  misses.miss_rate = 0.3;
  EXPECT_NEAR(mean_count(misses), 3 * 0.7, 0.05);
  DetectorNoiseOptions fakes;
  fakes.miss_rate = 1.0;
  fakes.false_positive_rate = 0.5;
  EXPECT_NEAR(mean_count(fakes), 0.5, 0.03);
}

TEST(DetectorNoise, JitteredBoxesStayInTheImageAndConfusedLabelsChange) {
  DetectorNoiseOptions o;
  o.box_jitter = 0.5;
  o.class_confusion_rate = 1.0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const auto truth = Truth();
    for (const auto& d : ApplyDetectorNoise(truth, o, seed, 640, 480)) {
      EXPECT_GE(d.box.x, 0.0F);
      EXPECT_GE(d.box.y, 0.0F);
      EXPECT_LE(d.box.x + d.box.width, 640.0F);
      EXPECT_LE(d.box.y + d.box.height, 480.0F);
      EXPECT_GE(d.score, 0.5F);
      EXPECT_EQ(d.class_id, CocoClassId(d.label));
      // All three true labels are distinct, so a confused box matches none of its own.
      EXPECT_THAT(SyntheticLabels(), ::testing::Contains(d.label));
    }
  }
  const auto one = ApplyDetectorNoise({Truth()[0]}, o, 3, 640, 480);
  ASSERT_EQ(one.size(), 1U);
  EXPECT_NE(one[0].label, "person");
}

TEST(DetectorNoise, CheckNamesTheParameter) {
  DetectorNoiseOptions o;
  o.miss_rate = 1.5;
  try {
    o.Check();
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    // The same wording as the sensor noise options (one shared check).
    EXPECT_THAT(e.what(), ::testing::HasSubstr("parameter detector_noise.miss_rate: must be in [0, 1], got 1.5"));
  }
  o.miss_rate = std::nan("");
  EXPECT_THROW(o.Check(), core::InputError);
  o.miss_rate = 0.1;
  o.box_jitter = 0.05;
  EXPECT_NO_THROW(o.Check());
  EXPECT_THAT(o.Describe(), ::testing::HasSubstr("miss 0.1"));
}

}  // namespace
}  // namespace hoidslam::synth
