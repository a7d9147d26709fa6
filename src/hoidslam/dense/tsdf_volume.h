#pragma once
// The static world as a truncated signed distance volume (Open3D's ScalableTSDFVolume: blocks of 16³ coloured voxels,
// kVolumeBlockVoxels, allocated where surfaces are), and what is drawn from it: a coloured triangle mesh (marching
// cubes) and a dense cloud of points at the voxel size. Open3D stays inside this file's .cc.
//
// Open3D 0.16 has two volumes; on this project's 2-core machine the legacy one integrates a 640×480 keyframe at
// 1 cm in 26 ms on one thread where the tensor VoxelBlockGrid takes 58 ms and, its blocks allocated up front,
// twice the memory (docs/dense.md).

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/dense/dense_options.h"
#include "hoidslam/io/ply_file.h"

namespace hoidslam::dense {

struct MeshCounts {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  double area = 0.0;         // m²
  std::size_t left_out = 0;  // vertices a PointFilter left out, with their triangles
};

// Says of a point of the surface (world) whether to leave it out of what is written.
using PointFilter = std::function<bool(const Eigen::Vector3d& p_w)>;

// Points of the surface with their normals (unit, pointing out of the surface towards where the cameras were).
struct OrientedPoints {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;
};

// Makes Open3D's OpenMP loops run on one thread when called from this thread. Open3D parallelises a view's
// integration over the volume's blocks in many short loops: two threads on a 2-core machine that something else
// keeps busy spin at their barriers against each other, and a keyframe took 0.3–2 s instead of 25 ms.
void UseOneOpenMPThread();

class TsdfVolume {
 public:
  TsdfVolume(const DenseOptions& options, const core::CameraIntrinsics& camera);
  ~TsdfVolume();
  TsdfVolume(const TsdfVolume&) = delete;
  TsdfVolume& operator=(const TsdfVolume&) = delete;

  // Fuses one view: colour CV_8UC3 (BGR), depth CV_32FC1 in metres with 0 where nothing is to be fused
  // (FusibleDepth; depth beyond options.max_depth is not fused either), the camera at T_wc. Throws
  // std::invalid_argument for images of another type or size.
  void Integrate(const cv::Mat& bgr, const cv::Mat& depth, const core::Pose& T_wc);

  std::size_t Blocks() const;       // blocks of kVolumeBlockVoxels³ voxels allocated
  std::size_t MemoryBytes() const;  // what they take

  // Writes the mesh (binary PLY, vertex colours and normals) / the points at the voxels' zero crossings, each
  // atomically, without the vertices (and their triangles) / points `leave_out` names (none: all); with nothing
  // left, no file (Open3D neither writes nor reads an empty one). Throws InputError naming the file when it cannot
  // be written.
  MeshCounts WriteMesh(const std::filesystem::path& path, const PointFilter& leave_out = {}) const;
  std::size_t WriteCloud(const std::filesystem::path& path, const PointFilter& leave_out = {}) const;
  // The mesh as it stands (marching cubes), with its vertices' colours: what the live preview shows.
  io::TriangleMesh Mesh() const;
  // The cloud's points, every `step`-th, with normals: what the floor is looked for in.
  OrientedPoints SamplePoints(std::size_t step) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hoidslam::dense
