#include "hoidslam/report/page_json.h"

#include <bit>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hoidslam/report/html_report.h"
#include "hoidslam/version.h"

namespace hoidslam::report {
namespace {

static_assert(std::endian::native == std::endian::little, "the page reads the arrays as little-endian");

template <typename T>
std::string Base64Of(const std::vector<T>& values) {
  return Base64Encode(std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
}

}  // namespace

nlohmann::json PoseJson(const core::Pose& pose) {
  nlohmann::json values = nlohmann::json::array();
  const Eigen::Matrix4d m = pose.matrix();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) values.push_back(Rounded(m(r, c), c == 3 ? 1e4 : 1e6));
  }
  return values;
}

nlohmann::json HelloJson(std::string_view sequence, std::size_t total_frames, const core::CameraIntrinsics& camera,
                         bool controllable) {
  return {{"version", HOIDSLAM_VERSION},
          {"sequence", sequence},
          {"total_frames", total_frames},
          {"camera",
           {{"fx", camera.fx},
            {"fy", camera.fy},
            {"cx", camera.cx},
            {"cy", camera.cy},
            {"width", camera.width},
            {"height", camera.height}}},
          {"controllable", controllable}};
}

nlohmann::json KeyframeJson(std::uint64_t id, std::uint32_t map, const core::Pose& T_wc) {
  return {{"id", id}, {"map", map}, {"T_wc", PoseJson(T_wc)}};
}

nlohmann::json MapCountsJson(std::uint32_t map, std::size_t points, std::size_t keyframes) {
  return {{"id", map}, {"points", points}, {"keyframes", keyframes}};
}

void PointsJson::Add(std::uint64_t id, std::uint32_t map, const Eigen::Vector3d& position, const cv::Vec3b& bgr) {
  ids_.push_back(id);
  maps_.push_back(map);
  for (int k = 0; k < 3; ++k) xyz_.push_back(Rounded(position[k], 1e4));
  for (int k = 2; k >= 0; --k) rgb_.push_back(bgr[k]);
}

nlohmann::json PointsJson::ToJson() && {
  return {{"ids", std::move(ids_)}, {"map", std::move(maps_)}, {"xyz", std::move(xyz_)}, {"rgb", std::move(rgb_)}};
}

nlohmann::json DenseMeshJson(const io::TriangleMesh& mesh) {
  static_assert(sizeof(Eigen::Vector3f) == 12 && sizeof(Eigen::Vector3i) == 12 && sizeof(cv::Vec3b) == 3,
                "the arrays are sent as they lie in memory");
  return {{"vertices", mesh.vertices.size()},
          {"triangles", mesh.triangles.size()},
          {"positions", Base64Of(mesh.vertices)},
          {"rgb", Base64Of(mesh.rgb)},
          {"indices", Base64Of(mesh.triangles)}};
}

}  // namespace hoidslam::report
