#pragma once
// What every frame and keyframe shares about the sensor: the camera, the virtual stereo baseline of depth
// measurements, the ORB scale pyramid, the close-depth threshold, and the bounds and grid of undistorted keypoint
// positions. Built once per run and shared read-only.

#include <memory>

#include "hoidslam/core/camera.h"
#include "hoidslam/features/orb_extractor.h"
#include "hoidslam/slam/data/measurement.h"

namespace hoidslam::slam {

struct Sensor {
  core::CameraIntrinsics intrinsics;
  RgbdCamera camera;
  features::ScalePyramid pyramid;
  double close_depth = 3.0;  // metres: below it a depth measurement counts as close (ORB-SLAM's ThDepth)

  // Bounds of the undistorted image (the distorted corners undistorted), and the keypoint grid over them.
  static constexpr int kGridCols = 64;
  static constexpr int kGridRows = 48;
  float min_x = 0, max_x = 640, min_y = 0, max_y = 480;
  float grid_cell_inv_width = 0, grid_cell_inv_height = 0;

  // Throws std::invalid_argument for a camera without size.
  static std::shared_ptr<const Sensor> Make(const core::CameraIntrinsics& intrinsics, double bf, double close_depth,
                                            const features::ScalePyramid& pyramid);

  bool InImage(double u, double v) const { return u >= min_x && u < max_x && v >= min_y && v < max_y; }
};

}  // namespace hoidslam::slam
