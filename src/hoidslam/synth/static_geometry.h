#pragma once
// The ground truth of a synthetic sequence's static world, for judging dense maps (a TSDF mesh, an occupancy map)
// that should hold the office without its people: the exact surfaces of what stays put, and the space that
// people and moved objects occupied at some frame.
//
// An instance is static over a sequence when it is not a person and its parts (poses and half sizes) are the
// same in the snapshot of every frame; an object someone picks up is not static, not even while it rests.

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "hoidslam/io/ply_file.h"
#include "hoidslam/synth/scene.h"

namespace hoidslam::synth {

// Edge of the cells of a sequence's moving volume, metres.
inline constexpr double kMovingVolumeVoxelSize = 0.02;

// Appends the surface of `box`: its 8 corners and 12 triangles, counter-clockwise seen from outside.
void AppendBoxMesh(const Box& box, io::TriangleMesh& mesh);

// Cells of the grid of edge `size` aligned to its multiples: cell (i, j, k) has its centre at
// ((i + 0.5) size, (j + 0.5) size, (k + 0.5) size). Cells are kept within about 20 km of the origin
// (2^20 cells each way).
class VoxelCells {
 public:
  explicit VoxelCells(double size) : size_(size) {}

  // Adds the cells whose centre lies inside `box` (on its surface counts as inside). Throws core::InputError
  // for a box beyond the grid's reach.
  void AddBox(const Box& box);

  // Every cell's centre once, sorted by (i, j, k).
  io::VoxelCentres Centres() const;

 private:
  double size_;
  std::unordered_set<std::uint64_t> cells_;  // (i, j, k) packed 21 bits each
};

// Gathers a sequence's static geometry and moving volume frame by frame. Add() may be called from several
// threads at once; the frames may come in any order, and adding one twice changes nothing.
class SequenceGeometry {
 public:
  // `first`: the snapshot of one of the sequence's frames (counted as added), which the others are compared with.
  explicit SequenceGeometry(SceneSnapshot first);

  void Add(const SceneSnapshot& snapshot);

  // Once every frame is added: the surfaces of the static instances' boxes, in the order of `first`.
  io::TriangleMesh StaticMesh() const;
  // Once every frame is added: the cells whose centre was inside a part of a person or of an instance that is
  // not static, at some frame.
  io::VoxelCentres MovingVolume() const;

 private:
  SceneSnapshot first_;
  std::unordered_map<int, std::size_t> index_;  // instance id -> index in first_.instances
  mutable std::mutex mutex_;                    // guards the members below
  std::unordered_set<int> moved_;                      // ids of the instances that are not static
  std::unordered_map<int, std::vector<Box>> covered_;  // the parts of each instance whose cells were added last
  VoxelCells cells_;
};

}  // namespace hoidslam::synth
