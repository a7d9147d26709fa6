#pragma once
// What `hoidslam run --dense` builds and how finely (docs/dense.md): a truncated signed distance volume of the
// static world fused from the keyframes' depth and colour, its mesh and dense cloud, and an occupancy map in 3D
// (OctoMap) and 2D (a grid over a height band, as ROS map_server and Nav2 read it).

#include <cstddef>
#include <string_view>

namespace hoidslam::dense {

// The 3D and 2D occupancy maps (occupancy.h).
struct OccupancyOptions {
  double resolution = 0.05;  // m: OctoMap's leaf size and the 2D grid's cell size (--occupancy-resolution)
  // The height band, m above the floor, whose occupied cells are obstacles in the 2D grid (--occupancy-band
  // LOW:HIGH): above the floor's own cells, up to what a robot of person height meets.
  double band_low = 0.1;
  double band_high = 1.8;
  // Every pixel_step-th pixel in x and in y casts a ray into the 3D map: at 4, 19,200 rays a 640×480 keyframe.
  int pixel_step = 4;

  // Throws InputError naming the parameter (--occupancy-resolution, --occupancy-band).
  void Check() const;
};

// Parses --occupancy-band LOW:HIGH (metres above the floor) into `options`; throws InputError naming the parameter.
void SetOccupancyBand(std::string_view text, OccupancyOptions& options);

struct DenseOptions {
  double voxel_size = 0.01;  // m, the volume's voxel edge (--dense-voxel)
  // m, how far in front of and behind a surface a depth measurement updates the volume (--dense-truncation); at
  // least two voxels, so that marching cubes finds the zero crossing.
  double truncation = 0.04;
  // The depth the sensor model trusts, m (--dense-min-depth, --dense-max-depth): beyond 3 m a Kinect-class
  // sensor's noise (core::KinectDepthSigma) exceeds 1.3 voxels of 1 cm, and the volume grows with the square of
  // the range. Deeper depth is not fused; its rays still free the occupancy map's cells up to max_depth.
  double min_depth = 0.3;
  double max_depth = 3.0;
  // Pixels the dynamic regions grow by: the colour and depth images of a person's outline disagree by a pixel or
  // two, and a detector's box edge by more (--dense-mask-margin).
  int mask_margin = 4;
  // m, how far behind the foreground of a box hoidplus dropped the static map still leaves out
  // (--dense-depth-extent); never less than the filter's own HOIDplus.depthExtent (0.5 m). Tracking needs the
  // wall behind a person now and drops only half a metre; the map keeps a ghost for good and sees the wall from
  // other views. A person seen from above reaches farther: on walking_xyz, standing people's legs lay up to 0.9 m
  // behind their torsos.
  double depth_extent = 1.0;
  // Share of a hoidplus dynamic box's width and height the static map also leaves out beyond each side
  // (--dense-box-margin), never less than the filter's own HOIDplus.boxMargin (0.05); there only the foreground as
  // far as tracking's cut, not depth_extent: a head or an arm the box cut off lies at the person's depth, the
  // floor and the desks around them farther. A detector's box edge is off by some of the box (the synthetic
  // detector noise moves each edge by 5 % of the box, one standard deviation), and what it cuts off, fused once,
  // stays in the map: 0.15 is three of those deviations.
  double box_margin = 0.15;
  // A pixel whose 3×3 neighbourhood spans more than this share of its depth lies on a depth edge, where a sensor
  // mixes foreground and background ("flying pixels"): left out.
  double depth_edge = 0.05;
  // How much memory the volume may take, MiB; a voxel size whose volume for a room would exceed it is refused
  // before the run (--dense-memory-mb). 0: half of the machine's memory.
  std::size_t memory_limit_mb = 0;
  // A surface that later keyframes looked through was not static: a person the filter missed in a few keyframes,
  // a chair moved away. The volume keeps it (a view changes only the voxels near the surface it measures); the
  // occupancy map's rays cross its cells and call them free. By default the mesh and the cloud leave out what lies
  // in free cells; true keeps it (--dense-keep-seen-through).
  bool keep_seen_through = false;
  OccupancyOptions occupancy;

  // The surface a volume must hold to be worth building: an office of 5 × 5 × 3 m has 110 m².
  static constexpr double kReferenceRoomSurface = 100.0;
  static constexpr double kMaxDepthLimit = 30.0;  // m

  // memory_limit_mb, or half of the machine's memory when it is 0.
  std::size_t MemoryLimitMb() const;
  // Throws InputError naming the parameter: a voxel size <= 0, a truncation under two voxels, a depth range or
  // height band upside down, a volume for kReferenceRoomSurface that would not fit in MemoryLimitMb().
  void Check() const;
};

// The volume's blocks (tsdf_volume.h): cubes of this many voxels a side, allocated where surfaces are (Open3D's
// default). Blocks of 8³ hold 0.6 of the voxels and fuse one frame faster, but a room's build slower: every depth
// sample looks up the blocks around it in a hash map four times the size (docs/dense.md).
inline constexpr int kVolumeBlockVoxels = 16;
// Open3D's coloured voxel: signed distance and weight (floats), colour (three doubles) and its grid index (three
// ints, padded), 48 bytes (checked against Open3D's own in tsdf_volume.cc).
inline constexpr std::size_t kVolumeVoxelBytes = 48;
inline constexpr std::size_t kVolumeBlockBytes =
    std::size_t{kVolumeBlockVoxels} * kVolumeBlockVoxels * kVolumeBlockVoxels * kVolumeVoxelBytes;

// What a volume of `voxel_size` voxels takes per m² of surface it holds, bytes (an estimate from measurements).
double VolumeBytesPerSquareMetre(double voxel_size);

}  // namespace hoidslam::dense
