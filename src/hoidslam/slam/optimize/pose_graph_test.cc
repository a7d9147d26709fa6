#include "hoidslam/slam/optimize/pose_graph.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace hoidslam::slam::pose_graph_test {
namespace {

// A camera going once round a circle of radius 2 m in `n` steps, facing outwards (world to camera).
std::vector<core::Pose> Circle(int n) {
  std::vector<core::Pose> T_cw;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * std::numbers::pi * k / n;
    core::Pose T_wc = core::Pose::Identity();
    T_wc.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_wc.translation() = Eigen::Vector3d(2.0 * std::sin(a), 0.0, 2.0 * std::cos(a));
    T_cw.push_back(T_wc.inverse());
  }
  return T_cw;
}

core::Pose Relative(const core::Pose& T_from_w, const core::Pose& T_to_w) { return T_from_w * T_to_w.inverse(); }

double MaxPositionError(const std::vector<core::Pose>& estimate, const std::vector<core::Pose>& truth) {
  double worst = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    worst = std::max(worst, (estimate[k].inverse().translation() - truth[k].inverse().translation()).norm());
  }
  return worst;
}

// Odometry edges between consecutive poses, each with the same small bias (a drifting visual odometry), the poses
// chained from them, and the first fixed.
PoseGraphProblem DriftedChain(const std::vector<core::Pose>& truth) {
  core::Pose bias = core::Pose::Identity();
  bias.linear() = Eigen::AngleAxisd(0.004, Eigen::Vector3d::UnitY()).toRotationMatrix();
  bias.translation() = Eigen::Vector3d(0.003, 0.002, 0.0);
  PoseGraphProblem problem;
  problem.T_cw.push_back(truth.front());
  problem.pose_fixed.push_back(1);
  for (std::size_t k = 1; k < truth.size(); ++k) {
    const core::Pose odometry = bias * Relative(truth[k], truth[k - 1]);  // camera k-1 into camera k
    problem.T_cw.push_back(odometry * problem.T_cw.back());
    problem.pose_fixed.push_back(0);
    problem.edges.push_back({static_cast<int>(k), static_cast<int>(k - 1), odometry});
  }
  return problem;
}

TEST(PoseGraphTest, ALoopEdgeSpreadsTheDriftOverTheCircle) {
  const std::vector<core::Pose> truth = Circle(60);
  PoseGraphProblem problem = DriftedChain(truth);
  const double drift_before = MaxPositionError(problem.T_cw, truth);
  ASSERT_GT(drift_before, 0.1);  // the chain ends far from where it started

  // The loop: the last camera seen from the first, as a loop detection measures it.
  problem.edges.push_back({59, 0, Relative(truth[59], truth[0])});
  const int iterations = OptimizePoseGraph(problem);
  EXPECT_GT(iterations, 0);
  const double drift_after = MaxPositionError(problem.T_cw, truth);
  EXPECT_LT(drift_after, 0.2 * drift_before) << drift_before << " m before";
  EXPECT_TRUE(problem.T_cw[0].isApprox(truth[0]));  // the fixed pose did not move
}

TEST(PoseGraphTest, PosesThatKeepEveryEdgeDoNotMove) {
  const std::vector<core::Pose> truth = Circle(20);
  PoseGraphProblem problem;
  problem.T_cw = truth;
  problem.pose_fixed.assign(truth.size(), 0);
  problem.pose_fixed[3] = 1;
  for (int k = 1; k < 20; ++k) problem.edges.push_back({k, k - 1, Relative(truth[k], truth[k - 1])});
  problem.edges.push_back({19, 0, Relative(truth[19], truth[0])});
  OptimizePoseGraph(problem);
  EXPECT_LT(MaxPositionError(problem.T_cw, truth), 1e-9);
}

TEST(PoseGraphTest, AGraphWithoutAFixedPoseOrWithABadEdgeIsRefused) {
  PoseGraphProblem problem;
  problem.T_cw = Circle(3);
  problem.pose_fixed = {0, 0, 0};
  problem.edges.push_back({0, 1, core::Pose::Identity()});
  EXPECT_THROW(OptimizePoseGraph(problem), std::invalid_argument);
  problem.pose_fixed = {1, 0, 0};
  problem.edges.push_back({2, 3, core::Pose::Identity()});
  EXPECT_THROW(OptimizePoseGraph(problem), std::invalid_argument);
  problem.edges.back() = {2, 2, core::Pose::Identity()};
  EXPECT_THROW(OptimizePoseGraph(problem), std::invalid_argument);
  problem.pose_fixed = {1, 0};
  problem.edges.pop_back();
  EXPECT_THROW(OptimizePoseGraph(problem), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::slam::pose_graph_test
