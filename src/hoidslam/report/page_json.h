#pragma once
// The viewer page's messages (docs/viewer.md, "The protocol between the run and the page") as JSON: the live
// viewer sends them, the run report embeds them for the same page to show. Numbers are rounded to what the page can
// show, so that the JSON stays short (a map of 20,000 points is sent whole to each new page, and written into each
// report).

#include <cmath>
#include <cstdint>
#include <cstddef>
#include <string_view>

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <opencv2/core/matx.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/io/ply_file.h"

namespace hoidslam::report {

// `value` rounded to 1 / `per_unit` (10: a tenth).
inline double Rounded(double value, double per_unit) { return std::round(value * per_unit) / per_unit; }

// A pose as the page takes it: the 4×4 matrix, row-major, rotation to 1e-6 and translation to 0.1 mm.
nlohmann::json PoseJson(const core::Pose& pose);

// The `hello` message: this hoidslam's version, the sequence, its frames (0: not known) and the camera whose field
// of view the page's frusta show; `controllable`: whether the page's playback controls apply.
nlohmann::json HelloJson(std::string_view sequence, std::size_t total_frames, const core::CameraIntrinsics& camera,
                         bool controllable);

// One of a map message's `keyframes`.
nlohmann::json KeyframeJson(std::uint64_t id, std::uint32_t map, const core::Pose& T_wc);

// One of a map message's `maps`: a map and its counts.
nlohmann::json MapCountsJson(std::uint32_t map, std::size_t points, std::size_t keyframes);

// A dense mesh as the page takes it (the live `dense` message, the report's embedded `dense`): its counts, and its
// arrays as base64 of their little-endian bytes — 20 characters a vertex and 16 a triangle, where numbers as JSON
// text take several times that: `positions` (float32 x y z a vertex, metres, world frame), `rgb` (uint8 red green
// blue a vertex; "" for a mesh without colours) and `indices` (uint32, three a triangle).
nlohmann::json DenseMeshJson(const io::TriangleMesh& mesh);

// A map message's `points` (ids, map, xyz to 0.1 mm, rgb), one point at a time.
class PointsJson {
 public:
  void Add(std::uint64_t id, std::uint32_t map, const Eigen::Vector3d& position, const cv::Vec3b& bgr);
  nlohmann::json ToJson() &&;

 private:
  nlohmann::json ids_ = nlohmann::json::array(), maps_ = nlohmann::json::array(), xyz_ = nlohmann::json::array(),
                 rgb_ = nlohmann::json::array();
};

}  // namespace hoidslam::report
