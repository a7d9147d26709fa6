#include "hoidslam/dense/floor.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

namespace hoidslam::dense {

namespace {

constexpr double kMaxTilt = 0.866;       // cos 30°: how far a floor's normal may lean from the camera's up
constexpr double kLayer = 0.03;          // m, half the thickness of what counts as one horizontal surface
constexpr double kMinSupport = 0.05;     // of the upward-facing points
constexpr std::size_t kMinPoints = 200;

// The frame with z along `up`, x along the first camera's view projected on the floor, the origin at `origin`.
core::Pose FloorFrameAt(const Eigen::Vector3d& up, const Eigen::Vector3d& origin, const core::Pose& first_T_wc) {
  Eigen::Vector3d forward = first_T_wc.linear() * Eigen::Vector3d::UnitZ();
  forward -= forward.dot(up) * up;
  if (forward.norm() < 1e-6) forward = (first_T_wc.linear() * Eigen::Vector3d::UnitX()).cross(up);  // looking down
  forward.normalize();
  Eigen::Matrix3d R_fw;
  R_fw.row(0) = forward.transpose();
  R_fw.row(1) = up.cross(forward).transpose();
  R_fw.row(2) = up.transpose();
  core::Pose T_fw = core::Pose::Identity();
  T_fw.linear() = R_fw;
  T_fw.translation() = -R_fw * origin;
  return T_fw;
}

}  // namespace

FloorFrame EstimateFloor(const OrientedPoints& surface, const core::Pose& first_T_wc) {
  const Eigen::Vector3d camera_up = first_T_wc.linear() * -Eigen::Vector3d::UnitY();
  const Eigen::Vector3d camera = first_T_wc.translation();
  std::vector<std::size_t> upward;
  for (std::size_t i = 0; i < surface.points.size(); ++i) {
    if (surface.normals[i].dot(camera_up) > kMaxTilt) upward.push_back(i);
  }
  const auto height = [&](std::size_t i) { return surface.points[i].dot(camera_up); };

  FloorFrame floor;
  if (upward.size() >= kMinPoints) {
    std::sort(upward.begin(), upward.end(), [&](std::size_t a, std::size_t b) { return height(a) < height(b); });
    const std::size_t needed = std::max(kMinPoints, static_cast<std::size_t>(kMinSupport * upward.size()));
    // The lowest window of 2 × kLayer that holds `needed` points: two pointers over the sorted heights.
    std::size_t end = 0;
    for (std::size_t begin = 0; begin < upward.size(); ++begin) {
      end = std::max(end, begin);
      while (end < upward.size() && height(upward[end]) <= height(upward[begin]) + 2.0 * kLayer) ++end;
      if (end - begin < needed) continue;
      // Fit the plane to the window's points: the normal is the direction of least spread.
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (std::size_t k = begin; k < end; ++k) mean += surface.points[upward[k]];
      mean /= static_cast<double>(end - begin);
      Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
      for (std::size_t k = begin; k < end; ++k) {
        const Eigen::Vector3d d = surface.points[upward[k]] - mean;
        scatter += d * d.transpose();
      }
      Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
      if (normal.dot(camera_up) < 0.0) normal = -normal;
      floor.found = true;
      floor.T_fw = FloorFrameAt(normal, camera - (camera - mean).dot(normal) * normal, first_T_wc);
      return floor;
    }
  }
  // No floor: the camera's up, and z = 0 at the lowest surface (its 1st percentile, past stray points).
  std::vector<double> heights;
  for (const Eigen::Vector3d& p : surface.points) heights.push_back(p.dot(camera_up));
  double lowest = camera.dot(camera_up) - 1.0;
  if (!heights.empty()) {
    const auto low = heights.begin() + static_cast<std::ptrdiff_t>(heights.size() / 100);
    std::nth_element(heights.begin(), low, heights.end());
    lowest = *low;
  }
  floor.T_fw = FloorFrameAt(camera_up, camera - (camera.dot(camera_up) - lowest) * camera_up, first_T_wc);
  return floor;
}

}  // namespace hoidslam::dense
