#include "hoidslam/slam/optimize/bundle_adjustment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <ceres/ceres.h>

namespace hoidslam::slam {
namespace {

// A keyframe's parameter block: the Eigen quaternion coefficients (x, y, z, w) of R_cw, then t_cw.
constexpr int kPoseSize = 7;
constexpr int kPoseTangentSize = 6;
using PoseBlock = std::array<double, kPoseSize>;

Eigen::Quaterniond ExpSo3(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta < 1e-8) return Eigen::Quaterniond(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta, w / theta));
}

// Tangent (ω, υ) of a pose block: R <- exp(ω) R, t <- t + υ. The cost functions below put their Jacobian with
// respect to this tangent straight into the first 6 of the 7 ambient columns (the 7th is zero), so the plus
// Jacobian is [I6; 0]: this spares Ceres a 7×6 product per residual block and us the quaternion chain rule.
class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseSize; }
  int TangentSize() const override { return kPoseTangentSize; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Eigen::Quaterniond> q(x);
    const Eigen::Map<const Eigen::Vector3d> t(x + 4), w(delta), v(delta + 3);
    Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta);
    Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta + 4);
    q_out = (ExpSo3(w) * q).normalized();
    t_out = t + v;
    return true;
  }
  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, kPoseSize, kPoseTangentSize, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<kPoseTangentSize>().setIdentity();
    return true;
  }
  bool RightMultiplyByPlusJacobian(const double* /*x*/, int num_rows, const double* ambient_matrix,
                                   double* tangent_matrix) const override {
    for (int r = 0; r < num_rows; ++r) {
      for (int c = 0; c < kPoseTangentSize; ++c) tangent_matrix[r * kPoseTangentSize + c] = ambient_matrix[r * kPoseSize + c];
    }
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Map<const Eigen::Quaterniond> qy(y), qx(x);
    const Eigen::Map<const Eigen::Vector3d> ty(y + 4), tx(x + 4);
    const Eigen::AngleAxisd dr(qy * qx.conjugate());
    Eigen::Map<Eigen::Vector3d> w(y_minus_x), v(y_minus_x + 3);
    w = dr.angle() * dr.axis();
    v = ty - tx;
    return true;
  }
  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, kPoseTangentSize, kPoseSize, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<kPoseTangentSize>().setIdentity();
    return true;
  }
};

// The reprojection error (u, v) of one observation, weighted by sqrt(inv_sigma2), and with depth a third residual:
// ORB-SLAM's ur, weighted as u and v, or, when the measurement has a disparity_information, the disparity bf / z
// alone, weighted by its square root. Analytic Jacobians (autodiff would cost most of the speed budget).
template <int kResiduals>
class ReprojectionCost final : public ceres::SizedCostFunction<kResiduals, kPoseSize, 3> {
 public:
  ReprojectionCost(const RgbdCamera& camera, const KeypointMeasurement& m)
      : camera_(camera), m_(m), scale_(std::sqrt(m.inv_sigma2)),
        disparity_scale_(std::sqrt(m.disparity_information)) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
    const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4), p_w(parameters[1]);
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const Eigen::Vector3d Rp = R * p_w;
    const Eigen::Vector3d p = Rp + t;
    if (p.z() == 0.0) return false;  // behind-camera points are still evaluated (and become outliers)

    const double iz = 1.0 / p.z();
    const double u = camera_.fx * p.x() * iz + camera_.cx;
    residuals[0] = scale_ * (u - m_.uv.x());
    residuals[1] = scale_ * (camera_.fy * p.y() * iz + camera_.cy - m_.uv.y());
    if constexpr (kResiduals == 3) {
      residuals[2] = disparity_scale_ > 0.0 ? disparity_scale_ * (camera_.bf * iz - (m_.uv.x() - m_.ur))
                                            : scale_ * (u - camera_.bf * iz - m_.ur);
    }
    if (jacobians == nullptr) return true;

    // Rows: gradients of the weighted residuals with respect to p_c.
    const double iz2 = iz * iz;
    Eigen::Matrix<double, kResiduals, 3> G;
    G.row(0) << camera_.fx * iz, 0.0, -camera_.fx * p.x() * iz2;
    G.row(1) << 0.0, camera_.fy * iz, -camera_.fy * p.y() * iz2;
    if constexpr (kResiduals == 3) G.row(2) << G(0, 0), 0.0, G(0, 2) + camera_.bf * iz2;
    G *= scale_;
    if constexpr (kResiduals == 3) {
      if (disparity_scale_ > 0.0) G.row(2) << 0.0, 0.0, -disparity_scale_ * camera_.bf * iz2;
    }

    if (jacobians[0] != nullptr) {
      // d p_c / dω = -[R p_w]x, so a row g gives (R p_w) × g; d p_c / dυ = I.
      Eigen::Map<Eigen::Matrix<double, kResiduals, kPoseSize, Eigen::RowMajor>> J(jacobians[0]);
      for (int r = 0; r < kResiduals; ++r) {
        const Eigen::Vector3d g = G.row(r).transpose();
        J.template block<1, 3>(r, 0) = Rp.cross(g).transpose();
        J.template block<1, 3>(r, 3) = g.transpose();
        J(r, 6) = 0.0;
      }
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, kResiduals, 3, Eigen::RowMajor>> J(jacobians[1]);
      J.noalias() = G * R;
    }
    return true;
  }

 private:
  const RgbdCamera& camera_;
  KeypointMeasurement m_;
  double scale_;
  double disparity_scale_;
};

// Ends a Ceres solve as soon as *stop becomes true.
class StopCallback final : public ceres::IterationCallback {
 public:
  explicit StopCallback(const std::atomic<bool>& stop) : stop_(stop) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& /*summary*/) override {
    if (!stop_.load(std::memory_order_relaxed)) return ceres::SOLVER_CONTINUE;
    stopped = true;
    return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
  }
  bool stopped = false;

 private:
  const std::atomic<bool>& stop_;
};

void Validate(const BundleAdjustmentProblem& problem) {
  const std::size_t num_poses = problem.T_cw.size();
  if (problem.pose_fixed.size() != num_poses) {
    throw std::invalid_argument("RunBundleAdjustment: " + std::to_string(problem.pose_fixed.size()) +
                                " pose_fixed flags for " + std::to_string(num_poses) + " keyframes");
  }
  bool any_fixed = false;
  for (const std::uint8_t fixed : problem.pose_fixed) any_fixed = any_fixed || fixed != 0;
  if (!any_fixed) throw std::invalid_argument("RunBundleAdjustment: no keyframe pose is fixed");
  for (std::size_t i = 0; i < problem.observations.size(); ++i) {
    const BundleAdjustmentProblem::Observation& o = problem.observations[i];
    if (o.keyframe < 0 || static_cast<std::size_t>(o.keyframe) >= num_poses || o.point < 0 ||
        static_cast<std::size_t>(o.point) >= problem.points_w.size()) {
      throw std::invalid_argument("RunBundleAdjustment: observation " + std::to_string(i) + " has keyframe " +
                                  std::to_string(o.keyframe) + " and point " + std::to_string(o.point) + " (" +
                                  std::to_string(num_poses) + " keyframes, " +
                                  std::to_string(problem.points_w.size()) + " points)");
    }
  }
}

// Whether an observation is an outlier at the current state: point behind the camera or χ² over the threshold.
bool IsOutlier(const BundleAdjustmentProblem& problem, const BundleAdjustmentOptions& options,
               const std::vector<PoseBlock>& poses, const BundleAdjustmentProblem::Observation& o) {
  const PoseBlock& pose = poses[static_cast<std::size_t>(o.keyframe)];
  const Eigen::Vector3d p = Eigen::Map<const Eigen::Quaterniond>(pose.data()) *
                                problem.points_w[static_cast<std::size_t>(o.point)] +
                            Eigen::Map<const Eigen::Vector3d>(pose.data() + 4);
  if (p.z() <= 0.0) return true;
  const KeypointMeasurement& m = o.measurement;
  const Eigen::Vector2d uv = problem.camera.Project(p);
  double chi2 = (uv - m.uv).squaredNorm();
  if (m.has_depth && m.disparity_information == 0.0) {
    const double dur = uv.x() - problem.camera.bf / p.z() - m.ur;
    chi2 += dur * dur;
  }
  chi2 *= m.inv_sigma2;
  if (m.has_depth && m.disparity_information > 0.0) {
    const double dd = problem.camera.bf / p.z() - (m.uv.x() - m.ur);
    chi2 += dd * dd * m.disparity_information;
  }
  return chi2 > (m.has_depth ? options.chi2_stereo : options.chi2_mono);
}

}  // namespace

BundleAdjustmentResult RunBundleAdjustment(BundleAdjustmentProblem& problem, const BundleAdjustmentOptions& options,
                                           const std::atomic<bool>* stop) {
  Validate(problem);
  const std::size_t num_obs = problem.observations.size();

  std::vector<PoseBlock> poses(problem.T_cw.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    Eigen::Map<Eigen::Quaterniond>(poses[k].data()) = Eigen::Quaterniond(problem.T_cw[k].rotation()).normalized();
    Eigen::Map<Eigen::Vector3d>(poses[k].data() + 4) = problem.T_cw[k].translation();
  }

  // Shared by both passes' problems, which do not own them.
  std::vector<std::unique_ptr<ceres::CostFunction>> costs(num_obs);
  for (std::size_t i = 0; i < num_obs; ++i) {
    const KeypointMeasurement& m = problem.observations[i].measurement;
    if (m.has_depth) {
      costs[i] = std::make_unique<ReprojectionCost<3>>(problem.camera, m);
    } else {
      costs[i] = std::make_unique<ReprojectionCost<2>>(problem.camera, m);
    }
  }
  PoseManifold manifold;
  ceres::HuberLoss huber_mono(std::sqrt(options.chi2_mono));
  ceres::HuberLoss huber_stereo(std::sqrt(options.chi2_stereo));

  BundleAdjustmentResult result;
  std::vector<std::uint8_t> included(num_obs, 1);
  std::vector<std::uint8_t> pose_used(poses.size());
  const auto run_pass = [&](int iterations, bool robust) {
    if (stop != nullptr && stop->load()) result.aborted = true;
    if (iterations <= 0 || result.aborted) return;

    ceres::Problem::Options problem_options;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem ceres_problem(problem_options);
    // Points first: eliminated by the Schur complement, leaving the small keyframe system.
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    std::fill(pose_used.begin(), pose_used.end(), 0);
    for (std::size_t i = 0; i < num_obs; ++i) {
      if (!included[i]) continue;
      const BundleAdjustmentProblem::Observation& o = problem.observations[i];
      const auto k = static_cast<std::size_t>(o.keyframe);
      double* pose = poses[k].data();
      double* point = problem.points_w[static_cast<std::size_t>(o.point)].data();
      ceres::LossFunction* loss = nullptr;
      if (robust) loss = o.measurement.has_depth ? &huber_stereo : &huber_mono;
      ceres_problem.AddResidualBlock(costs[i].get(), loss, pose, point);
      ordering->AddElementToGroup(point, 0);
      if (!pose_used[k]) {
        pose_used[k] = 1;
        ceres_problem.SetManifold(pose, &manifold);
        if (problem.pose_fixed[k]) ceres_problem.SetParameterBlockConstant(pose);
        ordering->AddElementToGroup(pose, 1);
      }
    }
    if (ceres_problem.NumResidualBlocks() == 0) return;

    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = options.sparse ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
    solver_options.linear_solver_ordering = ordering;
    solver_options.max_num_iterations = iterations;
    solver_options.num_threads = std::max(options.num_threads, 1);
    solver_options.logging_type = ceres::SILENT;
    std::unique_ptr<StopCallback> callback;
    if (stop != nullptr) {
      callback = std::make_unique<StopCallback>(*stop);
      solver_options.callbacks.push_back(callback.get());
    }
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &ceres_problem, &summary);
    result.iterations += summary.num_successful_steps + summary.num_unsuccessful_steps;
    if (callback && callback->stopped) result.aborted = true;
  };

  run_pass(options.first_iterations, true);
  if (options.second_iterations > 0) {
    for (std::size_t i = 0; i < num_obs; ++i) included[i] = !IsOutlier(problem, options, poses, problem.observations[i]);
  }
  run_pass(options.second_iterations, false);

  // Unobserved poses were not optimised: leave them bit for bit as they were.
  std::vector<std::uint8_t> observed(poses.size(), 0);
  for (const BundleAdjustmentProblem::Observation& o : problem.observations) observed[static_cast<std::size_t>(o.keyframe)] = 1;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (problem.pose_fixed[k] || !observed[k]) continue;
    problem.T_cw[k] = core::PoseFromTranslationQuaternion(Eigen::Map<const Eigen::Vector3d>(poses[k].data() + 4),
                                                          Eigen::Map<const Eigen::Quaterniond>(poses[k].data()));
  }
  result.outlier.resize(num_obs);
  for (std::size_t i = 0; i < num_obs; ++i) result.outlier[i] = IsOutlier(problem, options, poses, problem.observations[i]);
  return result;
}

}  // namespace hoidslam::slam
