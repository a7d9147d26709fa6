#pragma once
// The map file (.hmap), version 1: a map's good keyframes and points, and the camera and vocabulary they were made
// with; docs/slam.md ("Map reuse") describes its use. All numbers are little-endian:
//
//   header      8 bytes  magic "HOIDMAP\x1a"
//               u32      format version (1)
//   camera      f64 × 9  fx fy cx cy k1 k2 p1 p2 k3;  u32 × 2  width height;  f64 × 2  bf, close depth (metres)
//               u32      ORB pyramid levels;  f32  scale factor between levels
//   vocabulary  16 bytes bow::Vocabulary::identity(), hex digits
//   keyframes   u32 count, then per keyframe:
//               u64 frame id;  f64 timestamp;  f64 × 12  T_cw, the rotation row by row then the translation
//               u32 parent (a keyframe index, 0xffffffff: none)
//               u32 keypoint count, then per keypoint 63 bytes: f32 × 5  x y size angle response;  i32 octave;
//               f32 depth (metres, 0: none);  u8 × 3  colour (BGR);  32 bytes  descriptor
//   loop edges  u32 count, then per edge u32 × 2  keyframe indices a < b, pairs in increasing order
//   points      u32 count, then per point: f64 × 3  position;  u8 × 3  colour;  u32  reference observation (an
//               index into its observations);  u32 observation count (>= 1), then per observation
//               u32 × 2  keyframe index (increasing) and keypoint index
//   checksum    u64      FNV-1a 64 of every byte before it
//
// Keyframes and points are numbered by their place in the file: a loaded map's ids run from 0 without gaps and new
// ones continue after them. Covisibility, the points' normals, distance ranges and descriptors, and the keyframes'
// bags of words are not stored: loading recomputes them (Map::UpdateConnections, Map::UpdatePoint,
// bow::Vocabulary::Transform).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/slam/data/map.h"
#include "hoidslam/slam/data/sensor.h"

namespace hoidslam::slam {

inline constexpr std::uint32_t kMapFormatVersion = 1;

// What a map was made with; a map is only loaded with the same.
struct MapFileCamera {
  core::CameraIntrinsics intrinsics;
  double bf = 0.0;
  double close_depth = 0.0;
  int pyramid_levels = 0;
  float scale_factor = 0.0F;
  bool operator==(const MapFileCamera&) const = default;

  static MapFileCamera Of(const Sensor& sensor);
};

struct MapFileKeyFrame {
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  core::Pose T_cw = core::Pose::Identity();
  std::int64_t parent = -1;  // keyframe index, -1: none
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;  // CV_8U, one 32-byte row per keypoint
  std::vector<float> depth;
  std::vector<cv::Vec3b> colors;
};

struct MapFilePoint {
  struct Observation {
    std::uint32_t keyframe = 0;
    std::uint32_t keypoint = 0;
  };
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  cv::Vec3b color;
  std::uint32_t reference = 0;  // index into observations
  std::vector<Observation> observations;
};

// What a map file holds.
struct MapFileContent {
  MapFileCamera camera;
  std::string vocabulary;  // its identity
  std::vector<MapFileKeyFrame> keyframes;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> loop_edges;
  std::vector<MapFilePoint> points;
};

// The content of a map (its good keyframes and points; shared lock held).
MapFileContent ContentOf(const Map& map, MapId map_id, const Sensor& sensor, const bow::Vocabulary& vocabulary);

// The file's bytes.
std::vector<std::uint8_t> EncodeMap(const MapFileContent& content);

// Reads a file's bytes; `source` names it in errors. Every count is checked against the bytes left before anything
// is sized from it, and the checksum before any field is read past the header: throws core::InputError
// "<source>: <what is wrong>" for a file that is truncated, has trailing bytes, a wrong magic, an unsupported
// version, a checksum that does not match, or content that is not a map (a camera without size, a pose that is
// not rigid, a keypoint octave beyond the pyramid, an index out of range, a spanning tree with a cycle, two points
// on one keypoint, ...).
MapFileContent DecodeMap(std::span<const std::uint8_t> bytes, const std::string& source);

// Fills an empty map (exclusive lock held) with the content, its keypoints on `sensor` (which must match
// content.camera) and its keyframes' bags of words from `vocabulary`.
void RebuildMap(const MapFileContent& content, const std::shared_ptr<const Sensor>& sensor,
                const bow::Vocabulary& vocabulary, Map& map);

// Writes map `map_id` of the Atlas to a file, atomically (a temporary name, then a rename); throws core::InputError
// naming the file when it cannot.
void SaveMap(const Map& map, MapId map_id, const Sensor& sensor, const bow::Vocabulary& vocabulary,
             const std::filesystem::path& path);

// Reads a map file into an empty map (exclusive lock held). Throws core::InputError naming the file for a file that
// is missing or that DecodeMap rejects, and for a map made with another camera or vocabulary (saying what differs).
void LoadMap(const std::filesystem::path& path, const std::shared_ptr<const Sensor>& sensor,
             const bow::Vocabulary& vocabulary, Map& map);

}  // namespace hoidslam::slam
