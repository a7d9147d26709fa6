#include "hoidslam/eval/pose_check.h"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hoidslam/eval/ate.h"
#include "hoidslam/eval/test_trajectories.h"

namespace hoidslam::eval {
namespace {

// The ground truth, and the estimate: the same path seen from another world frame, with three poses spoiled.
class PoseCheckTest : public ::testing::Test {
 protected:
  void SetUp() override {
    gt_ = test_data::MakeLissajousTrajectory(300, 30.0, 1000.0);
    std::mt19937 rng(3);
    estimate_ = test_data::Transformed(gt_, test_data::RandomPose(rng));
    Spoil(100, Eigen::Vector3d(0.15, 0.0, 0.0), 0.0);  // 15 cm off
    Spoil(150, Eigen::Vector3d::Zero(), 3.0);           // turned 3°: within the limit
    Spoil(200, Eigen::Vector3d(0.0, 0.05, 0.0), 7.0);   // 5 cm, but turned 7°
    alignment_ = ComputeAte(gt_, estimate_, {}).alignment;
  }

  // Moves estimated pose k by `shift` (in its camera frame) and turns it by `degrees` about its optical axis.
  void Spoil(std::size_t k, const Eigen::Vector3d& shift, double degrees) {
    core::Pose& T_wc = estimate_[k].T_wc;
    T_wc = T_wc * Eigen::Translation3d(shift) * Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0,
                                                                  Eigen::Vector3d::UnitZ());
  }

  PoseCheck Check(const std::vector<double>& stamps) const {
    return CheckPoses(gt_, estimate_, alignment_, stamps, {}, {});
  }

  core::Trajectory gt_, estimate_;
  Alignment alignment_;
};

TEST_F(PoseCheckTest, APoseFarOrTurnedFromTheTruthIsWrong) {
  const PoseCheck check = Check({gt_[50].timestamp, gt_[100].timestamp, gt_[150].timestamp, gt_[200].timestamp});
  ASSERT_EQ(check.poses.size(), 4U);
  EXPECT_EQ(check.unmatched, 0U);
  EXPECT_FALSE(check.poses[0].wrong);
  EXPECT_LT(check.poses[0].position_error, 0.01);  // three spoiled poses of 300 barely move the alignment
  EXPECT_LT(check.poses[0].rotation_error_deg, 0.1);
  EXPECT_TRUE(check.poses[1].wrong);
  EXPECT_NEAR(check.poses[1].position_error, 0.15, 0.01);
  EXPECT_FALSE(check.poses[2].wrong);
  EXPECT_NEAR(check.poses[2].rotation_error_deg, 3.0, 0.1);
  EXPECT_TRUE(check.poses[3].wrong);
  EXPECT_NEAR(check.poses[3].rotation_error_deg, 7.0, 0.1);
  EXPECT_LT(check.poses[3].position_error, 0.10);
  EXPECT_EQ(check.Wrong(), 2U);
}

TEST_F(PoseCheckTest, StampsWithoutAnEstimatedOrATruePoseAreCountedApart) {
  estimate_.push_back({gt_.back().timestamp + 1.0, estimate_.back().T_wc});  // after the ground truth ends
  const PoseCheck check = Check({gt_[10].timestamp + 0.01, estimate_.back().timestamp, gt_[20].timestamp});
  EXPECT_EQ(check.unmatched, 2U);
  ASSERT_EQ(check.poses.size(), 1U);
  EXPECT_EQ(check.poses[0].timestamp, gt_[20].timestamp);
}

TEST_F(PoseCheckTest, JsonCountsTheFalseOnesAndKeepsTheLimits) {
  const nlohmann::json json = PoseCheckToJson(Check({gt_[100].timestamp, gt_[150].timestamp}), {});
  EXPECT_EQ(json["count"], 2);
  EXPECT_EQ(json["false"], 1);
  EXPECT_EQ(json["unmatched"], 0);
  EXPECT_EQ(json["max_position_error_m"], 0.10);
  EXPECT_EQ(json["max_rotation_error_deg"], 5.0);
  EXPECT_EQ(json["poses"][0]["false"], true);
}

TEST_F(PoseCheckTest, ALoopIsJudgedByTheRelativePoseOfItsTwoEndsInAnyWorldFrame) {
  // The loops the estimate (in a world frame of its own) would measure between frames 250 and 20, and 280 and 40.
  const auto measured = [&](std::size_t frame, std::size_t base) {
    return RelativePose{gt_[frame].timestamp, gt_[base].timestamp,
                        estimate_[base].T_wc.inverse() * estimate_[frame].T_wc};
  };
  std::vector<RelativePose> loops = {measured(250, 20), measured(280, 40), measured(100, 20)};  // 100: spoiled
  loops.push_back({gt_.back().timestamp + 1.0, gt_[0].timestamp, core::Pose::Identity()});    // no ground truth
  const PoseCheck check = CheckRelativePoses(gt_, loops, {}, {});
  ASSERT_EQ(check.poses.size(), 3U);
  EXPECT_EQ(check.unmatched, 1U);
  EXPECT_LT(check.poses[0].position_error, 1e-6);
  EXPECT_LT(check.poses[1].rotation_error_deg, 1e-6);
  EXPECT_FALSE(check.poses[0].wrong);
  EXPECT_TRUE(check.poses[2].wrong);
  EXPECT_NEAR(check.poses[2].position_error, 0.15, 1e-6);
  EXPECT_EQ(check.poses[2].timestamp, gt_[100].timestamp);
}

}  // namespace
}  // namespace hoidslam::eval
