// PLY files, read by each of the PLY readers: a map.ply as the report reads it (io::ReadPly), a triangle mesh
// (io::ReadPlyMesh) and voxel centres (io::ReadVoxelCentresPly).

#include <cmath>
#include <vector>

#include "fuzz/targets.h"
#include "hoidslam/io/ply_file.h"

namespace hoidslam::fuzz {
namespace {

bool Same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

template <typename Vector>
bool SamePoints(const std::vector<Vector>& a, const std::vector<Vector>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!Same(a[i].x(), b[i].x()) || !Same(a[i].y(), b[i].y()) || !Same(a[i].z(), b[i].z())) return false;
  }
  return true;
}

// What was read writes back as the same thing: each reader takes what its writer writes.
void FuzzPointCloud(const std::filesystem::path& path) {
  const auto points = ParseOrReject([&] { return io::ReadPly(path); }, path.string());
  if (!points) return;
  const std::filesystem::path again = ScratchDir() / "again.ply";
  io::WritePly(again, *points);
  const std::vector<io::ColoredPoint> reread = io::ReadPly(again);
  Require(reread.size() == points->size(), "a PLY read and written again lost points");
  for (std::size_t i = 0; i < reread.size(); ++i) {
    const Eigen::Vector3d& a = (*points)[i].position;
    const Eigen::Vector3d& b = reread[i].position;
    Require(reread[i].bgr == (*points)[i].bgr && Same(a.x(), b.x()) && Same(a.y(), b.y()) && Same(a.z(), b.z()),
            "a PLY read and written again changed a point");
  }
}

void FuzzMesh(const std::filesystem::path& path) {
  const auto mesh = ParseOrReject([&] { return io::ReadPlyMesh(path); }, path.string());
  if (!mesh) return;
  for (const Eigen::Vector3i& triangle : mesh->triangles) {
    Require(triangle.minCoeff() >= 0 && triangle.maxCoeff() < static_cast<int>(mesh->vertices.size()),
            "a mesh read with a vertex index out of range");
  }
  const std::filesystem::path again = ScratchDir() / "again_mesh.ply";
  io::WritePlyMesh(again, *mesh, "again");
  const io::TriangleMesh reread = io::ReadPlyMesh(again);
  Require(SamePoints(reread.vertices, mesh->vertices) && reread.triangles == mesh->triangles,
          "a mesh read and written again changed");
}

void FuzzVoxelCentres(const std::filesystem::path& path) {
  const auto voxels = ParseOrReject([&] { return io::ReadVoxelCentresPly(path); }, path.string());
  if (!voxels) return;
  Require(std::isfinite(voxels->voxel_size) && voxels->voxel_size > 0.0, "voxel centres read with a bad voxel size");
  const std::filesystem::path again = ScratchDir() / "again_voxels.ply";
  io::WriteVoxelCentresPly(again, *voxels);
  const io::VoxelCentres reread = io::ReadVoxelCentresPly(again);
  Require(reread.voxel_size == voxels->voxel_size && SamePoints(reread.centres, voxels->centres),
          "voxel centres read and written again changed");
}

}  // namespace

void FuzzPly(Bytes input) {
  const std::filesystem::path path = ScratchDir() / "input.ply";
  WriteBytes(path, input);
  FuzzPointCloud(path);
  FuzzMesh(path);
  FuzzVoxelCentres(path);
}

}  // namespace hoidslam::fuzz
