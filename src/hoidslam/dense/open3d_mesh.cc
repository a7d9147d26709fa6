#include "hoidslam/dense/open3d_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hoidslam::dense {

open3d::geometry::TriangleMesh ToOpen3d(const io::TriangleMesh& mesh) {
  open3d::geometry::TriangleMesh out;
  out.vertices_.reserve(mesh.vertices.size());
  for (const Eigen::Vector3f& v : mesh.vertices) out.vertices_.push_back(v.cast<double>());
  out.triangles_ = mesh.triangles;
  out.vertex_colors_.reserve(mesh.rgb.size());
  for (const cv::Vec3b& c : mesh.rgb) out.vertex_colors_.emplace_back(c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
  return out;
}

io::TriangleMesh FromOpen3d(const open3d::geometry::TriangleMesh& mesh) {
  io::TriangleMesh out;
  out.vertices.reserve(mesh.vertices_.size());
  for (const Eigen::Vector3d& v : mesh.vertices_) out.vertices.push_back(v.cast<float>());
  out.triangles = mesh.triangles_;
  const auto channel = [](double value) {
    return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(value, 0.0, 1.0)));
  };
  out.rgb.reserve(mesh.vertex_colors_.size());
  for (const Eigen::Vector3d& c : mesh.vertex_colors_) out.rgb.emplace_back(channel(c.x()), channel(c.y()), channel(c.z()));
  return out;
}

}  // namespace hoidslam::dense
