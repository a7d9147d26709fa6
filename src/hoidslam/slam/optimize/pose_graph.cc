#include "hoidslam/slam/optimize/pose_graph.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <ceres/ceres.h>

namespace hoidslam::slam {
namespace {

// The error of one edge, Log(T_from_to⁻¹ · T_from,w · T_to,w⁻¹) approximated as (2 vec(q), t): zero when the two
// poses keep the relative pose asked for.
class RelativePoseError {
 public:
  explicit RelativePoseError(const core::Pose& T_from_to)
      : q_to_from_(Eigen::Quaterniond(T_from_to.rotation()).conjugate().normalized()),
        t_from_to_(T_from_to.translation()) {}

  template <typename T>
  bool operator()(const T* q_from_data, const T* t_from_data, const T* q_to_data, const T* t_to_data,
                  T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_from(q_from_data), q_to(q_to_data);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_from(t_from_data), t_to(t_to_data);
    // The relative pose the two keyframes have now: R = R_from R_toᵀ, t = t_from - R t_to.
    const Eigen::Quaternion<T> q = q_from * q_to.conjugate();
    const Eigen::Matrix<T, 3, 1> t = t_from - q * t_to;
    // Taken back by the one asked for.
    const Eigen::Quaternion<T> q_error = q_to_from_.template cast<T>() * q;
    const Eigen::Matrix<T, 3, 1> t_error = q_to_from_.template cast<T>() * (t - t_from_to_.template cast<T>());
    const T sign = q_error.w() < T(0) ? T(-1) : T(1);  // the shorter way round
    residuals[0] = T(2) * sign * q_error.x();
    residuals[1] = T(2) * sign * q_error.y();
    residuals[2] = T(2) * sign * q_error.z();
    residuals[3] = t_error.x();
    residuals[4] = t_error.y();
    residuals[5] = t_error.z();
    return true;
  }

 private:
  Eigen::Quaterniond q_to_from_;
  Eigen::Vector3d t_from_to_;
};

void Validate(const PoseGraphProblem& problem) {
  const int n = static_cast<int>(problem.T_cw.size());
  if (problem.pose_fixed.size() != problem.T_cw.size()) {
    throw std::invalid_argument("pose graph: pose_fixed has " + std::to_string(problem.pose_fixed.size()) +
                                " entries for " + std::to_string(n) + " poses");
  }
  if (std::none_of(problem.pose_fixed.begin(), problem.pose_fixed.end(), [](std::uint8_t f) { return f != 0; })) {
    throw std::invalid_argument("pose graph: no pose is fixed, so the graph could drift as a whole");
  }
  for (const PoseGraphProblem::Edge& e : problem.edges) {
    if (e.from < 0 || e.from >= n || e.to < 0 || e.to >= n || e.from == e.to) {
      throw std::invalid_argument("pose graph: edge " + std::to_string(e.from) + " → " + std::to_string(e.to) +
                                  " is out of range or joins a pose to itself");
    }
  }
}

}  // namespace

int OptimizePoseGraph(PoseGraphProblem& problem, const PoseGraphOptions& options) {
  Validate(problem);
  const std::size_t n = problem.T_cw.size();
  std::vector<std::array<double, 4>> rotations(n);  // Eigen order: x, y, z, w
  std::vector<Eigen::Vector3d> translations(n);
  for (std::size_t k = 0; k < n; ++k) {
    Eigen::Map<Eigen::Quaterniond>(rotations[k].data()) = Eigen::Quaterniond(problem.T_cw[k].rotation()).normalized();
    translations[k] = problem.T_cw[k].translation();
  }

  ceres::EigenQuaternionManifold quaternion;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);
  std::vector<std::uint8_t> used(n, 0);
  for (const PoseGraphProblem::Edge& e : problem.edges) {
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 4, 3, 4, 3>(new RelativePoseError(e.T_from_to));
    const auto from = static_cast<std::size_t>(e.from), to = static_cast<std::size_t>(e.to);
    ceres_problem.AddResidualBlock(cost, nullptr, rotations[from].data(), translations[from].data(),
                                   rotations[to].data(), translations[to].data());
    for (const std::size_t k : {from, to}) {
      if (used[k]) continue;
      used[k] = 1;
      ceres_problem.SetManifold(rotations[k].data(), &quaternion);
      if (problem.pose_fixed[k]) {
        ceres_problem.SetParameterBlockConstant(rotations[k].data());
        ceres_problem.SetParameterBlockConstant(translations[k].data());
      }
    }
  }
  if (ceres_problem.NumResidualBlocks() == 0) return 0;

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &ceres_problem, &summary);

  for (std::size_t k = 0; k < n; ++k) {
    if (problem.pose_fixed[k] || !used[k]) continue;
    problem.T_cw[k] = core::PoseFromTranslationQuaternion(translations[k],
                                                          Eigen::Map<const Eigen::Quaterniond>(rotations[k].data()));
  }
  return summary.num_successful_steps + summary.num_unsuccessful_steps;
}

}  // namespace hoidslam::slam
