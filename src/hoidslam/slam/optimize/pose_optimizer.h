#pragma once
// Pose-only optimisation: the camera pose that best explains a frame's keypoints matched to fixed map points,
// with a robust kernel and χ² outlier rejection (the motion-only bundle adjustment of ORB-SLAM's tracking).

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/core/pose.h"
#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/data/measurement.h"

namespace hoidslam::slam {

struct PoseOptimizerOptions {
  int rounds = 4;                // outlier classification rounds, >= 1
  int iterations_per_round = 10; // Gauss-Newton / Levenberg-Marquardt iterations per round, >= 1
  double chi2_mono = kChi2Mono;      // outlier threshold for keypoints without depth (2 dof)
  double chi2_stereo = kChi2Stereo;  // outlier threshold for keypoints with depth (3 dof)

  // Throws InputError naming the parameter.
  void Check() const;
};

// A soft prior on the pose: where the camera is expected (T_cw), and how firmly, as the information (inverse
// covariance) of the increment δ = (ω, υ) that takes the expected pose to the estimate, T = exp(δ) T_cw. To first
// order ω is the turn and υ the camera centre's displacement, both in the camera's frame. Where the keypoints
// constrain the pose well it changes nothing; where they leave a direction open (far points in one corner of the
// image, where a sideways step looks like a turn) it holds the pose there.
struct PosePrior {
  core::Pose T_cw = core::Pose::Identity();
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

// The increment δ = (ω, υ) with T_cw = exp(δ) prior.T_cw, to first order.
Eigen::Matrix<double, 6, 1> PriorResidual(const core::Pose& T_cw, const PosePrior& prior);
// How far T_cw departs from the prior in its own units: δᵀ information δ, a χ² with 6 degrees of freedom when the
// prior's information is the inverse covariance of where the camera may be.
double PriorChi2(const core::Pose& T_cw, const PosePrior& prior);

// Refines T_cw (world to camera) from the correspondences points_w[i] ↔ measurements[i]. Every correspondence
// starts as an inlier; after each round, each is classified by its χ² error (squared residual times inv_sigma2)
// against the threshold, and outliers take no part in the next round (but are classified again after it). All
// rounds but the last use a Huber kernel (δ = sqrt(threshold)); the last uses none. Points behind the camera
// are outliers. On return `outlier` (resized to the number of correspondences) holds the final classification
// and T_cw the refined pose; returns the number of inliers. With fewer than 3 correspondences T_cw is left
// unchanged, all are marked outliers and 0 is returned; a round with fewer than 3 inliers leaves the pose as it
// is. Levenberg-Marquardt with analytic Jacobians and a left SE(3) increment; a round stops early once the
// update is negligible. With a `prior` its squared error (weighted by its information) joins the cost in every
// round; it takes no part in the classification. Throws std::invalid_argument when the two spans differ in size, and InputError for options that fail Check().
// With `information`, it receives the information of the pose the inliers give (the Gauss-Newton Hessian of
// their residuals at the solution, without kernel or prior): its inverse is the pose's covariance, in the
// increment δ. Deterministic.
int OptimizePose(const RgbdCamera& camera, std::span<const Eigen::Vector3d> points_w,
                 std::span<const KeypointMeasurement> measurements, core::Pose& T_cw, std::vector<std::uint8_t>& outlier,
                 const PoseOptimizerOptions& options = {}, const PosePrior* prior = nullptr,
                 Eigen::Matrix<double, 6, 6>* information = nullptr);

// OptimizePose over a frame's matches: refines frame.T_cw and sets frame.outlier; with `drop_outliers` the
// outliers' matches are cleared instead. Returns the inliers.
int OptimizeFramePose(Frame& frame, const PoseOptimizerOptions& options, bool drop_outliers,
                      const PosePrior* prior = nullptr, Eigen::Matrix<double, 6, 6>* information = nullptr);

}  // namespace hoidslam::slam
