#include "hoidslam/slam/track/motion_model.h"

#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/geometry.h"

namespace hoidslam::slam {
namespace {

using ::hoidslam::testing::PoseFromAxisAngle;

const core::Pose kStart = PoseFromAxisAngle({0.1, -0.2, 0.05}, {0.3, 0.1, 1.5});
// 1 cm and 0.6° a frame at 30 Hz.
const core::Pose kStep = PoseFromAxisAngle({0.0, 0.01, 0.0}, {0.01, 0.0, 0.0});

TEST(MotionModel, WithoutAMeasuredMotionTheCameraStaysWhereItWas) {
  const MotionModel model{MotionModelOptions{}};
  EXPECT_FALSE(model.measured());
  EXPECT_TRUE(model.Predict(kStart, 0.1).isApprox(kStart));
  EXPECT_EQ(model.IntervalsAhead(0.1), 0.0);
  EXPECT_FALSE(model.Prior(kStart, 1.0 / 30.0));
}

TEST(MotionModel, ContinuesTheMeasuredMotionScaledToTheTimeElapsed) {
  MotionModel model{MotionModelOptions{}};
  model.Measure(kStart, kStep * kStart, 1.0 / 30.0);
  EXPECT_TRUE(model.Predict(kStart, 1.0 / 30.0).isApprox(kStep * kStart, 1e-12));
  // Two frames' time: twice the turn about the same axis, twice the translation.
  const core::Pose doubled = PoseFromAxisAngle({0.0, 0.02, 0.0}, {0.02, 0.0, 0.0});
  EXPECT_TRUE(model.Predict(kStart, 2.0 / 30.0).isApprox(doubled * kStart, 1e-9));
  EXPECT_DOUBLE_EQ(model.IntervalsAhead(2.0 / 30.0), 2.0);
  // At most four intervals' worth.
  EXPECT_DOUBLE_EQ(model.IntervalsAhead(1.0), 4.0);
  model.Reset();
  EXPECT_FALSE(model.measured());
}

TEST(MotionModel, ThePriorLoosensWithTheSquareOfTheTimeElapsed) {
  MotionModel model{MotionModelOptions{}};
  model.Measure(kStart, kStep * kStart, 1.0 / 30.0);
  const auto one = model.Prior(kStart, 1.0 / 30.0);
  const auto two = model.Prior(kStart, 2.0 / 30.0);
  ASSERT_TRUE(one && two);
  // σ = 9 m/s² τ² = 10 mm and 900 °/s² τ² = 1° at 30 Hz.
  EXPECT_NEAR(1.0 / std::sqrt(one->information(3, 3)), 0.01, 1e-9);
  EXPECT_NEAR(1.0 / std::sqrt(one->information(0, 0)) * 180.0 / std::numbers::pi, 1.0, 1e-9);
  EXPECT_NEAR(one->information(3, 3) / two->information(3, 3), 16.0, 1e-9);
  // A pose 2 cm beside the prediction is 2 σ away: χ² 4.
  core::Pose off = one->T_cw;
  off.translation() += Eigen::Vector3d(0.02, 0.0, 0.0);
  EXPECT_NEAR(PriorChi2(off, *one), 4.0, 1e-6);
}

TEST(MotionModelOptions, CheckNamesTheParameter) {
  MotionModelOptions options;
  options.acceleration = -1.0;
  EXPECT_THROW(options.Check(), core::InputError);
  options = {};
  options.max_extrapolation = 0.5;
  EXPECT_THROW(options.Check(), core::InputError);
}

}  // namespace
}  // namespace hoidslam::slam
