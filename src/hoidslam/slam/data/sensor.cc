#include "hoidslam/slam/data/sensor.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "hoidslam/features/undistort.h"

namespace hoidslam::slam {

std::shared_ptr<const Sensor> Sensor::Make(const core::CameraIntrinsics& intrinsics, double bf, double close_depth,
                                           const features::ScalePyramid& pyramid) {
  if (intrinsics.width <= 0 || intrinsics.height <= 0) throw std::invalid_argument("Sensor: camera without size");
  auto sensor = std::make_shared<Sensor>();
  sensor->intrinsics = intrinsics;
  sensor->camera = RgbdCamera::From(intrinsics, bf);
  sensor->pyramid = pyramid;
  sensor->close_depth = close_depth;
  const auto w = static_cast<float>(intrinsics.width);
  const auto h = static_cast<float>(intrinsics.height);
  if (intrinsics.HasDistortion()) {
    const std::vector<cv::KeyPoint> corners = {cv::KeyPoint(0, 0, 1), cv::KeyPoint(w, 0, 1), cv::KeyPoint(0, h, 1),
                                               cv::KeyPoint(w, h, 1)};
    const std::vector<cv::Point2f> u = features::UndistortKeypoints(corners, intrinsics);
    sensor->min_x = std::min(u[0].x, u[2].x);
    sensor->max_x = std::max(u[1].x, u[3].x);
    sensor->min_y = std::min(u[0].y, u[1].y);
    sensor->max_y = std::max(u[2].y, u[3].y);
  } else {
    sensor->max_x = w;
    sensor->max_y = h;
  }
  sensor->grid_cell_inv_width = static_cast<float>(kGridCols) / (sensor->max_x - sensor->min_x);
  sensor->grid_cell_inv_height = static_cast<float>(kGridRows) / (sensor->max_y - sensor->min_y);
  return sensor;
}

}  // namespace hoidslam::slam
