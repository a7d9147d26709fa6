#include "hoidslam/slam/track/pnp_ransac.h"

#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "hoidslam/core/option_checks.h"

namespace hoidslam::slam {

void PnpRansacOptions::Check() const {
  core::CheckInRange(iterations, 1, 100000, "Tracking.ransacIterations");
  core::CheckPositive(max_error, "Tracking.ransacMaxError");
  core::CheckInRange(confidence, 0.5, 0.999999, "Tracking.ransacConfidence");
}

int EstimatePoseRansac(Frame& frame, const PnpRansacOptions& options) {
  const KeypointSet& keypoints = *frame.keypoints;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  std::vector<int> index;
  for (int i = 0; i < frame.size(); ++i) {
    const MapPoint* p = frame.map_points[static_cast<std::size_t>(i)];
    if (p == nullptr) continue;
    object.emplace_back(p->position().x(), p->position().y(), p->position().z());
    image.emplace_back(keypoints.undistorted(i).x(), keypoints.undistorted(i).y());
    index.push_back(i);
  }
  if (object.size() < 4) return 0;
  const core::CameraIntrinsics& intrinsics = keypoints.sensor().intrinsics;
  const cv::Matx33d K(intrinsics.fx, 0, intrinsics.cx, 0, intrinsics.fy, intrinsics.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, options.iterations,
                          static_cast<float>(options.max_error), options.confidence, inliers, cv::SOLVEPNP_EPNP)) {
    return 0;
  }
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  cv::cv2eigen(R, rotation);
  cv::cv2eigen(tvec, translation);
  frame.T_cw.linear() = rotation;
  frame.T_cw.translation() = translation;
  std::vector<MapPoint*> kept(frame.map_points.size(), nullptr);
  for (const int k : inliers) {
    const auto i = static_cast<std::size_t>(index[static_cast<std::size_t>(k)]);
    kept[i] = frame.map_points[i];
  }
  frame.map_points = std::move(kept);
  return static_cast<int>(inliers.size());
}

}  // namespace hoidslam::slam
