// The SLAM core's two optimisers at the sizes they meet in tracking and local mapping:
// - OptimizePose, 500 correspondences (30 % without depth, 10 % gross outliers), from a pose ~1° and 3 cm off;
//   it runs twice per frame, so it should take well under 1 ms;
// - RunBundleAdjustment, a local BA of 10 free + 10 fixed keyframes, 3000 points and ~15000 observations
//   (5 per point, 70 % with depth), free poses ~1° and 3 cm off and points ~2 cm off: target <= ~150 ms.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>

#include "hoidslam/slam/optimize/bundle_adjustment.h"
#include "hoidslam/slam/optimize/pose_optimizer.h"

namespace hoidslam::slam {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

core::Pose SmallMotion(std::mt19937& rng, double degrees, double metres) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d w = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  core::Pose D = core::Pose::Identity();
  D.linear() = Eigen::AngleAxisd(degrees * kDeg, w).toRotationMatrix();
  D.translation() = metres * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  return D;
}

// Noise of 1 px at level 0, scaled with the level like ORB keypoints.
KeypointMeasurement Observe(const RgbdCamera& camera, const Eigen::Vector3d& p_c, bool has_depth, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  const int level = std::uniform_int_distribution<int>(0, 7)(rng);
  const double sigma = std::pow(1.2, level);
  KeypointMeasurement m;
  m.inv_sigma2 = 1.0 / (sigma * sigma);
  m.uv = camera.Project(p_c) + sigma * Eigen::Vector2d(noise(rng), noise(rng));
  m.has_depth = has_depth;
  if (has_depth) m.ur = camera.ProjectRight(p_c) + sigma * noise(rng);
  return m;
}

void BM_OptimizePose(benchmark::State& state) {
  const int n = 500;
  const RgbdCamera camera;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const core::Pose T_cw_true = SmallMotion(rng, 20.0, 1.0);
  std::vector<Eigen::Vector3d> points_w;
  std::vector<KeypointMeasurement> measurements;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 + 5.0 * unit(rng);
    const Eigen::Vector3d p_c((unit(rng) * 640.0 - camera.cx) * z / camera.fx,
                              (unit(rng) * 480.0 - camera.cy) * z / camera.fy, z);
    KeypointMeasurement m = Observe(camera, p_c, unit(rng) >= 0.3, rng);
    if (i % 10 == 0) m.uv += Eigen::Vector2d(40.0 + 60.0 * unit(rng), -40.0 - 60.0 * unit(rng));
    points_w.push_back(T_cw_true.inverse() * p_c);
    measurements.push_back(m);
  }
  const core::Pose start = SmallMotion(rng, 1.0, 0.03) * T_cw_true;
  std::vector<std::uint8_t> outlier;
  int inliers = 0;
  for (auto _ : state) {
    core::Pose T_cw = start;
    inliers = OptimizePose(camera, points_w, measurements, T_cw, outlier);
    benchmark::DoNotOptimize(T_cw);
  }
  state.counters["inliers"] = inliers;
}
BENCHMARK(BM_OptimizePose)->Unit(benchmark::kMicrosecond);

// Keyframes along a 2 m sweep around a room-sized cloud of points, alternately fixed and free.
BundleAdjustmentProblem LocalMap(int keyframes, int points, int views) {
  BundleAdjustmentProblem problem;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < keyframes; ++k) {
    const double a = (k - keyframes / 2.0) * 3.0 * kDeg;
    const Eigen::Vector3d centre(4.0 * std::sin(a), 0.1 * std::sin(k), -4.0 * std::cos(a));
    const Eigen::Vector3d z = -centre.normalized();
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    core::Pose T_wc = core::Pose::Identity();
    T_wc.linear() << x, z.cross(x), z;
    T_wc.translation() = centre;
    problem.T_cw.push_back(T_wc.inverse());
    problem.pose_fixed.push_back(k % 2);
  }
  while (static_cast<int>(problem.points_w.size()) < points) {
    const Eigen::Vector3d x(4.0 * unit(rng) - 2.0, 3.0 * unit(rng) - 1.5, 3.0 * unit(rng) - 1.5);
    std::vector<int> seen_by;
    for (int k = 0; k < keyframes; ++k) {
      const Eigen::Vector3d p_c = problem.T_cw[static_cast<std::size_t>(k)] * x;
      const Eigen::Vector2d uv = problem.camera.Project(p_c);
      if (p_c.z() > 0.5 && uv.x() >= 0 && uv.x() < 640 && uv.y() >= 0 && uv.y() < 480) seen_by.push_back(k);
    }
    if (static_cast<int>(seen_by.size()) < views) continue;
    std::shuffle(seen_by.begin(), seen_by.end(), rng);
    const int point = static_cast<int>(problem.points_w.size());
    problem.points_w.push_back(x);
    for (int v = 0; v < views; ++v) {
      const int k = seen_by[static_cast<std::size_t>(v)];
      const Eigen::Vector3d p_c = problem.T_cw[static_cast<std::size_t>(k)] * x;
      problem.observations.push_back({k, point, Observe(problem.camera, p_c, unit(rng) < 0.7, rng)});
    }
  }
  for (std::size_t k = 0; k < problem.T_cw.size(); ++k) {
    if (!problem.pose_fixed[k]) problem.T_cw[k] = SmallMotion(rng, 1.0, 0.03) * problem.T_cw[k];
  }
  std::normal_distribution<double> normal(0.0, 0.02);
  for (Eigen::Vector3d& x : problem.points_w) x += Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  return problem;
}

void BM_LocalBundleAdjustment(benchmark::State& state) {
  const BundleAdjustmentProblem start = LocalMap(20, 3000, 5);
  BundleAdjustmentOptions options;
  options.num_threads = static_cast<int>(state.range(0));
  int iterations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    BundleAdjustmentProblem problem = start;
    state.ResumeTiming();
    iterations = RunBundleAdjustment(problem, options).iterations;
    benchmark::DoNotOptimize(problem.points_w.data());
  }
  state.counters["observations"] = static_cast<double>(start.observations.size());
  state.counters["ceres_iterations"] = iterations;
}
BENCHMARK(BM_LocalBundleAdjustment)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoidslam::slam
