#include "hoidslam/dense/dense_summary.h"

#include <algorithm>

#include <fmt/format.h>

namespace hoidslam::dense {

namespace {

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

nlohmann::json DenseSummaryJson(const DenseSummary& summary, const DenseOptions& options) {
  nlohmann::json json = {
      {"written", summary.written},
      {"keyframes", summary.keyframes},
      {"keyframes_without_images", summary.keyframes_without_images},
      {"mesh",
       {{"vertices", summary.mesh.vertices},
        {"triangles", summary.mesh.triangles},
        {"area_m2", summary.mesh.area},
        {"seen_through_vertices", summary.mesh.left_out}}},
      {"cloud_points", summary.cloud_points},
      {"occupied_cells", summary.occupied_cells},
      {"floor_found", summary.floor_found},
      {"volume_blocks", summary.volume_blocks},
      {"volume_mb", summary.volume_megabytes},
      {"held_mb", summary.held_megabytes},
      {"median_fuse_ms", Median(summary.fuse_ms)},
      {"build_seconds", summary.seconds},
      {"options",
       {{"voxel_size", options.voxel_size},
        {"truncation", options.truncation},
        {"min_depth", options.min_depth},
        {"max_depth", options.max_depth},
        {"mask_margin", options.mask_margin},
        {"depth_extent", options.depth_extent},
        {"box_margin", options.box_margin},
        {"keep_seen_through", options.keep_seen_through},
        {"occupancy_resolution", options.occupancy.resolution},
        {"occupancy_band", {options.occupancy.band_low, options.occupancy.band_high}}}},
      {"people", nullptr},
  };
  if (summary.people) json["people"] = eval::PersonSurfaceJson(*summary.people, {});
  return json;
}

std::string FormatDenseSummary(const DenseSummary& summary, const DenseOptions& options) {
  if (!summary.written) {
    return fmt::format("dense: nothing the sensor model trusts in {} keyframes; no dense outputs", summary.keyframes);
  }
  std::string line = fmt::format(
      "dense: {} keyframes fused in {:.1f} s ({:.1f} ms a keyframe): mesh {} vertices, {:.1f} m² at {:g} m voxels; "
      "{} cloud points; occupancy {} occupied cells of {:g} m, {}",
      summary.keyframes, summary.seconds, Median(summary.fuse_ms), summary.mesh.vertices, summary.mesh.area,
      options.voxel_size, summary.cloud_points, summary.occupied_cells, options.occupancy.resolution,
      summary.floor_found ? "the 2D grid on the floor found" : "no floor in view: the 2D grid on the first camera's up");
  if (summary.mesh.left_out > 0) {
    line += fmt::format("; {} mesh vertices left out where later keyframes saw through", summary.mesh.left_out);
  }
  if (summary.people) {
    line += fmt::format("; people kept: {:.1f} % of the person pixels in {} boxes of the keyframes",
                        100.0 * summary.people->Share(), summary.people->boxes);
  }
  if (summary.keyframes_without_images > 0) {
    line += fmt::format("; {} keyframes of the loaded map have no images to fuse", summary.keyframes_without_images);
  }
  return line;
}

}  // namespace hoidslam::dense
