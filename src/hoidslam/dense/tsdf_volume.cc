#include "hoidslam/dense/tsdf_volume.h"

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <open3d/camera/PinholeCameraIntrinsic.h>
#include <open3d/geometry/Image.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/RGBDImage.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/io/PointCloudIO.h>
#include <open3d/io/TriangleMeshIO.h>
#include <open3d/pipelines/integration/ScalableTSDFVolume.h>
#include <open3d/pipelines/integration/UniformTSDFVolume.h>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/dense/open3d_mesh.h"
#include "hoidslam/io/atomic_file.h"

// The OpenMP runtime Debian's Open3D is built with, libgomp (declared here rather than by an omp.h: the clang
// builds of the sanitizers have none of GCC's).
extern "C" void omp_set_num_threads(int threads);

namespace hoidslam::dense {

namespace integration = open3d::pipelines::integration;

static_assert(sizeof(open3d::geometry::TSDFVoxel) == kVolumeVoxelBytes,
              "the memory the volume reports and the estimate that refuses too fine a voxel count Open3D's voxel");

namespace {

// An Open3D image holding a copy of `mat` (continuous rows of `channels` × `bytes` per pixel).
open3d::geometry::Image ImageOf(const cv::Mat& mat, int channels, int bytes) {
  open3d::geometry::Image image;
  image.Prepare(mat.cols, mat.rows, channels, bytes);
  const std::size_t row = static_cast<std::size_t>(mat.cols) * channels * bytes;
  for (int r = 0; r < mat.rows; ++r) std::memcpy(image.data_.data() + r * row, mat.ptr(r), row);
  return image;
}

// Writes with Open3D's writer into a temporary sibling, then renames it into place.
template <typename Write>
void WriteAtomically(const std::filesystem::path& path, Write write) {
  const std::filesystem::path temporary = io::TemporarySibling(path);
  std::error_code error;
  if (!write(temporary.string())) {
    std::filesystem::remove(temporary, error);
    throw core::InputError::InFile(path, "cannot write (does the folder exist and is it writable?)");
  }
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw core::InputError::InFile(path, "cannot move the finished file into place: " + error.message());
  }
}

}  // namespace

void UseOneOpenMPThread() {
  // Open3D 0.16 sizes its loops by the machine's cores unless OMP_NUM_THREADS or OMP_DYNAMIC is in the environment,
  // and then by the calling thread's OpenMP setting (utility::EstimateMaxThreads). OMP_DYNAMIC changes nothing for
  // libgomp, which read its variables when it loaded; set once, and a user's own setting is kept.
  static std::once_flag environment;
  std::call_once(environment, [] { setenv("OMP_DYNAMIC", "false", /*overwrite=*/0); });
  omp_set_num_threads(1);
}

struct TsdfVolume::Impl {
  Impl(const DenseOptions& options, const core::CameraIntrinsics& camera)
      : volume(options.voxel_size, options.truncation, integration::TSDFVolumeColorType::RGB8, kVolumeBlockVoxels),
        intrinsic(camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy),
        size(camera.width, camera.height),
        max_depth(options.max_depth) {}

  std::shared_ptr<open3d::geometry::PointCloud> Cloud() const {
    return const_cast<integration::ScalableTSDFVolume&>(volume).ExtractPointCloud();
  }
  std::shared_ptr<open3d::geometry::TriangleMesh> Mesh() const {
    return const_cast<integration::ScalableTSDFVolume&>(volume).ExtractTriangleMesh();
  }

  integration::ScalableTSDFVolume volume;
  open3d::camera::PinholeCameraIntrinsic intrinsic;
  cv::Size size;
  double max_depth;
};

TsdfVolume::TsdfVolume(const DenseOptions& options, const core::CameraIntrinsics& camera)
    : impl_(std::make_unique<Impl>(options, camera)) {}

TsdfVolume::~TsdfVolume() = default;

void TsdfVolume::Integrate(const cv::Mat& bgr, const cv::Mat& depth, const core::Pose& T_wc) {
  if (bgr.type() != CV_8UC3 || depth.type() != CV_32FC1 || bgr.size() != impl_->size || depth.size() != impl_->size) {
    throw std::invalid_argument("TsdfVolume::Integrate: colour must be CV_8UC3 and depth CV_32FC1, both the camera's size");
  }
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::Mat trusted;  // deeper than max_depth: for the occupancy map's free space only
  cv::threshold(depth, trusted, impl_->max_depth, 0.0, cv::THRESH_TOZERO_INV);
  // Built directly rather than by RGBDImage::CreateFromColorAndDepth, which would turn the colour into intensity
  // (and the coloured volume then refuse it) and the depth into metres once more.
  const open3d::geometry::RGBDImage view(ImageOf(rgb, 3, 1), ImageOf(trusted, 1, 4));
  impl_->volume.Integrate(view, impl_->intrinsic, T_wc.inverse().matrix());
}

std::size_t TsdfVolume::Blocks() const { return impl_->volume.volume_units_.size(); }

std::size_t TsdfVolume::MemoryBytes() const {
  return Blocks() * kVolumeBlockBytes;
}

MeshCounts TsdfVolume::WriteMesh(const std::filesystem::path& path, const PointFilter& leave_out) const {
  const std::shared_ptr<open3d::geometry::TriangleMesh> mesh = impl_->Mesh();
  std::size_t left_out = 0;
  if (leave_out) {
    std::vector<bool> out(mesh->vertices_.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] = leave_out(mesh->vertices_[i]);
      left_out += out[i] ? 1 : 0;
    }
    if (left_out > 0) mesh->RemoveVerticesByMask(out);
  }
  if (mesh->vertices_.empty()) return {0, 0, 0.0, left_out};  // Open3D neither writes nor reads an empty mesh
  mesh->ComputeVertexNormals();
  WriteAtomically(path, [&mesh](const std::string& file) {
    return open3d::io::WriteTriangleMesh(file, *mesh, /*write_ascii=*/false, /*compressed=*/false);
  });
  return {mesh->vertices_.size(), mesh->triangles_.size(), mesh->GetSurfaceArea(), left_out};
}

io::TriangleMesh TsdfVolume::Mesh() const {
  return FromOpen3d(*impl_->Mesh());
}

std::size_t TsdfVolume::WriteCloud(const std::filesystem::path& path, const PointFilter& leave_out) const {
  std::shared_ptr<open3d::geometry::PointCloud> cloud = impl_->Cloud();
  if (leave_out) {
    std::vector<std::size_t> kept;
    kept.reserve(cloud->points_.size());
    for (std::size_t i = 0; i < cloud->points_.size(); ++i) {
      if (!leave_out(cloud->points_[i])) kept.push_back(i);
    }
    if (kept.size() < cloud->points_.size()) cloud = cloud->SelectByIndex(kept);
  }
  if (cloud->points_.empty()) return 0;  // as for the mesh
  WriteAtomically(path, [&cloud](const std::string& file) {
    return open3d::io::WritePointCloud(file, *cloud, {open3d::io::WritePointCloudOption::IsAscii::Binary});
  });
  return cloud->points_.size();
}

OrientedPoints TsdfVolume::SamplePoints(std::size_t step) const {
  const std::shared_ptr<open3d::geometry::PointCloud> cloud = impl_->Cloud();
  OrientedPoints sample;
  for (std::size_t i = 0; i < cloud->points_.size(); i += std::max<std::size_t>(step, 1)) {
    sample.points.push_back(cloud->points_[i]);
    sample.normals.push_back(cloud->HasNormals() ? cloud->normals_[i] : Eigen::Vector3d::Zero());
  }
  return sample;
}

}  // namespace hoidslam::dense
