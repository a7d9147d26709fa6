#include "hoidslam/dense/display_mesh.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>
#include <open3d/geometry/BoundingVolume.h>

#include "hoidslam/dense/open3d_mesh.h"

namespace hoidslam::dense {

io::TriangleMesh MeshForDisplay(const io::TriangleMesh& mesh, std::size_t max_triangles) {
  if (max_triangles == 0) throw std::invalid_argument("MeshForDisplay: a budget of 0 triangles");
  if (!mesh.rgb.empty() && mesh.rgb.size() != mesh.vertices.size()) {
    throw std::invalid_argument(
        fmt::format("MeshForDisplay: {} colours for {} vertices", mesh.rgb.size(), mesh.vertices.size()));
  }
  if (mesh.triangles.size() <= max_triangles) return mesh;
  const open3d::geometry::TriangleMesh full = ToOpen3d(mesh);
  // A cell of edge c leaves about two triangles per c² of surface: start there, and coarsen until the budget holds
  // (a folded surface crosses more cells than its area says). Without area (degenerate triangles only), the box.
  const double area = full.GetSurfaceArea();
  double cell = area > 0.0 ? std::sqrt(2.0 * area / static_cast<double>(max_triangles))
                           : full.GetAxisAlignedBoundingBox().GetExtent().norm() / std::sqrt(static_cast<double>(max_triangles));
  cell = std::max(cell, 1e-6);
  while (true) {
    std::shared_ptr<open3d::geometry::TriangleMesh> small = full.SimplifyVertexClustering(cell);
    small->RemoveDegenerateTriangles().RemoveDuplicatedTriangles().RemoveUnreferencedVertices();
    const std::size_t triangles = small->triangles_.size();
    if (triangles <= max_triangles) return FromOpen3d(*small);
    cell *= std::max(1.1, 1.02 * std::sqrt(static_cast<double>(triangles) / static_cast<double>(max_triangles)));
  }
}

std::optional<io::TriangleMesh> ReadMeshForDisplay(const std::filesystem::path& mesh_ply, std::size_t max_triangles) {
  if (!std::filesystem::exists(mesh_ply)) return std::nullopt;
  return MeshForDisplay(io::ReadPlyMesh(mesh_ply), max_triangles);
}

}  // namespace hoidslam::dense
