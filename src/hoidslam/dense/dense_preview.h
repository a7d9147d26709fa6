#pragma once
// A coarse dense map that grows while the run goes, for the live viewer. Each keyframe, once the mapper's thread
// has prepared it, is fused at the pose tracking gave it when it was made into a volume of coarse voxels, in a
// thread of its own; every interval the volume's mesh is drawn out, made small (MeshForDisplay) and handed to
// `show`. The final map is still built after the run from the final poses (DenseMapper::Build): loop closing and
// the final adjustment move keyframes, and Open3D cannot take a view back out of a volume.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include <opencv2/core/mat.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/dense/dense_options.h"
#include "hoidslam/io/ply_file.h"

namespace hoidslam::dense {

struct PreviewOptions {
  // m: 4 cm voxels hold a 64th of the voxels of 1 cm, and a room's preview mesh a 16th of the triangles.
  double voxel_size = 0.04;
  double interval_s = 1.0;              // how often the mesh is drawn out and shown, while keyframes come
  std::size_t max_triangles = 100'000;  // of each mesh shown
  // Keyframes waiting to be fused, at most: past that the oldest is dropped, so a preview that falls behind costs
  // a hole in the preview, never memory or the run's time.
  std::size_t max_waiting = 8;

  // Throws InputError naming the parameter.
  void Check() const;
};

class DensePreview {
 public:
  // `options`' depth limits and `camera` (without distortion) are the mapper's; `show` is called from the preview's
  // thread. Throws InputError when `preview` fails Check().
  DensePreview(const DenseOptions& options, const PreviewOptions& preview, const core::CameraIntrinsics& camera,
               std::function<void(io::TriangleMesh)> show);
  ~DensePreview();  // stops the thread (what waits is dropped); `show` is not called once it has returned
  DensePreview(const DensePreview&) = delete;
  DensePreview& operator=(const DensePreview&) = delete;

  // A prepared keyframe: colour CV_8UC3 (BGR) and depth CV_32FC1 with 0 where nothing is to be fused
  // (FusibleDepth), the camera at T_wc. Only queued: the fusion happens in the preview's thread.
  void Add(cv::Mat bgr, cv::Mat depth, const core::Pose& T_wc);

  // Keyframes fused so far.
  std::size_t Fused() const;

 private:
  struct View {
    cv::Mat bgr, depth;
    core::Pose T_wc;
  };
  void Work();

  DenseOptions options_;  // the preview volume's: the mapper's with the preview's voxels
  PreviewOptions preview_;
  core::CameraIntrinsics camera_;
  std::function<void(io::TriangleMesh)> show_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<View> waiting_;
  bool stopping_ = false;
  std::size_t fused_ = 0;
  std::thread thread_;
};

}  // namespace hoidslam::dense
