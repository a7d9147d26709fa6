#pragma once
// PLY files, the format Open3D, CloudCompare and MeshLab open directly: coloured point clouds (a run's map.ply),
// triangle meshes and voxel centres (the static geometry and the moving volume of a synthetic sequence). Every
// file is written binary little-endian with float coordinates, atomically (complete or absent).

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/matx.hpp>

namespace hoidslam::io {

struct ColoredPoint {
  Eigen::Vector3d position;  // metres
  cv::Vec3b bgr;             // colour in OpenCV's BGR order; written as RGB
};

// Writes float x y z, uchar red green blue per point.
void WritePly(const std::filesystem::path& path, std::span<const ColoredPoint> points);

// Reads a file as WritePly writes it (the run's map.ply), points in file order. Throws InputError naming the file
// when it cannot be read, has another layout, or holds fewer or more bytes than its header says.
std::vector<ColoredPoint> ReadPly(const std::filesystem::path& path);

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;   // metres
  std::vector<Eigen::Vector3i> triangles;  // indices into `vertices`, counter-clockwise seen from outside
  std::vector<cv::Vec3b> rgb;              // each vertex's colour (red, green, blue), or empty: none
};

// Writes float x y z (and uchar red green blue when the mesh has colours) per vertex and a face list (uchar count,
// int indices) with the header line "comment <comment>" (one line of text). Throws std::invalid_argument when the
// mesh has colours but not one a vertex.
void WritePlyMesh(const std::filesystem::path& path, const TriangleMesh& mesh, std::string_view comment);

// Reads a triangle mesh: what WritePlyMesh writes, and meshes as Open3D writes them (ascii or binary_little_endian;
// x y z float or double; colours when the vertices have uchar red, green and blue; other vertex properties such as
// normals skipped; a face list of any integer types; other elements skipped). Throws InputError naming the file when it cannot be read, is not such a PLY
// file, holds a face that is not a triangle or an index out of range, or holds fewer or more values than its
// header says.
TriangleMesh ReadPlyMesh(const std::filesystem::path& path);

// The centres of the cells of a regular grid, such as the cells something occupied.
struct VoxelCentres {
  double voxel_size = 0.0;  // edge of a cell, metres
  std::vector<Eigen::Vector3f> centres;
};

// A grid cell's index (i, j, k) packed into one key, 21 bits an axis, offset by kCellReach so that indices in
// [-kCellReach, kCellReach) fit and keys sort in (i, j, k) order: the sets of cells synth writes and eval reads.
inline constexpr int kCellBits = 21;
inline constexpr std::int64_t kCellReach = std::int64_t{1} << (kCellBits - 1);
std::uint64_t PackCell(std::int64_t i, std::int64_t j, std::int64_t k);
std::int64_t UnpackCell(std::uint64_t key, int axis);  // axis 0, 1 or 2
// The key of the cell of edge `size` that holds `point`.
std::uint64_t CellKeyOf(const Eigen::Vector3d& point, double size);

// Writes float x y z per centre with the header line "comment voxel_size <size>" (the shortest decimal that
// reads back as the same double).
void WriteVoxelCentresPly(const std::filesystem::path& path, const VoxelCentres& voxels);

// Reads what WriteVoxelCentresPly writes (and points read as ReadPlyMesh reads vertices), centres in file order.
// Throws InputError naming the file as ReadPlyMesh does, and when the header has no single voxel_size comment
// of a finite size > 0 or the file holds faces.
VoxelCentres ReadVoxelCentresPly(const std::filesystem::path& path);

}  // namespace hoidslam::io
