#pragma once
// Point clouds as PLY (binary little-endian, float x y z, uchar red green blue), the format Open3D,
// CloudCompare and MeshLab open directly.

#include <filesystem>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/matx.hpp>

namespace hoidslam::io {

struct ColoredPoint {
  Eigen::Vector3d position;  // metres
  cv::Vec3b bgr;             // colour in OpenCV's BGR order; written as RGB
};

// Writes atomically (complete or absent).
void WritePly(const std::filesystem::path& path, std::span<const ColoredPoint> points);

// Reads a file as WritePly writes it (the run's map.ply), points in file order. Throws InputError naming the file
// when it cannot be read, has another layout, or holds fewer or more bytes than its header says.
std::vector<ColoredPoint> ReadPly(const std::filesystem::path& path);

}  // namespace hoidslam::io
