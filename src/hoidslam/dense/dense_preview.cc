#include "hoidslam/dense/dense_preview.h"

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <exception>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "hoidslam/core/error.h"
#include "hoidslam/dense/display_mesh.h"
#include "hoidslam/dense/tsdf_volume.h"

namespace hoidslam::dense {
namespace {

using Clock = std::chrono::steady_clock;

// The preview's truncation in voxels: DenseOptions' default ratio (4 cm at 1 cm).
constexpr double kTruncationVoxels = 4.0;

}  // namespace

void PreviewOptions::Check() const {
  if (!(voxel_size > 0.0)) {
    throw core::InputError::ForParameter("preview voxel_size", fmt::format("must be > 0 m, got {}", voxel_size));
  }
  if (!(interval_s > 0.0)) {
    throw core::InputError::ForParameter("preview interval_s", fmt::format("must be > 0 s, got {}", interval_s));
  }
  if (max_triangles == 0) throw core::InputError::ForParameter("preview max_triangles", "must be > 0");
  if (max_waiting == 0) throw core::InputError::ForParameter("preview max_waiting", "must be > 0");
}

DensePreview::DensePreview(const DenseOptions& options, const PreviewOptions& preview,
                           const core::CameraIntrinsics& camera, std::function<void(io::TriangleMesh)> show)
    : options_(options), preview_(preview), camera_(camera), show_(std::move(show)) {
  preview_.Check();
  options_.voxel_size = preview_.voxel_size;
  options_.truncation = kTruncationVoxels * preview_.voxel_size;
  thread_ = std::thread([this] { Work(); });
}

DensePreview::~DensePreview() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void DensePreview::Add(cv::Mat bgr, cv::Mat depth, const core::Pose& T_wc) {
  {
    const std::lock_guard lock(mutex_);
    waiting_.push_back({std::move(bgr), std::move(depth), T_wc});
    if (waiting_.size() > preview_.max_waiting) waiting_.pop_front();
  }
  wake_.notify_one();
}

std::size_t DensePreview::Fused() const {
  const std::lock_guard lock(mutex_);
  return fused_;
}

void DensePreview::Work() {
  // The preview is worth less than any frame tracked: on a machine whose cores are all busy, the scheduler gives
  // them to tracking first (Linux sets a thread's niceness by its id).
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19);
  UseOneOpenMPThread();
  try {
    TsdfVolume volume(options_, camera_);
    const auto interval =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(preview_.interval_s));
    bool changed = false;     // keyframes were fused since the mesh was last shown
    Clock::time_point due{};  // then: when it is shown next, an interval after the first of them
    while (true) {
      std::optional<View> view;
      {
        std::unique_lock lock(mutex_);
        const auto ready = [this] { return stopping_ || !waiting_.empty(); };
        if (changed) {
          wake_.wait_until(lock, due, ready);
        } else {
          wake_.wait(lock, ready);
        }
        if (stopping_) return;
        if (!waiting_.empty()) {
          view = std::move(waiting_.front());
          waiting_.pop_front();
        }
      }
      if (view) {
        volume.Integrate(view->bgr, view->depth, view->T_wc);
        if (!changed) due = Clock::now() + interval;
        changed = true;
        const std::lock_guard lock(mutex_);
        ++fused_;
      }
      if (changed && Clock::now() >= due) {
        changed = false;
        show_(MeshForDisplay(volume.Mesh(), preview_.max_triangles));
      }
    }
  } catch (const std::exception& e) {
    // The run goes on without it: the final dense map is built after the run all the same.
    spdlog::warn("the dense map's live preview stopped: {}", e.what());
  }
}

}  // namespace hoidslam::dense
