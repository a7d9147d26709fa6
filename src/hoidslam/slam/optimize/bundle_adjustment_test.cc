#include "hoidslam/slam/optimize/bundle_adjustment.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::slam::bundle_adjustment_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Each random number is drawn in a statement of its own: the order in which a call's arguments are evaluated is
// unspecified (GCC goes right to left, clang left to right), and the scene must not depend on the compiler. Its
// order is GCC's, with which the thresholds below were set.
template <typename Distribution>
Eigen::Vector3d RandomVector(Distribution& distribution, std::mt19937& rng,
                             const Eigen::Vector3d& scale = Eigen::Vector3d::Ones(),
                             const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  const double z = distribution(rng);
  const double y = distribution(rng);
  const double x = distribution(rng);
  return scale.cwiseProduct(Eigen::Vector3d(x, y, z)) + offset;
}

struct Scene {
  BundleAdjustmentProblem problem;  // holds the true state until Perturb
  std::vector<core::Pose> T_cw_true;
  std::vector<Eigen::Vector3d> points_true;
};

// Camera at `centre` looking at the origin.
core::Pose LookAtOrigin(const Eigen::Vector3d& centre) {
  const Eigen::Vector3d z = -centre.normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  core::Pose T_wc = core::Pose::Identity();
  T_wc.linear() << x, z.cross(x), z;
  T_wc.translation() = centre;
  return T_wc.inverse();
}

// Keyframes on an arc 4 m from a 4×3×3 m cloud of points, the first `num_fixed` of them fixed; each point seen
// (noise-free) by up to `views` keyframes it projects into, a `depth_fraction` of the observations with depth.
Scene MakeScene(int num_fixed, int num_free, int num_points, int views, double depth_fraction, std::uint32_t seed) {
  Scene s;
  BundleAdjustmentProblem& p = s.problem;
  const int num_keyframes = num_fixed + num_free;
  for (int k = 0; k < num_keyframes; ++k) {
    const double a = (k - num_keyframes / 2.0) * 4.0 * kDeg;
    p.T_cw.push_back(LookAtOrigin(Eigen::Vector3d(4.0 * std::sin(a), 0.2 * std::sin(3.0 * k), -4.0 * std::cos(a))));
    p.pose_fixed.push_back(k < num_fixed ? 1 : 0);
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> level(0, 7);
  while (static_cast<int>(p.points_w.size()) < num_points) {
    const Eigen::Vector3d x =
        RandomVector(unit, rng, Eigen::Vector3d(4.0, 3.0, 3.0), Eigen::Vector3d(-2.0, -1.5, -1.5));
    std::vector<int> seen_by;
    for (int k = 0; k < num_keyframes; ++k) {
      const Eigen::Vector3d p_c = p.T_cw[static_cast<std::size_t>(k)] * x;
      const Eigen::Vector2d uv = p.camera.Project(p_c);
      if (p_c.z() > 0.5 && uv.x() >= 0 && uv.x() < 640 && uv.y() >= 0 && uv.y() < 480) seen_by.push_back(k);
    }
    if (seen_by.size() < 2) continue;
    std::shuffle(seen_by.begin(), seen_by.end(), rng);
    seen_by.resize(std::min<std::size_t>(seen_by.size(), static_cast<std::size_t>(views)));
    const int point = static_cast<int>(p.points_w.size());
    p.points_w.push_back(x);
    for (const int k : seen_by) {
      const Eigen::Vector3d p_c = p.T_cw[static_cast<std::size_t>(k)] * x;
      BundleAdjustmentProblem::Observation o{.keyframe = k, .point = point, .measurement = {}};
      o.measurement.uv = p.camera.Project(p_c);
      o.measurement.has_depth = unit(rng) < depth_fraction;
      o.measurement.ur = p.camera.ProjectRight(p_c);
      o.measurement.inv_sigma2 = std::pow(1.2, -2.0 * level(rng));
      p.observations.push_back(o);
    }
  }
  s.T_cw_true = p.T_cw;
  s.points_true = p.points_w;
  return s;
}

// Moves the free poses by about 2° and 5 cm and the points by about 3 cm.
void Perturb(BundleAdjustmentProblem& p, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (std::size_t k = 0; k < p.T_cw.size(); ++k) {
    if (p.pose_fixed[k]) continue;
    const Eigen::Vector3d w = RandomVector(normal, rng).normalized() * 2.0 * kDeg;
    core::Pose D = core::Pose::Identity();
    D.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    D.translation() = 0.03 * RandomVector(normal, rng);
    p.T_cw[k] = D * p.T_cw[k];
  }
  for (Eigen::Vector3d& x : p.points_w) x += 0.03 * RandomVector(normal, rng);
}

double RotationErrorDeg(const core::Pose& a, const core::Pose& b) {
  return Eigen::AngleAxisd(a.linear() * b.linear().transpose()).angle() / kDeg;
}
double CentreError(const core::Pose& a, const core::Pose& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

struct Errors {
  double rotation_deg = 0.0, centre = 0.0, point = 0.0;  // worst pose errors, mean point error
};
Errors Measure(const Scene& s) {
  Errors e;
  for (std::size_t k = 0; k < s.T_cw_true.size(); ++k) {
    e.rotation_deg = std::max(e.rotation_deg, RotationErrorDeg(s.problem.T_cw[k], s.T_cw_true[k]));
    e.centre = std::max(e.centre, CentreError(s.problem.T_cw[k], s.T_cw_true[k]));
  }
  for (std::size_t i = 0; i < s.points_true.size(); ++i) e.point += (s.problem.points_w[i] - s.points_true[i]).norm();
  e.point /= static_cast<double>(s.points_true.size());
  return e;
}

TEST(BundleAdjustment, RefinesFreePosesAndPointsAndKeepsFixedPoses) {
  Scene s = MakeScene(3, 4, 400, 4, 0.7, 1);
  Perturb(s.problem, 11);
  const Errors before = Measure(s);
  ASSERT_GT(before.rotation_deg, 1.0);
  ASSERT_GT(before.point, 0.03);

  const BundleAdjustmentResult result = RunBundleAdjustment(s.problem);
  const Errors after = Measure(s);
  EXPECT_LT(after.rotation_deg, 0.01);
  EXPECT_LT(after.centre, 1e-3);
  EXPECT_LT(after.point, 1e-3);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_TRUE(s.problem.T_cw[k].matrix() == s.T_cw_true[k].matrix());
  EXPECT_FALSE(result.aborted);
  EXPECT_GT(result.iterations, 0);
  ASSERT_EQ(result.outlier.size(), s.problem.observations.size());
  EXPECT_EQ(std::count(result.outlier.begin(), result.outlier.end(), 1), 0);
}

TEST(BundleAdjustment, WorksWithoutDepth) {
  Scene s = MakeScene(3, 4, 400, 4, 0.0, 2);
  Perturb(s.problem, 12);
  RunBundleAdjustment(s.problem, {.first_iterations = 10, .second_iterations = 20});
  const Errors after = Measure(s);
  EXPECT_LT(after.rotation_deg, 0.01);
  EXPECT_LT(after.centre, 1e-3);
  EXPECT_LT(after.point, 1e-3);
}

TEST(BundleAdjustment, FlagsGrossOutliers) {
  Scene s = MakeScene(3, 4, 400, 4, 0.7, 3);
  std::vector<std::uint8_t> corrupted(s.problem.observations.size(), 0);
  for (std::size_t i = 7; i < corrupted.size(); i += 20) {  // 5 % mismatches, 40 px off
    KeypointMeasurement& m = s.problem.observations[i].measurement;
    m.uv += Eigen::Vector2d(i % 40 < 20 ? 40.0 : -40.0, 30.0);
    m.ur += i % 40 < 20 ? 40.0 : -40.0;
    corrupted[i] = 1;
  }
  Perturb(s.problem, 13);
  const BundleAdjustmentResult result = RunBundleAdjustment(s.problem);
  ASSERT_EQ(result.outlier.size(), corrupted.size());
  // Every mismatch is flagged. A mismatch at a fine pyramid level can drag a point seen by few keyframes at
  // coarse levels far enough for some of its good observations to be flagged too (as in ORB-SLAM), but rarely.
  int false_alarms = 0, clean = 0;
  for (std::size_t i = 0; i < corrupted.size(); ++i) {
    if (corrupted[i]) {
      EXPECT_EQ(result.outlier[i], 1) << "observation " << i;
    } else {
      ++clean;
      false_alarms += result.outlier[i];
    }
  }
  EXPECT_LT(false_alarms, clean / 100);
  const Errors after = Measure(s);
  EXPECT_LT(after.rotation_deg, 0.01);
  EXPECT_LT(after.centre, 1e-3);
}

TEST(BundleAdjustment, PointsBehindACameraAreOutliers) {
  Scene s = MakeScene(3, 4, 200, 4, 0.7, 4);
  // Point 0 seen by a camera turned around: it lies behind it.
  BundleAdjustmentProblem& p = s.problem;
  core::Pose back = core::Pose::Identity();
  back.linear() = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY()).toRotationMatrix();
  p.T_cw.push_back(back * p.T_cw[0]);
  p.pose_fixed.push_back(1);
  KeypointMeasurement m;
  m.uv = Eigen::Vector2d(320.0, 240.0);
  p.observations.push_back({.keyframe = static_cast<int>(p.T_cw.size()) - 1, .point = 0, .measurement = m});
  ASSERT_LT((p.T_cw.back() * p.points_w[0]).z(), 0.0);
  const BundleAdjustmentResult result = RunBundleAdjustment(p);
  EXPECT_EQ(result.outlier.back(), 1);
  EXPECT_EQ(std::count(result.outlier.begin(), result.outlier.end(), 1), 1);
}

TEST(BundleAdjustment, IgnoresUnobservedPosesAndPoints) {
  Scene s = MakeScene(3, 4, 300, 4, 0.7, 5);
  Perturb(s.problem, 15);
  BundleAdjustmentProblem& p = s.problem;
  const core::Pose lonely = LookAtOrigin(Eigen::Vector3d(0.0, 4.0, 0.0));
  p.T_cw.push_back(lonely);
  p.pose_fixed.push_back(0);
  p.points_w.emplace_back(0.1, 0.2, 0.3);
  RunBundleAdjustment(p);
  EXPECT_TRUE(p.T_cw.back().matrix() == lonely.matrix());
  EXPECT_TRUE(p.points_w.back() == Eigen::Vector3d(0.1, 0.2, 0.3));
  p.T_cw.pop_back();
  p.points_w.pop_back();
  EXPECT_LT(Measure(s).rotation_deg, 0.01);
}

TEST(BundleAdjustment, RefinesPointsWhenAllPosesAreFixed) {
  Scene s = MakeScene(5, 0, 300, 4, 0.7, 6);
  Perturb(s.problem, 16);
  RunBundleAdjustment(s.problem);
  EXPECT_LT(Measure(s).point, 1e-3);
}

TEST(BundleAdjustment, IsDeterministic) {
  Scene s = MakeScene(4, 6, 800, 5, 0.7, 7);
  Perturb(s.problem, 17);
  for (std::size_t i = 3; i < s.problem.observations.size(); i += 25) s.problem.observations[i].measurement.uv.x() += 25.0;
  BundleAdjustmentProblem a = s.problem, b = s.problem;
  const BundleAdjustmentResult ra = RunBundleAdjustment(a), rb = RunBundleAdjustment(b);
  EXPECT_EQ(ra.outlier, rb.outlier);
  EXPECT_EQ(ra.iterations, rb.iterations);
  for (std::size_t k = 0; k < a.T_cw.size(); ++k) EXPECT_TRUE(a.T_cw[k].matrix() == b.T_cw[k].matrix()) << k;
  EXPECT_TRUE(a.points_w == b.points_w);
}

// Gives every observation with depth the disparity information of the Kinect model times `factor`, at its true
// depth (call before Perturb).
void WeighDepthBySensorNoise(Scene& s, double factor) {
  const core::DepthNoiseModel model{.factor = factor};
  for (BundleAdjustmentProblem::Observation& o : s.problem.observations) {
    if (!o.measurement.has_depth) continue;
    const double z = (s.T_cw_true[static_cast<std::size_t>(o.keyframe)] *
                      s.points_true[static_cast<std::size_t>(o.point)]).z();
    o.measurement.disparity_information = model.DisparityInformation(s.problem.camera.bf, z);
  }
}

TEST(BundleAdjustment, ConvergesWithDepthWeighedBySensorNoise) {
  Scene s = MakeScene(3, 4, 400, 4, 0.7, 21);
  WeighDepthBySensorNoise(s, 2.0);
  Perturb(s.problem, 31);
  ASSERT_GT(Measure(s).point, 0.03);
  const BundleAdjustmentResult result = RunBundleAdjustment(s.problem);
  const Errors after = Measure(s);
  EXPECT_LT(after.rotation_deg, 0.01);
  EXPECT_LT(after.centre, 1e-3);
  EXPECT_LT(after.point, 1e-3);
  EXPECT_EQ(std::count(result.outlier.begin(), result.outlier.end(), 1), 0);
}

// Two fixed keyframes 5 cm apart see points 2 m away, with 0.3 px of keypoint noise and depth as noisy as the
// Kinect model says (6 mm there). Triangulation over 5 cm leaves some 4 cm of depth error, so the depths decide:
// weighed by the model they are trusted, weighed as one pixel of ur (some 10 cm at 2 m) they are not.
double MeanDepthErrorOfNoisyPoints(bool weigh_by_sensor_noise) {
  const core::DepthNoiseModel truth{.factor = 1.0};
  std::mt19937 rng(41);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  BundleAdjustmentProblem p;
  for (const double x : {0.0, 0.05}) {
    core::Pose T_cw = core::Pose::Identity();
    T_cw.translation() = Eigen::Vector3d(-x, 0.0, 0.0);
    p.T_cw.push_back(T_cw);
    p.pose_fixed.push_back(1);
  }
  std::vector<Eigen::Vector3d> points_true;
  for (int i = 0; i < 200; ++i) {
    const double px = unit(rng);
    const double py = unit(rng);
    const double pz = 2.0 + 0.1 * unit(rng);
    points_true.emplace_back(px, 0.7 * py, pz);
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d p_c = p.T_cw[static_cast<std::size_t>(k)] * points_true.back();
      KeypointMeasurement m;
      const double du = normal(rng);
      const double dv = normal(rng);
      const double dz = normal(rng);
      m.uv = p.camera.Project(p_c) + 0.3 * Eigen::Vector2d(du, dv);
      m.has_depth = true;
      const double z = p_c.z() + truth.Sigma(p_c.z()) * dz;
      m.ur = m.uv.x() - p.camera.bf / z;
      if (weigh_by_sensor_noise) m.disparity_information = truth.DisparityInformation(p.camera.bf, z);
      p.observations.push_back({.keyframe = k, .point = i, .measurement = m});
    }
    p.points_w.push_back(points_true.back() + Eigen::Vector3d(0.0, 0.0, 0.05));
  }
  RunBundleAdjustment(p);
  double error = 0.0;
  for (std::size_t i = 0; i < points_true.size(); ++i) error += std::abs(p.points_w[i].z() - points_true[i].z());
  return error / static_cast<double>(points_true.size());
}

TEST(BundleAdjustment, TrustsDepthAsMuchAsTheSensorNoiseModelSays) {
  const double by_sensor_noise = MeanDepthErrorOfNoisyPoints(true);
  const double as_one_pixel = MeanDepthErrorOfNoisyPoints(false);
  EXPECT_LT(by_sensor_noise, 0.006);
  EXPECT_LT(by_sensor_noise, 0.5 * as_one_pixel);
}

TEST(BundleAdjustment, FlagsADepthTheSensorNoiseModelRulesOut) {
  Scene s = MakeScene(3, 4, 300, 4, 1.0, 22);
  WeighDepthBySensorNoise(s, 2.0);
  // 15 % too deep is 7–25 σ of the doubled model at the scene's 2–6 m.
  KeypointMeasurement& m = s.problem.observations[10].measurement;
  const double z = s.problem.camera.bf / (m.uv.x() - m.ur);
  m.ur = m.uv.x() - s.problem.camera.bf / (1.15 * z);
  const BundleAdjustmentResult result = RunBundleAdjustment(s.problem);
  EXPECT_EQ(result.outlier[10], 1);
  EXPECT_EQ(std::count(result.outlier.begin(), result.outlier.end(), 1), 1);
}

TEST(BundleAdjustment, StopsAtOnceWhenAskedTo) {
  Scene s = MakeScene(3, 4, 300, 4, 0.7, 8);
  Perturb(s.problem, 18);
  const std::vector<Eigen::Vector3d> start = s.problem.points_w;
  const std::atomic<bool> stop{true};
  const BundleAdjustmentResult result = RunBundleAdjustment(s.problem, {}, &stop);
  EXPECT_TRUE(result.aborted);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_TRUE(s.problem.points_w == start);
  EXPECT_EQ(result.outlier.size(), s.problem.observations.size());
}

TEST(BundleAdjustment, RejectsBadProblems) {
  const Scene s = MakeScene(2, 2, 50, 3, 0.7, 9);
  const auto throws = [](BundleAdjustmentProblem p) {
    EXPECT_THROW(RunBundleAdjustment(p), std::invalid_argument);
  };
  BundleAdjustmentProblem p = s.problem;
  p.observations[5].keyframe = 4;
  throws(p);
  p = s.problem;
  p.observations[5].keyframe = -1;
  throws(p);
  p = s.problem;
  p.observations[0].point = 50;
  throws(p);
  p = s.problem;
  p.observations[0].point = -1;
  throws(p);
  p = s.problem;
  p.pose_fixed.assign(4, 0);
  throws(p);
  p = s.problem;
  p.pose_fixed.pop_back();
  throws(p);
}

}  // namespace
}  // namespace hoidslam::slam::bundle_adjustment_test
