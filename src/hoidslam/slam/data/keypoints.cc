#include "hoidslam/slam/data/keypoints.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hoidslam/features/undistort.h"

namespace hoidslam::slam {
namespace {

// The grid cell of an undistorted position, or false outside the grid.
bool CellOf(const Sensor& s, double u, double v, int& col, int& row) {
  col = static_cast<int>(std::floor((u - s.min_x) * s.grid_cell_inv_width));
  row = static_cast<int>(std::floor((v - s.min_y) * s.grid_cell_inv_height));
  return col >= 0 && col < Sensor::kGridCols && row >= 0 && row < Sensor::kGridRows;
}

// An image's pixel under each keypoint (the zero value where the image is empty or the keypoint outside it). Depth
// is registered to the colour image, so it is read at the keypoint as the sensor saw it (distorted).
template <typename Pixel>
std::vector<Pixel> SampleAt(const std::vector<cv::KeyPoint>& keypoints, const cv::Mat& image, int type,
                            const char* what) {
  if (!image.empty() && image.type() != type) throw std::invalid_argument(std::string("KeypointSet: ") + what);
  std::vector<Pixel> samples(keypoints.size(), Pixel());
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const int x = static_cast<int>(std::lround(keypoints[i].pt.x));
    const int y = static_cast<int>(std::lround(keypoints[i].pt.y));
    if (!image.empty() && x >= 0 && y >= 0 && x < image.cols && y < image.rows) samples[i] = image.at<Pixel>(y, x);
  }
  return samples;
}

}  // namespace

KeypointSet::KeypointSet(std::shared_ptr<const Sensor> sensor, std::vector<cv::KeyPoint> keypoints,
                         cv::Mat descriptors, const cv::Mat& depth, const cv::Mat& bgr)
    : KeypointSet(std::move(sensor), keypoints, std::move(descriptors),
                  SampleAt<float>(keypoints, depth, CV_32FC1, "depth must be CV_32FC1"),
                  SampleAt<cv::Vec3b>(keypoints, bgr, CV_8UC3, "colour must be CV_8UC3")) {}

KeypointSet::KeypointSet(std::shared_ptr<const Sensor> sensor, std::vector<cv::KeyPoint> keypoints,
                         cv::Mat descriptors, std::vector<float> depth, std::vector<cv::Vec3b> colors)
    : sensor_(std::move(sensor)), keypoints_(std::move(keypoints)), depth_(std::move(depth)),
      descriptors_(std::move(descriptors)), colors_(std::move(colors)) {
  const std::size_t n = keypoints_.size();
  if (static_cast<std::size_t>(descriptors_.rows) != n || (n > 0 && descriptors_.cols != 32)) {
    throw std::invalid_argument("KeypointSet: one 32-byte descriptor row per keypoint expected");
  }
  if (depth_.size() != n || colors_.size() != n) {
    throw std::invalid_argument("KeypointSet: one depth and one colour per keypoint expected");
  }

  const std::vector<cv::Point2f> undistorted = features::UndistortKeypoints(keypoints_, sensor_->intrinsics);
  undistorted_.resize(n);
  right_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    undistorted_[i] = {undistorted[i].x, undistorted[i].y};
    const float z = depth_[i];
    if (std::isfinite(z) && z > 0.0F) {
      right_[i] = undistorted_[i].x() - sensor_->camera.bf / z;
      ++num_with_depth_;
    } else {
      depth_[i] = 0.0F;
    }
  }

  // Counting sort of the keypoints into grid cells.
  constexpr int kCells = Sensor::kGridCols * Sensor::kGridRows;
  std::vector<int> cell_of(n, -1);
  cell_start_.assign(kCells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    int col = 0, row = 0;
    if (CellOf(*sensor_, undistorted_[i].x(), undistorted_[i].y(), col, row)) {
      cell_of[i] = row * Sensor::kGridCols + col;
      ++cell_start_[static_cast<std::size_t>(cell_of[i]) + 1];
    }
  }
  for (int c = 0; c < kCells; ++c) cell_start_[static_cast<std::size_t>(c) + 1] += cell_start_[static_cast<std::size_t>(c)];
  cell_indices_.resize(static_cast<std::size_t>(cell_start_.back()));
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (cell_of[i] >= 0) cell_indices_[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[i])]++)] = static_cast<int>(i);
  }
}

KeypointMeasurement KeypointSet::Measurement(int i) const {
  KeypointMeasurement m;
  m.uv = undistorted(i);
  m.has_depth = has_depth(i);
  m.ur = right(i);
  m.inv_sigma2 = sensor_->pyramid.inv_sigma2[static_cast<std::size_t>(level(i))];
  return m;
}

Eigen::Vector3d KeypointSet::Unproject(int i) const {
  const Eigen::Vector2d& uv = undistorted(i);
  return sensor_->intrinsics.Unproject(uv.x(), uv.y(), depth(i));
}

std::vector<int> KeypointSet::FeaturesInArea(double u, double v, double radius, int min_level, int max_level) const {
  std::vector<int> found;
  FeaturesInArea(u, v, radius, min_level, max_level, found);
  return found;
}

void KeypointSet::FeaturesInArea(double u, double v, double radius, int min_level, int max_level,
                                 std::vector<int>& found) const {
  found.clear();
  const Sensor& s = *sensor_;
  const int col0 = std::max(0, static_cast<int>(std::floor((u - radius - s.min_x) * s.grid_cell_inv_width)));
  const int col1 = std::min(Sensor::kGridCols - 1, static_cast<int>(std::floor((u + radius - s.min_x) * s.grid_cell_inv_width)));
  const int row0 = std::max(0, static_cast<int>(std::floor((v - radius - s.min_y) * s.grid_cell_inv_height)));
  const int row1 = std::min(Sensor::kGridRows - 1, static_cast<int>(std::floor((v + radius - s.min_y) * s.grid_cell_inv_height)));
  if (col0 > col1 || row0 > row1) return;
  for (int row = row0; row <= row1; ++row) {
    for (int col = col0; col <= col1; ++col) {
      const auto c = static_cast<std::size_t>(row * Sensor::kGridCols + col);
      for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const int i = cell_indices_[static_cast<std::size_t>(k)];
        const int l = level(i);
        if (l < min_level || (max_level >= 0 && l > max_level)) continue;
        const Eigen::Vector2d& p = undistorted(i);
        if (std::abs(p.x() - u) < radius && std::abs(p.y() - v) < radius) found.push_back(i);
      }
    }
  }
  std::sort(found.begin(), found.end());
}

}  // namespace hoidslam::slam
