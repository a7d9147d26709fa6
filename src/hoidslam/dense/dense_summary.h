#pragma once
// What a dense build made, for summary.json and the run's printout.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hoidslam/dense/dense_options.h"
#include "hoidslam/dense/tsdf_volume.h"
#include "hoidslam/eval/person_surface.h"

namespace hoidslam::dense {

// The files a dense build writes into the run's folder.
inline constexpr std::array<const char*, 5> kDenseOutputs = {"mesh.ply", "cloud.ply", "occupancy.bt", "occupancy.pgm",
                                                              "occupancy.yaml"};

struct DenseSummary {
  bool written = false;  // the outputs (kDenseOutputs); none when there was nothing to fuse
  std::size_t keyframes = 0;                 // fused
  std::size_t keyframes_without_images = 0;  // final keyframes never handed over (those of a loaded map)
  MeshCounts mesh;
  std::size_t cloud_points = 0;
  std::size_t occupied_cells = 0;  // leaves of the 3D occupancy map
  bool floor_found = false;
  std::size_t volume_blocks = 0;
  double volume_megabytes = 0.0;
  double held_megabytes = 0.0;  // the keyframes' prepared images, compressed, held until the build
  std::vector<double> fuse_ms;  // per keyframe: the volume's integration and the occupancy's rays, side by side
  // The people the map kept: in the fused keyframes' person boxes, the share of the person's pixels where the map
  // has surface (eval/person_surface.h); none when no keyframe had a person box.
  std::optional<eval::PersonSurface> people;
  double seconds = 0.0;         // the whole build: fusion, writing the outputs and the people check
};

// summary.json's "dense" object: the counts, the median fusion time a keyframe, and the options.
nlohmann::json DenseSummaryJson(const DenseSummary& summary, const DenseOptions& options);
// One line for the run's printout.
std::string FormatDenseSummary(const DenseSummary& summary, const DenseOptions& options);

}  // namespace hoidslam::dense
