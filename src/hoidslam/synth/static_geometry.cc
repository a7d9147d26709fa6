#include "hoidslam/synth/static_geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "hoidslam/core/error.h"

namespace hoidslam::synth {
namespace {

// The 12 triangles of a box's surface over its corners (numbered as BoxCorner does), counter-clockwise seen from
// outside, two a face.
constexpr std::array<std::array<int, 3>, 12> kBoxTriangles = {{
    {0, 4, 6}, {0, 6, 2},  // -x
    {1, 3, 7}, {1, 7, 5},  // +x
    {0, 1, 5}, {0, 5, 4},  // -y
    {2, 6, 7}, {2, 7, 3},  // +y
    {0, 2, 3}, {0, 3, 1},  // -z
    {4, 5, 7}, {4, 7, 6},  // +z
}};

bool SameParts(const std::vector<Box>& a, const std::vector<Box>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const Box& x, const Box& y) {
    return x.T_wb.matrix() == y.T_wb.matrix() && x.half_size == y.half_size;
  });
}

}  // namespace

void AppendBoxMesh(const Box& box, io::TriangleMesh& mesh) {
  const int first = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < 8; ++i) mesh.vertices.push_back((box.T_wb * BoxCorner(box.half_size, i)).cast<float>());
  for (const auto& [a, b, c] : kBoxTriangles) mesh.triangles.emplace_back(first + a, first + b, first + c);
}

void VoxelCells::AddBox(const Box& box) {
  const Eigen::Matrix3d R_bw = box.T_wb.linear().transpose();
  const Eigen::Vector3d& centre = box.T_wb.translation();
  const Eigen::Vector3d& half = box.half_size;
  // The cells whose centre lies in the box's world-aligned bounding box: (index + 0.5) size within it.
  const Eigen::Vector3d reach = box.T_wb.linear().cwiseAbs() * half;
  const Eigen::Vector3d low = ((centre - reach) / size_).array() - 0.5;
  const Eigen::Vector3d high = ((centre + reach) / size_).array() - 0.5;
  std::array<std::int64_t, 3> first{}, last{};
  for (int axis = 0; axis < 3; ++axis) {
    constexpr double kLimit = static_cast<double>(io::kCellReach - 1);
    if (!(std::abs(low[axis]) < kLimit && std::abs(high[axis]) < kLimit)) {  // also NaN
      throw core::InputError(fmt::format("a box at ({:.3f}, {:.3f}, {:.3f}) m lies beyond the {:.0f} m from the "
                                         "origin that the moving volume's grid covers",
                                         centre.x(), centre.y(), centre.z(),
                                         static_cast<double>(io::kCellReach) * size_));
    }
    first[axis] = static_cast<std::int64_t>(std::ceil(low[axis]));
    last[axis] = static_cast<std::int64_t>(std::floor(high[axis]));
  }
  // Cell centres in box coordinates, stepping along world z within a column.
  const Eigen::Vector3d step = R_bw.col(2) * size_;
  for (std::int64_t i = first[0]; i <= last[0]; ++i) {
    for (std::int64_t j = first[1]; j <= last[1]; ++j) {
      Eigen::Vector3d p = R_bw * (Eigen::Vector3d(static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5,
                                                  static_cast<double>(first[2]) + 0.5) * size_ - centre);
      for (std::int64_t k = first[2]; k <= last[2]; ++k, p += step) {
        if (std::abs(p.x()) <= half.x() && std::abs(p.y()) <= half.y() && std::abs(p.z()) <= half.z()) {
          cells_.insert(io::PackCell(i, j, k));
        }
      }
    }
  }
}

io::VoxelCentres VoxelCells::Centres() const {
  std::vector<std::uint64_t> keys(cells_.begin(), cells_.end());
  std::sort(keys.begin(), keys.end());
  io::VoxelCentres voxels{size_, {}};
  voxels.centres.reserve(keys.size());
  for (const std::uint64_t key : keys) {
    Eigen::Vector3d centre;
    for (int axis = 0; axis < 3; ++axis) centre[axis] = (static_cast<double>(io::UnpackCell(key, axis)) + 0.5) * size_;
    voxels.centres.push_back(centre.cast<float>());
  }
  return voxels;
}

SequenceGeometry::SequenceGeometry(SceneSnapshot first) : first_(std::move(first)), cells_(kMovingVolumeVoxelSize) {
  for (std::size_t i = 0; i < first_.instances.size(); ++i) index_.emplace(first_.instances[i].id, i);
  Add(first_);
}

void SequenceGeometry::Add(const SceneSnapshot& snapshot) {
  // The instances that differ from `first_` (or are missing in it) have moved; they and the people occupy
  // moving space in this frame.
  std::vector<int> moved;
  std::vector<const SceneInstance*> occupying;
  std::vector<bool> present(first_.instances.size(), false);
  for (const SceneInstance& instance : snapshot.instances) {
    const auto it = index_.find(instance.id);
    if (it != index_.end()) present[it->second] = true;
    const bool same = it != index_.end() && SameParts(first_.instances[it->second].parts, instance.parts);
    if (!same) moved.push_back(instance.id);
    if (!same || instance.label == "person") occupying.push_back(&instance);
  }
  for (std::size_t i = 0; i < present.size(); ++i) {
    if (!present[i]) moved.push_back(first_.instances[i].id);
  }

  // Covered here: parts not covered just before (a person standing still is covered once), and the parts in
  // `first_` of an instance found to move, which it occupied at that frame. The cells go straight into the one set
  // under the lock: a frame's few boxes take far less time than rendering it, so threads seldom wait.
  const std::lock_guard lock(mutex_);
  for (const int id : moved) {
    const auto it = index_.find(id);
    if (!moved_.insert(id).second || it == index_.end()) continue;
    for (const Box& box : first_.instances[it->second].parts) cells_.AddBox(box);
  }
  for (const SceneInstance* instance : occupying) {
    std::vector<Box>& covered = covered_[instance->id];
    if (SameParts(covered, instance->parts)) continue;
    covered = instance->parts;
    for (const Box& box : instance->parts) cells_.AddBox(box);
  }
}

io::TriangleMesh SequenceGeometry::StaticMesh() const {
  const std::lock_guard lock(mutex_);
  io::TriangleMesh mesh;
  for (const SceneInstance& instance : first_.instances) {
    if (instance.label == "person" || moved_.contains(instance.id)) continue;
    for (const Box& box : instance.parts) AppendBoxMesh(box, mesh);
  }
  return mesh;
}

io::VoxelCentres SequenceGeometry::MovingVolume() const {
  const std::lock_guard lock(mutex_);
  return cells_.Centres();
}

}  // namespace hoidslam::synth
