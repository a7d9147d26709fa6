#include "hoidslam/eval/evaluation.h"

#include <cmath>
#include <fstream>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/eval/test_trajectories.h"
#include "hoidslam/io/trajectory_file.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::eval {
namespace {

using ::testing::HasSubstr;

core::Trajectory EveryNth(const core::Trajectory& trajectory, std::size_t n) {
  core::Trajectory result;
  for (std::size_t k = 0; k < trajectory.size(); k += n) result.push_back(trajectory[k]);
  return result;
}

TEST(RealGroundTruthTest, RigidlyMovedSubsampledCopyHasZeroError) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, "data/tum/groundtruth/fr3_walking_xyz.txt");
  const core::Trajectory gt = io::ReadTumTrajectory(path);
  ASSERT_GT(gt.size(), 2000U);
  std::mt19937 rng(21);
  // 100 Hz ground truth sampled down to about 33 Hz, like a camera-rate estimate.
  const core::Trajectory est = test_data::Transformed(EveryNth(gt, 3), test_data::RandomPose(rng));
  const AteResult ate = ComputeAte(gt, est, {});
  EXPECT_EQ(ate.error.count, est.size());
  EXPECT_LT(ate.error.max, 1e-9);
  const RpeResult rpe = ComputeRpe(gt, est, {});
  EXPECT_GT(rpe.translation.count, est.size() / 2);
  EXPECT_LT(rpe.translation.max, 1e-9);
  EXPECT_LT(rpe.rotation_deg.max, 1e-6);
}

TEST(RealGroundTruthTest, GaussianNoiseGivesSigmaTimesRootThree) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, "data/tum/groundtruth/fr3_walking_xyz.txt");
  const core::Trajectory gt = io::ReadTumTrajectory(path);
  const double sigma = 0.01;
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, sigma);
  core::Trajectory est = gt;
  for (core::StampedPose& pose : est) pose.T_wc.translation() += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  // E|n|^2 = 3 sigma^2; the alignment absorbs only 6 of the ~8600 degrees of freedom.
  const AteResult ate = ComputeAte(gt, est, {});
  EXPECT_NEAR(ate.error.rmse, sigma * std::sqrt(3.0), 0.03 * sigma * std::sqrt(3.0));
}

TEST(RealGroundTruthTest, RepeatedTimestampInWalkingStaticIsHarmless) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, "data/tum/groundtruth/fr3_walking_static.txt");
  hoidslam::testing::TempDir dir;
  std::mt19937 rng(4);
  const core::Trajectory gt = io::ReadTumTrajectory(path);
  io::WriteTumTrajectory(dir / "est.txt", test_data::Transformed(EveryNth(gt, 3), test_data::RandomPose(rng)));
  const Evaluation evaluation = EvaluateTrajectoryFiles(path, dir / "est.txt", {});
  EXPECT_EQ(evaluation.groundtruth_poses, gt.size());
  EXPECT_EQ(evaluation.ate.error.count, evaluation.estimate_poses);
  // Written to 9 decimals, so zero up to rounding.
  EXPECT_LT(evaluation.ate.error.max, 1e-7);
  EXPECT_LT(evaluation.rpe.translation.max, 1e-7);
}

class EvaluateFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    gt_ = test_data::MakeLissajousTrajectory(400, 100.0, 1341846313.5);
    // 25 Hz, so one-second pairs are exactly 25 poses apart.
    core::Trajectory est = EveryNth(gt_, 4);
    for (core::StampedPose& pose : est) pose.T_wc.translation().y() += 0.02 * (pose.timestamp - gt_[0].timestamp);
    io::WriteTumTrajectory(dir_ / "gt.txt", gt_);
    io::WriteTumTrajectory(dir_ / "est.txt", est);
  }

  hoidslam::testing::TempDir dir_;
  core::Trajectory gt_;
};

TEST_F(EvaluateFilesTest, ComputesBothErrorsAndPrintsThem) {
  const Evaluation evaluation = EvaluateTrajectoryFiles(dir_ / "gt.txt", dir_ / "est.txt", {});
  EXPECT_EQ(evaluation.groundtruth_poses, 400U);
  EXPECT_EQ(evaluation.estimate_poses, 100U);
  EXPECT_EQ(evaluation.ate.error.count, 100U);
  EXPECT_EQ(evaluation.rpe.translation.count, 100U - 26U);
  EXPECT_GT(evaluation.ate.error.rmse, 0.0);
  EXPECT_NEAR(evaluation.rpe.translation.mean, 0.02, 1e-6);  // the drift per second

  const std::string table = FormatEvaluation(evaluation);
  EXPECT_THAT(table, HasSubstr("ATE (m)"));
  EXPECT_THAT(table, HasSubstr("RPE translation (m/s)"));
  EXPECT_THAT(table, HasSubstr("RPE rotation (deg/s)"));
  EXPECT_THAT(table, HasSubstr("74"));
  EXPECT_THAT(table, HasSubstr("0.020000"));
}

TEST_F(EvaluateFilesTest, WritesJsonThatReadsBack) {
  EvaluationOptions options;
  options.ate.estimate_scale = true;
  options.rpe.delta = 2.0;
  const Evaluation evaluation = EvaluateTrajectoryFiles(dir_ / "gt.txt", dir_ / "est.txt", options);
  WriteEvaluationJson(dir_ / "eval.json", evaluation);
  std::ifstream in(dir_ / "eval.json");
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json["estimate"]["poses"], 100);
  EXPECT_EQ(json["ate"]["error_m"]["pairs"], 100);
  EXPECT_DOUBLE_EQ(json["ate"]["error_m"]["rmse"].get<double>(), evaluation.ate.error.rmse);
  EXPECT_DOUBLE_EQ(json["ate"]["alignment"]["scale"].get<double>(), evaluation.ate.alignment.scale);
  EXPECT_EQ(json["ate"]["alignment"]["rotation"].size(), 3U);
  EXPECT_NEAR(json["rpe"]["translation_m"]["mean"].get<double>(), 0.04, 1e-6);  // two seconds of drift
  EXPECT_EQ(json["rpe"]["translation_m"]["pairs"], 100 - 51);
  EXPECT_EQ(json["options"]["rpe_delta_unit"], "s");
  EXPECT_EQ(json["options"]["estimate_scale"], true);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_.path()), {}), 3);  // no temporary left
}

TEST_F(EvaluateFilesTest, TrajectoriesOfDifferentSequencesNameBothFiles) {
  io::WriteTumTrajectory(dir_ / "other.txt", test_data::MakeLissajousTrajectory(100, 30.0, 1341840000.0));
  try {
    EvaluateTrajectoryFiles(dir_ / "gt.txt", dir_ / "other.txt", {});
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr((dir_ / "gt.txt").string()));
    EXPECT_THAT(e.what(), HasSubstr((dir_ / "other.txt").string()));
    EXPECT_THAT(e.what(), HasSubstr("same sequence"));
  }
}

TEST_F(EvaluateFilesTest, BadFilesAndOptionsAreInputErrors) {
  EXPECT_THROW(EvaluateTrajectoryFiles(dir_ / "missing.txt", dir_ / "est.txt", {}), core::InputError);
  std::ofstream(dir_ / "bad.txt") << "1.0 2.0 3.0\n";
  try {
    EvaluateTrajectoryFiles(dir_ / "gt.txt", dir_ / "bad.txt", {});
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.txt:1"));
  }
  EvaluationOptions options;
  options.ate.association.max_difference = -0.1;
  EXPECT_THROW(EvaluateTrajectoryFiles(dir_ / "gt.txt", dir_ / "est.txt", options), core::InputError);
  const Evaluation evaluation = EvaluateTrajectoryFiles(dir_ / "gt.txt", dir_ / "est.txt", {});
  EXPECT_THROW(WriteEvaluationJson(dir_ / "no-such-folder" / "eval.json", evaluation), core::InputError);
}

}  // namespace
}  // namespace hoidslam::eval
