#include "hoidslam/eval/alignment.h"

#include <random>

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "hoidslam/eval/test_trajectories.h"

namespace hoidslam::eval {
namespace {

Eigen::Matrix3Xd RandomPoints(std::mt19937& rng, Eigen::Index count) {
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  Eigen::Matrix3Xd points(3, count);
  for (Eigen::Index k = 0; k < count; ++k) points.col(k) = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
  return points;
}

TEST(AlignPointsTest, RecoversKnownRigidTransforms) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const core::Pose T = test_data::RandomPose(rng);
    const Eigen::Matrix3Xd model = RandomPoints(rng, 3 + trial);
    const Eigen::Matrix3Xd data = (T.linear() * model).colwise() + T.translation();
    const Alignment a = AlignPoints(model, data, /*with_scale=*/false);
    EXPECT_LT((a.rotation - T.linear()).norm(), 1e-9) << "trial " << trial;
    EXPECT_LT((a.translation - T.translation()).norm(), 1e-9) << "trial " << trial;
    EXPECT_EQ(a.scale, 1.0);
  }
}

TEST(AlignPointsTest, RecoversKnownSimilarityWhenAskedForScale) {
  std::mt19937 rng(11);
  const core::Pose T = test_data::RandomPose(rng);
  const double scale = 0.37;
  const Eigen::Matrix3Xd model = RandomPoints(rng, 50);
  const Eigen::Matrix3Xd data = (scale * T.linear() * model).colwise() + T.translation();
  const Alignment a = AlignPoints(model, data, /*with_scale=*/true);
  EXPECT_NEAR(a.scale, scale, 1e-12);
  EXPECT_LT((a.rotation - T.linear()).norm(), 1e-9);
  EXPECT_LT((a.translation - T.translation()).norm(), 1e-9);
  // Without scale the same data cannot be fitted exactly.
  const Alignment rigid = AlignPoints(model, data, /*with_scale=*/false);
  EXPECT_EQ(rigid.scale, 1.0);
  EXPECT_GT((rigid.Apply(model.col(0)) - data.col(0)).norm(), 1e-3);
}

TEST(AlignPointsTest, MirroredDataGivesAProperRotationNotAReflection) {
  std::mt19937 rng(3);
  const Eigen::Matrix3Xd model = RandomPoints(rng, 30);
  Eigen::Matrix3Xd data = model;
  data.row(0) *= -1.0;  // a mirror image: the best orthogonal fit would be the reflection diag(-1, 1, 1)
  const Alignment a = AlignPoints(model, data, /*with_scale=*/false);
  EXPECT_NEAR(a.rotation.determinant(), 1.0, 1e-12);
  EXPECT_LT((a.rotation.transpose() * a.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(AlignPointsTest, ScaleOfCoincidentPointsIsAnInputError) {
  const Eigen::Matrix3Xd model = Eigen::Matrix3Xd::Ones(3, 5);
  std::mt19937 rng(1);
  const Eigen::Matrix3Xd data = RandomPoints(rng, 5);
  EXPECT_THROW(AlignPoints(model, data, /*with_scale=*/true), core::InputError);
  EXPECT_NO_THROW(AlignPoints(model, data, /*with_scale=*/false));
}

}  // namespace
}  // namespace hoidslam::eval
