#pragma once
// Point clouds as PLY (binary little-endian, float x y z, uchar red green blue), the format Open3D,
// CloudCompare and MeshLab open directly.

#include <filesystem>
#include <span>

#include <Eigen/Core>
#include <opencv2/core/matx.hpp>

namespace hoidslam::io {

struct ColoredPoint {
  Eigen::Vector3d position;  // metres
  cv::Vec3b bgr;             // colour in OpenCV's BGR order; written as RGB
};

// Writes atomically (complete or absent).
void WritePly(const std::filesystem::path& path, std::span<const ColoredPoint> points);

}  // namespace hoidslam::io
