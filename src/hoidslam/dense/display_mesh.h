#pragma once
// A dense mesh made small enough to show in a browser (the live viewer, the run report's 3D map): a 1 cm mesh of a
// room holds a few hundred thousand triangles, tens of MB in a report and slow to draw on a machine without a GPU.

#include <cstddef>
#include <filesystem>
#include <optional>

#include "hoidslam/io/ply_file.h"

namespace hoidslam::dense {

// `mesh` with at most `max_triangles` triangles: as it is when it has no more, else Open3D's vertex clustering
// (TriangleMesh::SimplifyVertexClustering: the vertices in each cell of a grid merged into their mean, colours
// averaged) at about the finest cell that fits the budget. Throws std::invalid_argument for a budget of 0 or
// colours not one a vertex.
io::TriangleMesh MeshForDisplay(const io::TriangleMesh& mesh, std::size_t max_triangles);

// MeshForDisplay of the mesh a file holds (a run's mesh.ply); none when there is no such file. Throws InputError
// naming the file when it cannot be read.
std::optional<io::TriangleMesh> ReadMeshForDisplay(const std::filesystem::path& mesh_ply, std::size_t max_triangles);

}  // namespace hoidslam::dense
