#include "hoidslam/slam/optimize/pose_optimizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "hoidslam/core/option_checks.h"

namespace hoidslam::slam {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// A round has converged once an update moves the pose by less than this (radians and metres together): far
// below what tracking can resolve, and it saves most iterations of the later rounds.
constexpr double kConvergedStep = 1e-6;
// Levenberg-Marquardt damping (Marquardt's scaling of the diagonal): start close to Gauss-Newton.
constexpr double kInitialLambda = 1e-5;
constexpr double kMinLambda = 1e-12;
constexpr double kMaxLambda = 1e8;

struct Correspondences {
  const RgbdCamera& camera;
  std::span<const Eigen::Vector3d> points_w;
  std::span<const KeypointMeasurement> measurements;
  const PoseOptimizerOptions& options;
  const PosePrior* prior;

  double Threshold(std::size_t i) const {
    return measurements[i].has_depth ? options.chi2_stereo : options.chi2_mono;
  }
};

// Unweighted residual (prediction minus measurement) of a point in camera coordinates; the third entry is
// only meaningful with depth.
Eigen::Vector3d Residual(const RgbdCamera& camera, const Eigen::Vector3d& p_c, const KeypointMeasurement& m) {
  const double iz = 1.0 / p_c.z();
  const double u = camera.fx * p_c.x() * iz + camera.cx;
  const double v = camera.fy * p_c.y() * iz + camera.cy;
  return {u - m.uv.x(), v - m.uv.y(), m.has_depth ? u - camera.bf * iz - m.ur : 0.0};
}

double Chi2(const Eigen::Vector3d& r, const KeypointMeasurement& m) {
  return (m.has_depth ? r.squaredNorm() : r.head<2>().squaredNorm()) * m.inv_sigma2;
}

struct Linearization {
  double cost = 0.0;  // robust cost; +inf when an active point went behind the camera
  Matrix6d H = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
};

// Cost and Gauss-Newton normal equations (IRLS weights for Huber) of the active correspondences at T = (R, t),
// for the left increment T <- exp(δ) T with δ = (ω, υ): d p_c / dδ = [-[p_c]x  I].
Linearization Linearize(const Correspondences& c, const std::vector<std::uint8_t>& active, const Eigen::Matrix3d& R,
                        const Eigen::Vector3d& t, bool robust) {
  Linearization lin;
  const RgbdCamera& cam = c.camera;
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (!active[i]) continue;
    const KeypointMeasurement& m = c.measurements[i];
    const Eigen::Vector3d p = R * c.points_w[i] + t;
    if (p.z() <= 0.0) {
      lin.cost = std::numeric_limits<double>::infinity();
      return lin;
    }
    const Eigen::Vector3d r = Residual(cam, p, m);
    const double chi2 = Chi2(r, m);
    double weight = m.inv_sigma2;
    if (const double delta2 = c.Threshold(i); robust && chi2 > delta2) {
      const double e = std::sqrt(chi2), delta = std::sqrt(delta2);
      lin.cost += 2.0 * delta * e - delta2;
      weight *= delta / e;
    } else {
      lin.cost += chi2;
    }

    // With G the gradients of the residuals with respect to p_c (one row each), M = w GᵀG and m = w Gᵀr, the
    // normal equations of J = G [-[p_c]x  I] are [S M Sᵀ, S M; M Sᵀ, M] and [S m; m] with S = [p_c]x. G is
    // sparse: rows (gx 0 gu), (0 gy gv) and, for ur, (gx 0 gr).
    const double iz = 1.0 / p.z(), iz2 = iz * iz;
    const double gx = cam.fx * iz, gy = cam.fy * iz, gu = -cam.fx * p.x() * iz2, gv = -cam.fy * p.y() * iz2;
    Eigen::Matrix3d M;
    Eigen::Vector3d g(gx * r.x(), gy * r.y(), gu * r.x() + gv * r.y());
    M << gx * gx, 0.0, gx * gu, 0.0, gy * gy, gy * gv, gx * gu, gy * gv, gu * gu + gv * gv;
    if (m.has_depth) {
      const double gr = gu + cam.bf * iz2;
      M(0, 0) += gx * gx;
      M(0, 2) += gx * gr;
      M(2, 0) += gx * gr;
      M(2, 2) += gr * gr;
      g += r.z() * Eigen::Vector3d(gx, 0.0, gr);
    }
    M *= weight;
    g *= weight;
    const Eigen::Matrix3d S = (Eigen::Matrix3d() << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0).finished();
    const Eigen::Matrix3d SM = S * M;
    lin.H.topLeftCorner<3, 3>().noalias() -= SM * S;
    lin.H.topRightCorner<3, 3>() += SM;
    lin.H.bottomRightCorner<3, 3>() += M;
    lin.b.head<3>() += p.cross(g);
    lin.b.tail<3>() += g;
  }
  lin.H.bottomLeftCorner<3, 3>() = lin.H.topRightCorner<3, 3>().transpose();
  if (c.prior != nullptr) {
    // Its Jacobian taken as the identity: the prior's error is small.
    core::Pose T = core::Pose::Identity();
    T.linear() = R;
    T.translation() = t;
    const Vector6d r = PriorResidual(T, *c.prior);
    const Vector6d weighted = c.prior->information * r;
    lin.cost += r.dot(weighted);
    lin.H += c.prior->information;
    lin.b += weighted;
  }
  return lin;
}

// exp(δ) T for δ = (ω, υ) on SE(3): R <- exp(ω) R, t <- exp(ω) t + V(ω) υ.
void ApplyLeftIncrement(const Vector6d& delta, Eigen::Quaterniond& q, Eigen::Vector3d& t) {
  const Eigen::Vector3d w = delta.head<3>();
  const double theta = w.norm();
  const Eigen::Matrix3d W = (Eigen::Matrix3d() << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0).finished();
  Eigen::Quaterniond dq = Eigen::Quaterniond::Identity();
  Eigen::Matrix3d V;
  if (theta < 1e-8) {
    dq = Eigen::Quaterniond(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
    V = Eigen::Matrix3d::Identity() + 0.5 * W;
  } else {
    dq = Eigen::Quaterniond(Eigen::AngleAxisd(theta, w / theta));
    const double theta2 = theta * theta;
    V = Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / theta2 * W +
        (theta - std::sin(theta)) / (theta2 * theta) * W * W;
  }
  q = (dq * q).normalized();
  t = dq * t + V * delta.tail<3>();
}

// Levenberg-Marquardt on the active correspondences, at most `iterations` steps.
void RunRound(const Correspondences& c, const std::vector<std::uint8_t>& active, bool robust, int iterations,
              Eigen::Quaterniond& q, Eigen::Vector3d& t) {
  Linearization current = Linearize(c, active, q.toRotationMatrix(), t, robust);
  double lambda = kInitialLambda;
  for (int it = 0; it < iterations; ++it) {
    Matrix6d A = current.H;
    A.diagonal() *= 1.0 + lambda;
    const Vector6d delta = A.ldlt().solve(-current.b);
    if (!delta.allFinite()) break;  // degenerate geometry: keep the pose reached

    Eigen::Quaterniond q_new = q;
    Eigen::Vector3d t_new = t;
    ApplyLeftIncrement(delta, q_new, t_new);
    Linearization candidate = Linearize(c, active, q_new.toRotationMatrix(), t_new, robust);
    const bool converged = delta.norm() < kConvergedStep;
    if (candidate.cost < current.cost) {
      q = q_new;
      t = t_new;
      current = candidate;
      lambda = std::max(lambda * 0.1, kMinLambda);
    } else {
      lambda *= 10.0;
      if (lambda > kMaxLambda) break;
    }
    if (converged) break;
  }
}

}  // namespace

void PoseOptimizerOptions::Check() const {
  core::CheckInRange(rounds, 1, 100, "PoseOptimizer.rounds");
  core::CheckInRange(iterations_per_round, 1, 1000, "PoseOptimizer.iterationsPerRound");
  core::CheckPositive(chi2_mono, "PoseOptimizer.chi2Mono");
  core::CheckPositive(chi2_stereo, "PoseOptimizer.chi2Stereo");
}

Vector6d PriorResidual(const core::Pose& T_cw, const PosePrior& prior) {
  const Eigen::Matrix3d dR = T_cw.linear() * prior.T_cw.linear().transpose();
  const Eigen::AngleAxisd turn(dR);
  Vector6d r;
  r << turn.angle() * turn.axis(), T_cw.translation() - dR * prior.T_cw.translation();
  return r;
}

double PriorChi2(const core::Pose& T_cw, const PosePrior& prior) {
  const Vector6d r = PriorResidual(T_cw, prior);
  return r.dot(prior.information * r);
}

int OptimizePose(const RgbdCamera& camera, std::span<const Eigen::Vector3d> points_w,
                 std::span<const KeypointMeasurement> measurements, core::Pose& T_cw, std::vector<std::uint8_t>& outlier,
                 const PoseOptimizerOptions& options, const PosePrior* prior, Matrix6d* information) {
  if (points_w.size() != measurements.size()) {
    throw std::invalid_argument("OptimizePose: " + std::to_string(points_w.size()) + " points but " +
                                std::to_string(measurements.size()) + " measurements");
  }
  options.Check();
  const std::size_t n = points_w.size();
  if (information != nullptr) information->setZero();
  if (n < 3) {
    outlier.assign(n, 1);
    return 0;
  }
  const Correspondences c{camera, points_w, measurements, options, prior};

  Eigen::Quaterniond q(T_cw.rotation());
  q.normalize();
  Eigen::Vector3d t = T_cw.translation();

  // Every correspondence starts as an inlier, unless its point is behind the camera.
  outlier.assign(n, 0);
  std::vector<std::uint8_t> active(n);
  {
    const Eigen::Matrix3d R = q.toRotationMatrix();
    for (std::size_t i = 0; i < n; ++i) outlier[i] = (R * points_w[i] + t).z() <= 0.0;
  }

  int inliers = 0;
  const int rounds = options.rounds;
  for (int round = 0; round < rounds; ++round) {
    int num_active = 0;
    for (std::size_t i = 0; i < n; ++i) num_active += active[i] = !outlier[i];
    // Fewer than 3 points leave the pose undetermined: keep it and only classify.
    if (num_active >= 3) RunRound(c, active, round + 1 < rounds, options.iterations_per_round, q, t);

    const Eigen::Matrix3d R = q.toRotationMatrix();
    inliers = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d p = R * points_w[i] + t;
      const bool bad = p.z() <= 0.0 || Chi2(Residual(camera, p, measurements[i]), measurements[i]) > c.Threshold(i);
      outlier[i] = bad;
      inliers += !bad;
    }
  }

  T_cw = core::Pose::Identity();
  T_cw.linear() = q.toRotationMatrix();
  T_cw.translation() = t;
  if (information != nullptr) {
    std::vector<std::uint8_t> kept(n);
    for (std::size_t i = 0; i < n; ++i) kept[i] = !outlier[i];
    const Correspondences unweighted{camera, points_w, measurements, options, nullptr};
    *information = Linearize(unweighted, kept, T_cw.linear(), t, false).H;
  }
  return inliers;
}

int OptimizeFramePose(Frame& frame, const PoseOptimizerOptions& options, bool drop_outliers, const PosePrior* prior,
                      Matrix6d* information) {
  std::vector<Eigen::Vector3d> points;
  std::vector<KeypointMeasurement> measurements;
  std::vector<int> index;
  for (int i = 0; i < frame.size(); ++i) {
    const MapPoint* p = frame.map_points[static_cast<std::size_t>(i)];
    if (p == nullptr) continue;
    points.push_back(p->position());
    measurements.push_back(frame.keypoints->Measurement(i));
    index.push_back(i);
  }
  std::vector<std::uint8_t> outlier;
  const int inliers = OptimizePose(frame.keypoints->sensor().camera, points, measurements, frame.T_cw, outlier,
                                   options, prior, information);
  for (std::size_t k = 0; k < index.size(); ++k) {
    const auto i = static_cast<std::size_t>(index[k]);
    frame.outlier[i] = outlier.empty() ? 1 : outlier[k];
    if (drop_outliers && frame.outlier[i] != 0) {
      frame.map_points[i] = nullptr;
      frame.outlier[i] = 0;
    }
  }
  return inliers;
}

}  // namespace hoidslam::slam
