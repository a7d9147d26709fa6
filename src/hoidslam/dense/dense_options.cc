#include "hoidslam/dense/dense_options.h"

#include <unistd.h>

#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/core/option_checks.h"

namespace hoidslam::dense {

namespace {

constexpr double kMiB = 1024.0 * 1024.0;

std::size_t HalfThePhysicalMemoryMb() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 4096;  // unknown: assume a small machine
  return static_cast<std::size_t>(static_cast<double>(pages) * static_cast<double>(page_size) / kMiB / 2.0);
}

}  // namespace

void OccupancyOptions::Check() const {
  core::CheckInRange(resolution, 0.005, 1.0, "--occupancy-resolution");
  if (!(band_low < band_high)) {
    throw core::InputError::ForParameter(
        "--occupancy-band", fmt::format("the band's low edge must lie below its high edge, got {}:{}", band_low, band_high));
  }
  if (pixel_step < 1) throw core::InputError::ForParameter("occupancy pixel step", fmt::format("must be >= 1, got {}", pixel_step));
}

void SetOccupancyBand(std::string_view text, OccupancyOptions& options) {
  const std::size_t colon = text.find(':');
  double low = 0.0, high = 0.0;
  std::size_t low_end = 0, high_end = 0;
  try {
    if (colon == std::string_view::npos) throw std::invalid_argument("no colon");
    const std::string low_text(text.substr(0, colon)), high_text(text.substr(colon + 1));
    low = std::stod(low_text, &low_end);
    high = std::stod(high_text, &high_end);
    if (low_end != low_text.size() || high_end != high_text.size()) throw std::invalid_argument("trailing text");
  } catch (const std::exception&) {
    throw core::InputError::ForParameter(
        "--occupancy-band", fmt::format("takes LOW:HIGH in metres above the floor, e.g. 0.1:1.8, got '{}'", text));
  }
  options.band_low = low;
  options.band_high = high;
}

double VolumeBytesPerSquareMetre(double voxel_size) {
  // Measured on walking_xyz (docs/dense.md): 90 blocks of 16³ voxels per m² of surface at 1 cm with a four-voxel
  // truncation, 2.3 times one layer of blocks (surfaces cross blocks at a slant, the truncation band is thick).
  constexpr double kBlockLayers = 2.5;
  const double block_edge = kVolumeBlockVoxels * voxel_size;
  return kBlockLayers / (block_edge * block_edge) * static_cast<double>(kVolumeBlockBytes);
}

std::size_t DenseOptions::MemoryLimitMb() const {
  return memory_limit_mb > 0 ? memory_limit_mb : HalfThePhysicalMemoryMb();
}

void DenseOptions::Check() const {
  core::CheckPositive(voxel_size, "--dense-voxel");
  if (!(truncation >= 2.0 * voxel_size)) {
    throw core::InputError::ForParameter(
        "--dense-truncation",
        fmt::format("must be at least two voxels ({} m at --dense-voxel {}), got {}", 2.0 * voxel_size, voxel_size,
                    truncation));
  }
  core::CheckPositive(min_depth, "--dense-min-depth");
  if (!(min_depth < max_depth)) {
    throw core::InputError::ForParameter(
        "--dense-max-depth", fmt::format("must lie beyond --dense-min-depth {}, got {}", min_depth, max_depth));
  }
  // The keyframes' depth is kept in half-millimetres of 16 bits until the build (dense_mapper.h).
  if (max_depth > kMaxDepthLimit) {
    throw core::InputError::ForParameter(
        "--dense-max-depth", fmt::format("must be at most {} m, beyond what an RGB-D sensor measures, got {}",
                                         kMaxDepthLimit, max_depth));
  }
  if (!(depth_extent >= 0.0)) {
    throw core::InputError::ForParameter("--dense-depth-extent", fmt::format("must be >= 0 m, got {}", depth_extent));
  }
  if (!(box_margin >= 0.0)) {
    throw core::InputError::ForParameter("--dense-box-margin", fmt::format("must be >= 0, got {}", box_margin));
  }
  if (mask_margin < 0) {
    throw core::InputError::ForParameter("--dense-mask-margin", fmt::format("must be >= 0, got {}", mask_margin));
  }
  core::CheckPositive(depth_edge, "dense depth edge");
  const double room_mb = kReferenceRoomSurface * VolumeBytesPerSquareMetre(voxel_size) / kMiB;
  const std::size_t limit = MemoryLimitMb();
  if (room_mb > static_cast<double>(limit)) {
    throw core::InputError::ForParameter(
        "--dense-voxel",
        fmt::format("a volume of {} m voxels takes about {:.0f} MiB for a room of {:.0f} m² of surface, more than the "
                    "{} MiB it may use (--dense-memory-mb; default half of this machine's memory): use larger voxels",
                    voxel_size, room_mb, kReferenceRoomSurface, limit));
  }
  occupancy.Check();
}

}  // namespace hoidslam::dense
