#include "hoidslam/dense/static_world.h"

#include <future>

namespace hoidslam::dense {

StaticWorld::StaticWorld(const DenseOptions& options, const core::CameraIntrinsics& camera)
    : options_(options), camera_(camera), volume_(options, camera), occupancy_(options.occupancy) {}

void StaticWorld::Fuse(const cv::Mat& bgr, const cv::Mat& depth, const core::Pose& T_wc) {
  // Should the volume throw, the future's end still waits for the rays: nothing outlives this call.
  std::future<void> rays = std::async(std::launch::async, [&] { occupancy_.InsertDepth(depth, camera_, T_wc, options_.max_depth); });
  volume_.Integrate(bgr, depth, T_wc);
  rays.get();
}

bool StaticWorld::SeenThrough(const Eigen::Vector3d& p_w) const {
  return occupancy_.At(p_w) == CellState::kFree;
}

PointFilter StaticWorld::LeaveOut() const {
  if (options_.keep_seen_through) return {};
  return [this](const Eigen::Vector3d& p_w) { return SeenThrough(p_w); };
}

MeshCounts StaticWorld::WriteMesh(const std::filesystem::path& path) const { return volume_.WriteMesh(path, LeaveOut()); }

std::size_t StaticWorld::WriteCloud(const std::filesystem::path& path) const {
  return volume_.WriteCloud(path, LeaveOut());
}

}  // namespace hoidslam::dense
