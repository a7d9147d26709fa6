#include "hoidslam/dense/dense_preview.h"

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "hoidslam/dense/test_views.h"

namespace hoidslam::dense {
namespace {

using namespace std::chrono_literals;

// What `show` was handed, from the preview's thread.
struct Shown {
  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<io::TriangleMesh> meshes;

  std::function<void(io::TriangleMesh)> Show() {
    return [this](io::TriangleMesh mesh) {
      {
        const std::lock_guard lock(mutex);
        meshes.push_back(std::move(mesh));
      }
      arrived.notify_all();
    };
  }
  // The newest mesh once `count` have come; an empty mesh after 30 s without.
  io::TriangleMesh WaitFor(std::size_t count) {
    std::unique_lock lock(mutex);
    if (!arrived.wait_for(lock, 30s, [&] { return meshes.size() >= count; })) return {};
    return meshes.back();
  }
};

// What the small camera sees of a wall 1.5 m in front of it, everywhere fusible.
struct WallView {
  core::CameraIntrinsics camera = test_views::SmallCamera();
  cv::Mat bgr = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar(40, 120, 220));
  cv::Mat depth = cv::Mat(camera.height, camera.width, CV_32FC1, cv::Scalar(1.5F));
};

core::Pose Moved(double x, double z) {
  core::Pose T_wc = core::Pose::Identity();
  T_wc.translation() = Eigen::Vector3d(x, 0.0, z);
  return T_wc;
}

TEST(DensePreview, FusesEachViewAtItsPoseAndShowsTheMeshInItsOwnThread) {
  const WallView view;
  Shown shown;
  PreviewOptions options;
  options.interval_s = 0.05;
  options.max_triangles = 200;
  DensePreview preview(test_views::CoarseOptions(), options, view.camera, shown.Show());
  // The camera 0.2 m forward of the world's origin: the wall stands at z = 1.7 m in the world.
  for (const double x : {0.0, 0.1, 0.2}) preview.Add(view.bgr.clone(), view.depth.clone(), Moved(x, 0.2));
  const io::TriangleMesh mesh = shown.WaitFor(1);
  ASSERT_FALSE(mesh.triangles.empty()) << "nothing shown in 30 s";
  EXPECT_LE(mesh.triangles.size(), options.max_triangles);
  ASSERT_EQ(mesh.rgb.size(), mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    ASSERT_NEAR(mesh.vertices[i].z(), 1.7F, options.voxel_size) << "vertex " << i;
    EXPECT_NEAR(mesh.rgb[i][0], 220, 3) << "red, from the BGR image";
  }
}

TEST(DensePreview, AddNeverWaitsForTheThreadAndKeepsOnlyTheNewestViewsWhenItFallsBehind) {
  const WallView view;
  PreviewOptions options;
  options.interval_s = 0.01;
  options.max_waiting = 8;
  std::mutex mutex;
  std::condition_variable changed;
  bool showing = false, released = false;
  // The first mesh shown holds the preview's thread until released: a preview that falls far behind.
  DensePreview preview(test_views::CoarseOptions(), options, view.camera, [&](io::TriangleMesh) {
    std::unique_lock lock(mutex);
    showing = true;
    changed.notify_all();
    changed.wait(lock, [&] { return released; });
  });
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(preview.Fused(), 0U);
  EXPECT_FALSE(showing) << "no mesh of an empty volume";
  preview.Add(view.bgr.clone(), view.depth.clone(), Moved(0.0, 0.0));
  {
    std::unique_lock lock(mutex);
    ASSERT_TRUE(changed.wait_for(lock, 30s, [&] { return showing; }));
  }
  for (int i = 1; i <= 50; ++i) preview.Add(view.bgr.clone(), view.depth.clone(), Moved(0.01 * i, 0.0));
  {
    const std::lock_guard lock(mutex);
    released = true;
  }
  changed.notify_all();
  // The first view and the 8 newest; the 42 before them were dropped.
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (preview.Fused() < 9 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(10ms);
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(preview.Fused(), 9U);
}

TEST(DensePreview, RefusesBadOptions) {
  const WallView view;
  for (const auto& [name, change] : std::vector<std::pair<std::string, std::function<void(PreviewOptions&)>>>{
           {"voxel_size", [](PreviewOptions& o) { o.voxel_size = 0.0; }},
           {"interval_s", [](PreviewOptions& o) { o.interval_s = -1.0; }},
           {"max_triangles", [](PreviewOptions& o) { o.max_triangles = 0; }},
           {"max_waiting", [](PreviewOptions& o) { o.max_waiting = 0; }}}) {
    PreviewOptions options;
    change(options);
    EXPECT_THROW(DensePreview(test_views::CoarseOptions(), options, view.camera, [](io::TriangleMesh) {}),
                 core::InputError)
        << name;
  }
}

}  // namespace
}  // namespace hoidslam::dense
