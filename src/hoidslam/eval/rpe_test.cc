#include "hoidslam/eval/rpe.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "hoidslam/eval/test_trajectories.h"

namespace hoidslam::eval {
namespace {

core::Pose Translation(const Eigen::Vector3d& t) {
  return core::PoseFromTranslationQuaternion(t, Eigen::Quaterniond::Identity());
}

TEST(ComputeRpeTest, RigidlyMovedCopyHasZeroError) {
  const core::Trajectory gt = test_data::MakeLissajousTrajectory(600, 30.0, 1341846313.0);
  std::mt19937 rng(9);
  const RpeResult rpe = ComputeRpe(gt, test_data::Transformed(gt, test_data::RandomPose(rng)), {});
  // Pairs i -> i + 30 (one second) for every i whose partner is not the last pose.
  EXPECT_EQ(rpe.translation.count, 600U - 31U);
  EXPECT_LT(rpe.translation.max, 1e-9);
  EXPECT_LT(rpe.rotation_deg.max, 1e-6);
}

TEST(ComputeRpeTest, ConstantDriftVelocityGivesThatVelocityPerSecond) {
  // Same orientations, positions drifting by v per second in the world frame: every one-second relative
  // motion is off by exactly v (rotated into the camera frame), so every error is |v| and no rotation error.
  const Eigen::Vector3d v(0.03, -0.04, 0.12);  // |v| = 0.13 m/s
  const core::Trajectory gt = test_data::MakeLissajousTrajectory(450, 30.0, 100.0);
  core::Trajectory est = gt;
  for (core::StampedPose& pose : est) pose.T_wc.translation() += v * (pose.timestamp - 100.0);
  const RpeResult rpe = ComputeRpe(gt, est, {});
  EXPECT_EQ(rpe.translation.count, 450U - 31U);
  EXPECT_NEAR(rpe.translation.rmse, 0.13, 1e-9);
  EXPECT_NEAR(rpe.translation.min, 0.13, 1e-9);
  EXPECT_NEAR(rpe.translation.max, 0.13, 1e-9);
  EXPECT_LT(rpe.rotation_deg.max, 1e-6);
  for (const RpePair& pair : rpe.pairs) EXPECT_NEAR(pair.estimate_timestamp_1 - pair.estimate_timestamp_0, 1.0, 1e-6);

  // The same drift over two seconds: twice the error.
  const RpeResult two = ComputeRpe(gt, est, {.delta = 2.0});
  EXPECT_NEAR(two.translation.mean, 0.26, 1e-9);
  // Counted in frames: 15 frames at 30 Hz is half a second.
  const RpeResult frames = ComputeRpe(gt, est, {.delta = 15.0, .delta_unit = DeltaUnit::kFrames});
  EXPECT_EQ(frames.translation.count, 450U - 16U);
  EXPECT_NEAR(frames.translation.mean, 0.065, 1e-9);
  // A step longer than the whole run leaves no pair: an error that says so, whatever its size.
  EXPECT_THROW(ComputeRpe(gt, est, {.delta = 1e30, .delta_unit = DeltaUnit::kFrames}), core::InputError);
}

TEST(ComputeRpeTest, ComposesTheErrorAsTumEvaluateRpeDoes) {
  // Ground truth moves 1 m along x per second without turning; the estimate does the same but turns 90° about z
  // every second. evaluate_rpe.py's error is E = (P_i^-1 P_j) (Q_i^-1 Q_j)^-1: for i = 0 its translation is
  // x - Rz(90°) x = (1, -1, 0), |.| = √2; for i = 1 it is Rz(-90°) x - Rz(90°) x = (0, -2, 0), |.| = 2.
  // (The other order, (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), would give 0 and √2.) Pairs starting at 2 and 3 end at
  // the last pose and are dropped.
  core::Trajectory gt;
  core::Trajectory est;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d position(k, 0.0, 0.0);
    gt.push_back({static_cast<double>(k), Translation(position)});
    est.push_back({static_cast<double>(k),
                   core::PoseFromTranslationQuaternion(
                       position, Eigen::Quaterniond(Eigen::AngleAxisd(k * std::numbers::pi / 2.0, Eigen::Vector3d::UnitZ())))});
  }
  const RpeResult rpe = ComputeRpe(gt, est, {});
  ASSERT_EQ(rpe.pairs.size(), 2U);
  EXPECT_NEAR(rpe.pairs[0].translation_error, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(rpe.pairs[1].translation_error, 2.0, 1e-12);
  EXPECT_NEAR(rpe.pairs[0].rotation_error_deg, 90.0, 1e-9);
  EXPECT_NEAR(rpe.rotation_deg.rmse, 90.0, 1e-9);
  EXPECT_EQ(rpe.pairs[1].estimate_timestamp_0, 1.0);
  EXPECT_EQ(rpe.pairs[1].groundtruth_timestamp_1, 2.0);
}

TEST(ComputeRpeTest, SkipsPairsWhoseGroundTruthIsTooFarInTime) {
  // Ground truth at 100 Hz with a 1 s gap: estimated poses in the gap are more than 2 × 10 ms from any
  // ground truth, so every pair touching the gap is skipped rather than compared to a distant pose.
  const core::Trajectory full = test_data::MakeLissajousTrajectory(1000, 100.0);
  core::Trajectory gt;
  for (const core::StampedPose& pose : full)
    if (pose.timestamp < 4.0 || pose.timestamp >= 5.0) gt.push_back(pose);
  core::Trajectory est;
  for (std::size_t k = 0; k < full.size(); k += 10) est.push_back(full[k]);  // 10 Hz, 100 poses
  core::Trajectory drifting = est;
  for (core::StampedPose& pose : drifting) pose.T_wc.translation().x() += 0.05 * pose.timestamp;
  const RpeResult rpe = ComputeRpe(gt, drifting, {});
  // Pairs (i, i + 10) for i = 0..88 (i = 89 ends at the last pose). The estimated stamps 4.1 .. 4.9 are at
  // least 0.1 s from any ground truth (4.0 still has 3.99, 10 ms away), so the 9 pairs starting there and the
  // 9 ending there are dropped.
  for (const RpePair& pair : rpe.pairs) {
    EXPECT_FALSE(pair.estimate_timestamp_0 > 4.02 && pair.estimate_timestamp_0 < 4.98);
    EXPECT_FALSE(pair.estimate_timestamp_1 > 4.02 && pair.estimate_timestamp_1 < 4.98);
    // Pairs whose ground truth is exactly at their stamps see the pure drift (3.0 -> 4.0 is compared to the
    // ground truth 3.0 -> 3.99 and differs by the motion over those 10 ms).
    if (pair.groundtruth_timestamp_0 == pair.estimate_timestamp_0 &&
        pair.groundtruth_timestamp_1 == pair.estimate_timestamp_1) {
      EXPECT_NEAR(pair.translation_error, 0.05, 1e-9);
    }
  }
  EXPECT_EQ(rpe.pairs.size(), 89U - 18U);
}

TEST(ComputeRpeTest, TooShortOrDisjointTrajectoriesAreInputErrors) {
  const core::Trajectory gt = test_data::MakeLissajousTrajectory(300, 30.0);
  const core::Trajectory short_est(gt.begin(), gt.begin() + 20);  // 0.63 s: no pair one second apart
  EXPECT_THROW(ComputeRpe(gt, short_est, {}), core::InputError);
  EXPECT_NO_THROW(ComputeRpe(gt, short_est, {.delta = 0.2}));
  const core::Trajectory later = test_data::MakeLissajousTrajectory(300, 30.0, 1000.0);
  try {
    ComputeRpe(gt, later, {});
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("same sequence"));
  }
  EXPECT_THROW(ComputeRpe(gt, core::Trajectory(gt.begin(), gt.begin() + 1), {}), core::InputError);
}

TEST(RpeOptionsTest, RejectsBadDeltasNamingTheParameter) {
  EXPECT_THROW((RpeOptions{.delta = 0.0}.Check()), core::InputError);
  EXPECT_THROW((RpeOptions{.delta = -1.0}.Check()), core::InputError);
  EXPECT_THROW((RpeOptions{.delta = 1.5, .delta_unit = DeltaUnit::kFrames}.Check()), core::InputError);
  EXPECT_NO_THROW((RpeOptions{.delta = 1.5}.Check()));
  try {
    RpeOptions{.delta = std::nan("")}.Check();
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("--rpe-delta"));
  }
}

}  // namespace
}  // namespace hoidslam::eval
