#include "hoidslam/slam/optimize/pose_optimizer.h"
#include "support/geometry.h"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace hoidslam::slam {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Keypoint levels as ORB-SLAM's pyramid: scale factor 1.2, 8 levels.
double InvSigma2(int level) { return std::pow(1.2, -2.0 * level); }

struct Scene {
  RgbdCamera camera;
  core::Pose T_cw_true = core::Pose::Identity();
  std::vector<Eigen::Vector3d> points_w;
  std::vector<KeypointMeasurement> measurements;
};

// Each random number is drawn in a statement of its own: the order in which a call's arguments are evaluated is
// unspecified (GCC goes right to left, clang left to right), and the scene must not depend on the compiler. The
// order is GCC's, with which the thresholds below were set.
// Where the points are: a share of the image's width from its left edge, and a range of depths.
struct View {
  double width_share = 1.0;
  double near = 1.0, far = 6.0;  // metres
};

// `n` points in `view` of a camera at T_cw_true (the whole image, 1-6 m away, by default), seen with `pixel_noise`
// (σ in pixels at level 0), a `depth_fraction` of them with depth.
Scene MakeScene(int n, double depth_fraction, double pixel_noise, std::uint32_t seed, const View& view = {}) {
  Scene s;
  s.T_cw_true = testing::PoseFromAxisAngle(Eigen::Vector3d(0.1, -0.3, 0.05), Eigen::Vector3d(0.4, -0.2, 1.0));
  const core::Pose T_wc = s.T_cw_true.inverse();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_int_distribution<int> level(0, 7);
  while (static_cast<int>(s.points_w.size()) < n) {
    const double z = view.near + (view.far - view.near) * unit(rng);
    const double v = unit(rng);
    const double u = view.width_share * unit(rng);
    const Eigen::Vector3d p_c((u * 640.0 - s.camera.cx) * z / s.camera.fx, (v * 480.0 - s.camera.cy) * z / s.camera.fy,
                              z);
    KeypointMeasurement m;
    const int l = level(rng);
    m.inv_sigma2 = InvSigma2(l);
    const double sigma = pixel_noise * std::pow(1.2, l);
    const double noise_v = noise(rng);
    const double noise_u = noise(rng);
    m.uv = s.camera.Project(p_c) + sigma * Eigen::Vector2d(noise_u, noise_v);
    m.has_depth = unit(rng) < depth_fraction;
    if (m.has_depth) m.ur = s.camera.ProjectRight(p_c) + sigma * noise(rng);
    s.points_w.push_back(T_wc * p_c);
    s.measurements.push_back(m);
  }
  return s;
}

double RotationErrorDeg(const core::Pose& a, const core::Pose& b) {
  return Eigen::AngleAxisd(a.linear() * b.linear().transpose()).angle() / kDeg;
}
double TranslationError(const core::Pose& a, const core::Pose& b) {
  // Camera centres, so that the error is in metres in the world.
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

// The true pose moved by ~3° and ~10 cm.
core::Pose Perturbed(const core::Pose& T) {
  return testing::PoseFromAxisAngle(Eigen::Vector3d(2.0, -1.5, 1.0) * kDeg, Eigen::Vector3d(0.06, -0.05, 0.07)) * T;
}

TEST(OptimizePose, RecoversPoseFromNoiseFreeData) {
  const Scene s = MakeScene(300, 0.7, 0.0, 1);
  core::Pose T = Perturbed(s.T_cw_true);
  ASSERT_GT(RotationErrorDeg(T, s.T_cw_true), 2.0);
  std::vector<std::uint8_t> outlier;
  const int inliers = OptimizePose(s.camera, s.points_w, s.measurements, T, outlier);
  EXPECT_EQ(inliers, 300);
  ASSERT_EQ(outlier.size(), 300U);
  EXPECT_LT(RotationErrorDeg(T, s.T_cw_true), 0.01);
  EXPECT_LT(TranslationError(T, s.T_cw_true), 1e-3);
}

TEST(OptimizePose, RecoversPoseFromNoisyData) {
  const Scene s = MakeScene(300, 0.7, 1.0, 2);
  core::Pose T = Perturbed(s.T_cw_true);
  std::vector<std::uint8_t> outlier;
  const int inliers = OptimizePose(s.camera, s.points_w, s.measurements, T, outlier);
  // With σ = 1 px about 5 % of the points exceed the 95 % χ² thresholds.
  EXPECT_GT(inliers, 260);
  EXPECT_LT(RotationErrorDeg(T, s.T_cw_true), 0.05);
  EXPECT_LT(TranslationError(T, s.T_cw_true), 5e-3);
}

TEST(OptimizePose, FlagsGrossOutliersAndStillRecoversThePose) {
  Scene s = MakeScene(300, 0.7, 0.0, 3);
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> offset(30.0, 150.0);
  std::bernoulli_distribution sign(0.5);
  std::vector<bool> corrupted(s.measurements.size(), false);
  for (std::size_t i = 0; i < s.measurements.size(); i += 5) {  // 20 % mismatches, 30-150 px off
    KeypointMeasurement& m = s.measurements[i];
    const double dv = (sign(rng) ? 1 : -1) * offset(rng);
    const double du = (sign(rng) ? 1 : -1) * offset(rng);
    const Eigen::Vector2d d(du, dv);
    m.uv += d;
    m.ur += d.x();
    corrupted[i] = true;
  }
  core::Pose T = Perturbed(s.T_cw_true);
  std::vector<std::uint8_t> outlier;
  const int inliers = OptimizePose(s.camera, s.points_w, s.measurements, T, outlier);
  EXPECT_EQ(inliers, 240);
  for (std::size_t i = 0; i < outlier.size(); ++i) EXPECT_EQ(outlier[i] != 0, corrupted[i]) << "correspondence " << i;
  EXPECT_LT(RotationErrorDeg(T, s.T_cw_true), 0.01);
  EXPECT_LT(TranslationError(T, s.T_cw_true), 1e-3);
}

TEST(OptimizePose, WorksWithoutDepth) {
  const Scene s = MakeScene(200, 0.0, 0.0, 4);
  core::Pose T = Perturbed(s.T_cw_true);
  std::vector<std::uint8_t> outlier;
  EXPECT_EQ(OptimizePose(s.camera, s.points_w, s.measurements, T, outlier), 200);
  EXPECT_LT(RotationErrorDeg(T, s.T_cw_true), 0.01);
  EXPECT_LT(TranslationError(T, s.T_cw_true), 1e-3);
}

TEST(OptimizePose, FewerThanThreeCorrespondencesLeaveThePose) {
  const Scene s = MakeScene(2, 1.0, 0.0, 5);
  const core::Pose start = Perturbed(s.T_cw_true);
  core::Pose T = start;
  std::vector<std::uint8_t> outlier;
  EXPECT_EQ(OptimizePose(s.camera, s.points_w, s.measurements, T, outlier), 0);
  EXPECT_TRUE(T.matrix() == start.matrix());
  EXPECT_EQ(outlier, std::vector<std::uint8_t>({1, 1}));

  EXPECT_EQ(OptimizePose(s.camera, {}, {}, T, outlier), 0);
  EXPECT_TRUE(outlier.empty());
  EXPECT_TRUE(T.matrix() == start.matrix());
}

TEST(OptimizePose, PointsBehindTheCameraAreOutliers) {
  Scene s = MakeScene(100, 0.7, 0.0, 6);
  const core::Pose T_wc = s.T_cw_true.inverse();
  // Three points 2 m behind the camera, "seen" near the image centre.
  for (int i = 0; i < 3; ++i) {
    s.points_w.push_back(T_wc * Eigen::Vector3d(0.1 * i, 0.05, -2.0));
    KeypointMeasurement m;
    m.uv = Eigen::Vector2d(320.0 + 10.0 * i, 240.0);
    s.measurements.push_back(m);
  }
  core::Pose T = Perturbed(s.T_cw_true);
  std::vector<std::uint8_t> outlier;
  EXPECT_EQ(OptimizePose(s.camera, s.points_w, s.measurements, T, outlier), 100);
  for (std::size_t i = 100; i < 103; ++i) EXPECT_EQ(outlier[i], 1);
  EXPECT_LT(RotationErrorDeg(T, s.T_cw_true), 0.01);
}

TEST(OptimizePose, PreviousOutliersAreClassifiedAgain) {
  // One iteration a round from 10° off: after the first round most points are still far off and classified as
  // outliers; the later rounds bring the pose, and so them, back.
  const Scene s = MakeScene(200, 0.7, 0.0, 7);
  const core::Pose start =
      testing::PoseFromAxisAngle(Eigen::Vector3d(4.0, 8.0, -4.0) * kDeg, Eigen::Vector3d(0.1, 0.2, -0.1)) * s.T_cw_true;
  PoseOptimizerOptions options;
  options.iterations_per_round = 1;
  options.rounds = 1;
  core::Pose T = start;
  std::vector<std::uint8_t> outlier;
  EXPECT_LT(OptimizePose(s.camera, s.points_w, s.measurements, T, outlier, options), 150);
  options.rounds = 6;
  T = start;
  EXPECT_EQ(OptimizePose(s.camera, s.points_w, s.measurements, T, outlier, options), 200);
  EXPECT_LT(RotationErrorDeg(T, s.T_cw_true), 0.01);
}

TEST(OptimizePose, IsDeterministic) {
  const Scene s = MakeScene(300, 0.7, 1.0, 8);
  core::Pose a = Perturbed(s.T_cw_true), b = a;
  std::vector<std::uint8_t> outlier_a, outlier_b;
  EXPECT_EQ(OptimizePose(s.camera, s.points_w, s.measurements, a, outlier_a),
            OptimizePose(s.camera, s.points_w, s.measurements, b, outlier_b));
  EXPECT_TRUE(a.matrix() == b.matrix());
  EXPECT_EQ(outlier_a, outlier_b);
}

// A prior as the tracker gives one: 10 mm and 1° (at 30 Hz) around `T_cw`.
PosePrior PriorAround(const core::Pose& T_cw) {
  PosePrior prior;
  prior.T_cw = T_cw;
  prior.information.diagonal() << Eigen::Vector3d::Constant(1.0 / (kDeg * kDeg)), Eigen::Vector3d::Constant(1e4);
  return prior;
}

TEST(OptimizePose, APriorChangesLittleWhereTheKeypointsFixThePose) {
  const Scene s = MakeScene(300, 0.7, 1.0, 2);
  // The prior 3 cm and 1.5° off: the keypoints, seen all over the image, outweigh it.
  const PosePrior prior = PriorAround(
      testing::PoseFromAxisAngle(Eigen::Vector3d(1.0, 0.5, -1.0) * kDeg, Eigen::Vector3d(0.02, -0.02, 0.01)) *
      s.T_cw_true);
  core::Pose T = Perturbed(s.T_cw_true);
  std::vector<std::uint8_t> outlier;
  EXPECT_GT(OptimizePose(s.camera, s.points_w, s.measurements, T, outlier, {}, &prior), 260);
  EXPECT_LT(RotationErrorDeg(T, s.T_cw_true), 0.05);
  EXPECT_LT(TranslationError(T, s.T_cw_true), 5e-3);
}

TEST(OptimizePose, APriorHoldsTheDirectionFarPointsInOneStripLeaveOpen) {
  // 40 points 4-4.5 m away in the left sixth of the image, few with depth: a sideways step looks like a turn.
  const Scene s = MakeScene(40, 0.2, 1.0, 10, View{.width_share = 1.0 / 6.0, .near = 4.0, .far = 4.5});
  std::vector<std::uint8_t> outlier;
  core::Pose free = Perturbed(s.T_cw_true);
  OptimizePose(s.camera, s.points_w, s.measurements, free, outlier);
  const PosePrior prior = PriorAround(s.T_cw_true);
  core::Pose held = Perturbed(s.T_cw_true);
  OptimizePose(s.camera, s.points_w, s.measurements, held, outlier, {}, &prior);
  EXPECT_GT(TranslationError(free, s.T_cw_true), 0.04);
  EXPECT_LT(TranslationError(held, s.T_cw_true), 0.02);  // within twice the prior's σ
  EXPECT_LT(RotationErrorDeg(held, s.T_cw_true), 0.3);
}

TEST(OptimizePose, RejectsSpansOfDifferentSizes) {
  const Scene s = MakeScene(10, 0.7, 0.0, 9);
  core::Pose T = s.T_cw_true;
  std::vector<std::uint8_t> outlier;
  EXPECT_THROW(OptimizePose(s.camera, s.points_w, std::span(s.measurements).first(9), T, outlier),
               std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::slam
