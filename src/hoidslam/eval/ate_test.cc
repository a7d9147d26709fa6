#include "hoidslam/eval/ate.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "hoidslam/eval/test_trajectories.h"

namespace hoidslam::eval {
namespace {

TEST(ComputeAteTest, RigidlyMovedCopyHasZeroError) {
  const core::Trajectory gt = test_data::MakeLissajousTrajectory(300, 30.0, 1000.0);
  std::mt19937 rng(5);
  const core::Pose T = test_data::RandomPose(rng);
  const AteResult ate = ComputeAte(gt, test_data::Transformed(gt, T), {});
  EXPECT_EQ(ate.error.count, 300U);
  EXPECT_LT(ate.error.rmse, 1e-9);
  EXPECT_LT(ate.error.max, 1e-9);
  // The alignment maps the estimate back: it is T^-1.
  EXPECT_LT((ate.alignment.rotation - T.inverse().linear()).norm(), 1e-9);
  EXPECT_LT((ate.alignment.translation - T.inverse().translation()).norm(), 1e-9);
  ASSERT_EQ(ate.pairs.size(), 300U);
  EXPECT_EQ(ate.pairs[7].groundtruth_timestamp, gt[7].timestamp);
  EXPECT_LT((ate.pairs[7].aligned_position - gt[7].T_wc.translation()).norm(), 1e-9);
}

TEST(ComputeAteTest, KnownPerturbationGivesKnownStatistics) {
  // Eight poses on the ellipse x = 2 cos(θ_k), y = sin(θ_k), θ_k = kπ/4, z = 0 (centred at the origin). The
  // estimate moves pose k along z by a_k = d cos(πk/2) + b (-1)^k. Since Σ a_k = 0, Σ a_k cos θ_k = 0 and
  // Σ a_k sin θ_k = 0 (discrete frequencies 2 and 4 are orthogonal to 0 and 1 over 8 samples), the
  // cross-covariance of the centred point sets is Σ p_k p_k^T, symmetric positive semi-definite, for which the
  // identity is the best rotation (tr(R W) ≤ tr(W) for every rotation R); the translation is the difference of
  // the centroids, 0. So the aligned errors are exactly |a_k|.
  // With d = 0.03, b = 0.01: |a_k| = 0.04, 0.01, 0.02, 0.01, 0.04, 0.01, 0.02, 0.01.
  const double d = 0.03;
  const double b = 0.01;
  core::Trajectory gt;
  core::Trajectory est;
  for (int k = 0; k < 8; ++k) {
    const double theta = k * std::numbers::pi / 4.0;
    const Eigen::Vector3d p(2.0 * std::cos(theta), std::sin(theta), 0.0);
    const double a = d * std::cos(k * std::numbers::pi / 2.0) + b * (k % 2 == 0 ? 1.0 : -1.0);
    gt.push_back({0.1 * k, core::PoseFromTranslationQuaternion(p, Eigen::Quaterniond::Identity())});
    est.push_back({0.1 * k, core::PoseFromTranslationQuaternion(p + Eigen::Vector3d(0, 0, a), Eigen::Quaterniond::Identity())});
  }
  const AteResult ate = ComputeAte(gt, est, {});
  EXPECT_EQ(ate.error.count, 8U);
  EXPECT_NEAR(ate.error.rmse, std::sqrt((2 * 0.0016 + 2 * 0.0004 + 4 * 0.0001) / 8.0), 1e-12);
  EXPECT_NEAR(ate.error.mean, 0.02, 1e-12);
  EXPECT_NEAR(ate.error.median, 0.015, 1e-12);
  EXPECT_NEAR(ate.error.std, std::sqrt(0.00055 - 0.0004), 1e-12);
  EXPECT_NEAR(ate.error.min, 0.01, 1e-12);
  EXPECT_NEAR(ate.error.max, 0.04, 1e-12);
  EXPECT_LT((ate.alignment.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(ComputeAteTest, ScaledEstimateNeedsSimilarityAlignment) {
  const core::Trajectory gt = test_data::MakeLissajousTrajectory(200, 30.0);
  core::Trajectory est = gt;
  for (core::StampedPose& pose : est) pose.T_wc.translation() *= 0.5;  // a monocular-style scale error
  EXPECT_GT(ComputeAte(gt, est, {}).error.rmse, 0.05);
  const AteResult sim3 = ComputeAte(gt, est, {.estimate_scale = true});
  EXPECT_LT(sim3.error.rmse, 1e-9);
  EXPECT_NEAR(sim3.alignment.scale, 2.0, 1e-9);
}

TEST(ComputeAteTest, OnlyAssociatedPosesCount) {
  // The estimate runs at 30 Hz with stamps 3 ms after the ground truth's 100 Hz; an error on a pose with no
  // ground truth within 20 ms must not enter the result.
  const core::Trajectory gt = test_data::MakeLissajousTrajectory(300, 100.0);
  core::Trajectory est;
  for (std::size_t k = 0; k < gt.size(); k += 3) est.push_back({gt[k].timestamp + 0.003, gt[k].T_wc});
  est.push_back({gt.back().timestamp + 1.0, core::Pose::Identity()});
  const AteResult ate = ComputeAte(gt, est, {});
  EXPECT_EQ(ate.error.count, 100U);
  EXPECT_LT(ate.error.rmse, 1e-9);
}

TEST(ComputeAteTest, TooFewMatchesSaysSo) {
  const core::Trajectory gt = test_data::MakeLissajousTrajectory(100, 30.0, 0.0);
  const core::Trajectory other = test_data::MakeLissajousTrajectory(100, 30.0, 500.0);
  try {
    ComputeAte(gt, other, {});
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("only 0 of 100"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("same sequence"));
  }
  // Two matches are not enough for an alignment.
  const core::Trajectory two(gt.begin(), gt.begin() + 2);
  EXPECT_THROW(ComputeAte(gt, two, {}), core::InputError);
  const core::Trajectory three(gt.begin(), gt.begin() + 3);
  EXPECT_EQ(ComputeAte(gt, three, {}).error.count, 3U);
}

double AngleDegrees(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / std::numbers::pi;
}

TEST(AlignPosesTest, FindsTheTurnAboutAStraightPathThatPositionsLeaveOpen) {
  // A camera walks 1 m along x, swaying 1 cm sideways, looking along z. The estimate is the same poses in a world
  // turned 0.3° about x (the path's own axis) and shifted, its positions 0.5 mm off upwards where the camera swayed
  // left and downwards where it swayed right — an error no tracker would be blamed for.
  core::Trajectory gt;
  for (int k = 0; k < 100; ++k) {
    const Eigen::Vector3d p(0.01 * k, 0.01 * std::sin(0.2 * k), 0.0);
    gt.push_back({0.033 * k, core::PoseFromTranslationQuaternion(
                                 p, Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * k, Eigen::Vector3d::UnitY())))});
  }
  core::Pose T = core::Pose::Identity();
  T.linear() = Eigen::AngleAxisd(0.3 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.5, -0.2, 1.0);
  core::Trajectory est = test_data::Transformed(gt, T);
  for (std::size_t k = 0; k < est.size(); ++k) {
    const double sway = gt[k].T_wc.translation().y();
    est[k].T_wc.translation() += T.linear() * Eigen::Vector3d(0.0, 0.0, sway > 0.0 ? 0.0005 : -0.0005);
  }

  const Alignment by_positions = ComputeAte(gt, est, {}).alignment;
  const Alignment by_poses = AlignPoses(gt, est, {}, 2.0);
  EXPECT_GT(AngleDegrees(by_positions.rotation, T.inverse().linear()), 1.0);
  EXPECT_LT(AngleDegrees(by_poses.rotation, T.inverse().linear()), 0.01);
  EXPECT_LT((by_poses.translation - T.inverse().translation()).norm(), 0.002);
  EXPECT_THROW(AlignPoses(gt, est, {}, 0.0), core::InputError);
}

}  // namespace
}  // namespace hoidslam::eval
