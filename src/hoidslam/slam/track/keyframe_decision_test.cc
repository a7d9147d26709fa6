#include "hoidslam/slam/track/keyframe_decision.h"

#include <string>

#include <gtest/gtest.h>

namespace hoidslam::slam {
namespace {

struct KeyFrameRow {
  std::string name;
  KeyFrameDecisionInput input;
  bool keyframe;
};

// A frame tracked well against a reference keyframe of 400 points, local mapping idle, half a second after the last
// keyframe, in a map of 50 keyframes.
KeyFrameDecisionInput Steady() {
  KeyFrameDecisionInput input;
  input.map_keyframes = 50;
  input.inliers = 350;
  input.reference_points = 400;
  input.close_tracked = 300;
  input.close_untracked = 20;
  input.since_keyframe = 0.5;
  return input;
}

template <typename Change>
KeyFrameDecisionInput With(Change change) {
  KeyFrameDecisionInput input = Steady();
  change(input);
  return input;
}

class NeedNewKeyFrameTable : public ::testing::TestWithParam<KeyFrameRow> {};

TEST_P(NeedNewKeyFrameTable, DecidesByItsRule) {
  EXPECT_EQ(NeedNewKeyFrame(GetParam().input, KeyFrameDecisionOptions{}), GetParam().keyframe);
}

INSTANTIATE_TEST_SUITE_P(
    Rules, NeedNewKeyFrameTable,
    ::testing::Values(
        KeyFrameRow{"TrackingStrongAgainstTheReference", Steady(), false},
        KeyFrameRow{"WeakerThanThreeQuartersOfTheReferenceMapperIdle", With([](auto& i) { i.inliers = 280; }), true},
        KeyFrameRow{"WeakerMapperBusyWithinTheSecond", With([](auto& i) {
              i.inliers = 280;
              i.mapper_idle = false;
              i.mapper_queued = 1;
            }), false},
        KeyFrameRow{"WeakerMapperBusyASecondOn", With([](auto& i) {
              i.inliers = 280;
              i.mapper_idle = false;
              i.mapper_queued = 1;
              i.since_keyframe = 1.0;
            }), true},
        KeyFrameRow{"WeakerMapperBusyQueueFull", With([](auto& i) {
              i.inliers = 280;
              i.mapper_idle = false;
              i.mapper_queued = 3;
              i.since_keyframe = 2.0;
            }), false},
        KeyFrameRow{"VeryWeakMapperBusy", With([](auto& i) {
              i.inliers = 90;
              i.mapper_idle = false;
              i.mapper_queued = 1;
            }), true},
        KeyFrameRow{"ManyCloseKeypointsUntracked", With([](auto& i) {
              i.close_tracked = 80;
              i.close_untracked = 200;
            }), true},
        KeyFrameRow{"TooFewInliersForAnyKeyFrame", With([](auto& i) { i.inliers = 15; }), false},
        KeyFrameRow{"LoopBeingCorrected", With([](auto& i) {
              i.inliers = 90;
              i.mapper_paused = true;
            }), false},
        KeyFrameRow{"TheFirstKeyFrameAskedLess", With([](auto& i) {
              i.map_keyframes = 1;
              i.inliers = 200;
            }), false}),
    [](const ::testing::TestParamInfo<KeyFrameRow>& info) { return info.param.name; });

}  // namespace
}  // namespace hoidslam::slam
