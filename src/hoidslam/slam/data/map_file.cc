#include "hoidslam/slam/data/map_file.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include <fmt/format.h>

#include "hoidslam/bow/vocabulary_file.h"
#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/files.h"
#include "hoidslam/slam/data/keyframe_database.h"

namespace hoidslam::slam {
namespace {

constexpr std::array<std::uint8_t, 8> kMagic = {'H', 'O', 'I', 'D', 'M', 'A', 'P', 0x1a};
constexpr std::size_t kIdentityBytes = 16;
constexpr std::uint32_t kNoParent = 0xffffffffU;
constexpr std::size_t kKeypointBytes = 5 * 4 + 4 + 4 + 3 + 32;
// The least bytes a keyframe, a loop edge, a point and an observation take: what a count is checked against.
constexpr std::size_t kMinKeyFrameBytes = 8 + 8 + 12 * 8 + 4 + 4;
constexpr std::size_t kLoopEdgeBytes = 8;
constexpr std::size_t kMinPointBytes = 3 * 8 + 3 + 4 + 4 + 8;
constexpr std::size_t kObservationBytes = 8;
// Bounds that keep a camera's numbers sane (ORB pyramids have 8 levels or so).
constexpr std::uint32_t kMaxImageSide = 1U << 16;
constexpr std::uint32_t kMaxPyramidLevels = 64;
// A pose's rotation is taken for one when R^T R is the identity to this much.
constexpr double kRotationTolerance = 1e-6;

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}
  template <typename Unsigned>
  void Put(Unsigned value) {
    for (std::size_t i = 0; i < sizeof(Unsigned); ++i) out_.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
  }
  void F32(float value) { Put(std::bit_cast<std::uint32_t>(value)); }
  void F64(double value) { Put(std::bit_cast<std::uint64_t>(value)); }
  void Raw(const std::uint8_t* data, std::size_t n) { out_.insert(out_.end(), data, data + n); }

 private:
  std::vector<std::uint8_t>& out_;
};

// Reads fields in order, each checked against the bytes left; every failure names the source.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, const std::string& source) : bytes_(bytes), source_(source) {}

  core::InputError Fail(const std::string& what) const { return core::InputError::InFile(source_, what); }

  void Need(std::size_t n, const char* what) const {
    if (n > bytes_.size() - offset_) {
      throw Fail(fmt::format("truncated: {} ends {} bytes early", what, n - (bytes_.size() - offset_)));
    }
  }
  template <typename Unsigned>
  Unsigned Get(const char* what) {
    Need(sizeof(Unsigned), what);
    Unsigned value = 0;
    for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
      value |= static_cast<Unsigned>(static_cast<Unsigned>(bytes_[offset_ + i]) << (8 * i));
    }
    offset_ += sizeof(Unsigned);
    return value;
  }
  float F32(const char* what) { return std::bit_cast<float>(Get<std::uint32_t>(what)); }
  double F64(const char* what) { return std::bit_cast<double>(Get<std::uint64_t>(what)); }
  // A finite number.
  double Finite(const char* what) {
    const double value = F64(what);
    if (!std::isfinite(value)) throw Fail(fmt::format("{} is not finite", what));
    return value;
  }
  const std::uint8_t* Raw(std::size_t n, const char* what) {
    Need(n, what);
    const std::uint8_t* data = bytes_.data() + offset_;
    offset_ += n;
    return data;
  }
  // A count of items that take at least `item_bytes` each: more than the bytes left can hold is truncation.
  std::uint32_t Count(std::size_t item_bytes, const char* what) {
    const auto count = Get<std::uint32_t>(what);
    if (std::uint64_t{count} * item_bytes > bytes_.size() - offset_) {
      throw Fail(fmt::format("truncated: {} {} take at least {} bytes, {} are left", count, what,
                             std::uint64_t{count} * item_bytes, bytes_.size() - offset_));
    }
    return count;
  }
  std::size_t left() const { return bytes_.size() - offset_; }

 private:
  std::span<const std::uint8_t> bytes_;
  const std::string& source_;
  std::size_t offset_ = 0;
};

void PutPose(Writer& w, const core::Pose& pose) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) w.F64(pose.linear()(r, c));
  }
  for (int r = 0; r < 3; ++r) w.F64(pose.translation()(r));
}

core::Pose GetPose(Reader& r, std::size_t keyframe) {
  core::Pose pose = core::Pose::Identity();
  for (int row = 0; row < 3; ++row) {
    for (int c = 0; c < 3; ++c) pose.linear()(row, c) = r.Finite("a keyframe's pose");
  }
  for (int row = 0; row < 3; ++row) pose.translation()(row) = r.Finite("a keyframe's pose");
  const Eigen::Matrix3d R = pose.linear();
  if (!(R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), kRotationTolerance) || R.determinant() <= 0.0) {
    throw r.Fail(fmt::format("keyframe {}: the pose's rotation is not a rotation", keyframe));
  }
  return pose;
}

MapFileCamera GetCamera(Reader& r) {
  MapFileCamera camera;
  core::CameraIntrinsics& k = camera.intrinsics;
  for (double* value : {&k.fx, &k.fy, &k.cx, &k.cy, &k.k1, &k.k2, &k.p1, &k.p2, &k.k3}) {
    *value = r.Finite("the camera");
  }
  const auto width = r.Get<std::uint32_t>("the camera");
  const auto height = r.Get<std::uint32_t>("the camera");
  camera.bf = r.Finite("the camera");
  camera.close_depth = r.Finite("the camera");
  const auto levels = r.Get<std::uint32_t>("the camera");
  camera.scale_factor = r.F32("the camera");
  if (width == 0 || height == 0 || width > kMaxImageSide || height > kMaxImageSide || !(k.fx > 0.0) ||
      !(k.fy > 0.0)) {
    throw r.Fail(fmt::format("a camera of {}×{} pixels with focal lengths {} and {}", width, height, k.fx, k.fy));
  }
  if (levels < 1 || levels > kMaxPyramidLevels || !(camera.scale_factor >= 1.0F && std::isfinite(camera.scale_factor))) {
    throw r.Fail(fmt::format("an ORB pyramid of {} levels and scale factor {}", levels, camera.scale_factor));
  }
  k.width = static_cast<int>(width);
  k.height = static_cast<int>(height);
  camera.pyramid_levels = static_cast<int>(levels);
  return camera;
}

MapFileKeyFrame GetKeyFrame(Reader& r, const MapFileCamera& camera, std::size_t index) {
  MapFileKeyFrame keyframe;
  keyframe.frame_id = r.Get<std::uint64_t>("a keyframe");
  keyframe.timestamp = r.Finite("a keyframe's timestamp");
  keyframe.T_cw = GetPose(r, index);
  const auto parent = r.Get<std::uint32_t>("a keyframe");
  if (parent != kNoParent) keyframe.parent = parent;
  const std::uint32_t n = r.Count(kKeypointBytes, "keypoints");
  keyframe.keypoints.reserve(n);
  keyframe.descriptors.create(static_cast<int>(n), bow::kDescriptorBytes, CV_8UC1);
  keyframe.depth.reserve(n);
  keyframe.colors.reserve(n);
  const auto fail = [&](std::uint32_t i, const std::string& what) {
    return r.Fail(fmt::format("keyframe {}, keypoint {}: {}", index, i, what));
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    cv::KeyPoint kp;
    kp.pt.x = r.F32("a keypoint");
    kp.pt.y = r.F32("a keypoint");
    kp.size = r.F32("a keypoint");
    kp.angle = r.F32("a keypoint");
    kp.response = r.F32("a keypoint");
    kp.octave = static_cast<std::int32_t>(r.Get<std::uint32_t>("a keypoint"));
    const float depth = r.F32("a keypoint");
    const std::uint8_t* bgr = r.Raw(3, "a keypoint");
    std::memcpy(keyframe.descriptors.ptr(static_cast<int>(i)), r.Raw(bow::kDescriptorBytes, "a keypoint"),
                bow::kDescriptorBytes);
    if (!(kp.pt.x >= 0.0F && kp.pt.x < static_cast<float>(camera.intrinsics.width) && kp.pt.y >= 0.0F &&
          kp.pt.y < static_cast<float>(camera.intrinsics.height))) {
      throw fail(i, fmt::format("({}, {}) is outside the {}×{} image", kp.pt.x, kp.pt.y, camera.intrinsics.width,
                                camera.intrinsics.height));
    }
    if (!(std::isfinite(kp.size) && kp.size > 0.0F && std::isfinite(kp.angle) && std::isfinite(kp.response))) {
      throw fail(i, "a size, angle or response that is not a finite number (or a size <= 0)");
    }
    if (kp.octave < 0 || kp.octave >= camera.pyramid_levels) {
      throw fail(i, fmt::format("octave {} is outside the pyramid's {} levels", kp.octave, camera.pyramid_levels));
    }
    if (!(std::isfinite(depth) && depth >= 0.0F)) throw fail(i, fmt::format("depth {} (0 for none)", depth));
    keyframe.keypoints.push_back(kp);
    keyframe.depth.push_back(depth);
    keyframe.colors.emplace_back(bgr[0], bgr[1], bgr[2]);
  }
  return keyframe;
}

// Every keyframe's parent chain must end, at a keyframe without a parent; the first keyframe has none.
void CheckTree(const std::vector<MapFileKeyFrame>& keyframes, Reader& r) {
  const std::size_t n = keyframes.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t parent = keyframes[i].parent;
    if (parent >= 0 && static_cast<std::uint64_t>(parent) >= n) {
      throw r.Fail(fmt::format("keyframe {}: parent {} of {} keyframes", i, parent, n));
    }
  }
  if (n > 0 && keyframes[0].parent >= 0) throw r.Fail("the first keyframe has a parent");
  // 0: not visited, 1: on the chain being followed, 2: its chain ends.
  std::vector<std::uint8_t> state(n, 0);
  std::vector<std::size_t> chain;
  for (std::size_t start = 0; start < n; ++start) {
    chain.clear();
    std::int64_t at = static_cast<std::int64_t>(start);
    while (at >= 0 && state[static_cast<std::size_t>(at)] == 0) {
      state[static_cast<std::size_t>(at)] = 1;
      chain.push_back(static_cast<std::size_t>(at));
      at = keyframes[static_cast<std::size_t>(at)].parent;
    }
    if (at >= 0 && state[static_cast<std::size_t>(at)] == 1) {
      throw r.Fail(fmt::format("keyframe {}: the spanning tree has a cycle", at));
    }
    for (const std::size_t k : chain) state[k] = 2;
  }
}

MapFilePoint GetPoint(Reader& r, const std::vector<MapFileKeyFrame>& keyframes,
                      std::vector<std::vector<std::uint8_t>>& used, std::size_t index) {
  MapFilePoint point;
  for (int c = 0; c < 3; ++c) point.position(c) = r.Finite("a point's position");
  const std::uint8_t* bgr = r.Raw(3, "a point");
  point.color = cv::Vec3b(bgr[0], bgr[1], bgr[2]);
  point.reference = r.Get<std::uint32_t>("a point");
  const std::uint32_t n = r.Count(kObservationBytes, "observations");
  const auto fail = [&](const std::string& what) { return r.Fail(fmt::format("point {}: {}", index, what)); };
  if (n == 0) throw fail("no observation");
  if (point.reference >= n) throw fail(fmt::format("reference observation {} of {}", point.reference, n));
  point.observations.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    MapFilePoint::Observation& o = point.observations[i];
    o.keyframe = r.Get<std::uint32_t>("an observation");
    o.keypoint = r.Get<std::uint32_t>("an observation");
    if (o.keyframe >= keyframes.size()) throw fail(fmt::format("keyframe {} of {}", o.keyframe, keyframes.size()));
    if (i > 0 && o.keyframe <= point.observations[i - 1].keyframe) {
      throw fail("observations not in increasing keyframe order");
    }
    const std::size_t keypoints = keyframes[o.keyframe].keypoints.size();
    if (o.keypoint >= keypoints) {
      throw fail(fmt::format("keypoint {} of keyframe {}'s {}", o.keypoint, o.keyframe, keypoints));
    }
    std::uint8_t& slot = used[o.keyframe][o.keypoint];
    if (slot != 0) throw fail(fmt::format("keypoint {} of keyframe {} already has a point", o.keypoint, o.keyframe));
    slot = 1;
  }
  return point;
}

std::string Describe(const MapFileCamera& c) {
  const core::CameraIntrinsics& k = c.intrinsics;
  return fmt::format("{}×{} px, fx {} fy {} cx {} cy {}, distortion {} {} {} {} {}, bf {}, close depth {} m, "
                     "{} pyramid levels × {}",
                     k.width, k.height, k.fx, k.fy, k.cx, k.cy, k.k1, k.k2, k.p1, k.p2, k.k3, c.bf, c.close_depth,
                     c.pyramid_levels, c.scale_factor);
}

}  // namespace

MapFileCamera MapFileCamera::Of(const Sensor& sensor) {
  const auto& scale = sensor.pyramid.scale;
  return {sensor.intrinsics, sensor.camera.bf, sensor.close_depth, sensor.pyramid.levels(),
          scale.size() > 1 ? scale[1] : 1.0F};
}

MapFileContent ContentOf(const Map& map, MapId map_id, const Sensor& sensor, const bow::Vocabulary& vocabulary) {
  MapFileContent content;
  content.camera = MapFileCamera::Of(sensor);
  content.vocabulary = vocabulary.identity();
  const std::vector<KeyFrame*> keyframes = map.KeyFrames(map_id);
  std::unordered_map<const KeyFrame*, std::uint32_t> index_of;
  for (const KeyFrame* keyframe : keyframes) index_of.emplace(keyframe, static_cast<std::uint32_t>(index_of.size()));
  for (const KeyFrame* keyframe : keyframes) {
    const KeypointSet& kps = keyframe->keypoints();
    MapFileKeyFrame& saved = content.keyframes.emplace_back();
    saved.frame_id = keyframe->frame_id();
    saved.timestamp = keyframe->timestamp();
    saved.T_cw = keyframe->T_cw();
    if (keyframe->parent() != nullptr) saved.parent = index_of.at(keyframe->parent());
    saved.keypoints = kps.keypoints();
    saved.descriptors = kps.descriptors();
    for (int i = 0; i < kps.size(); ++i) {
      saved.depth.push_back(kps.depth(i));
      saved.colors.push_back(kps.color(i));
    }
    for (const KeyFrame* other : keyframe->loop_edges()) {
      if (other->id() > keyframe->id()) content.loop_edges.emplace_back(index_of.at(keyframe), index_of.at(other));
    }
  }
  std::sort(content.loop_edges.begin(), content.loop_edges.end());
  for (const MapPoint* point : map.MapPoints(map_id)) {
    MapFilePoint& saved = content.points.emplace_back();
    saved.position = point->position();
    saved.color = point->color();
    for (const MapPoint::Observation& o : point->observations()) {
      if (o.keyframe == point->reference_keyframe()) saved.reference = static_cast<std::uint32_t>(saved.observations.size());
      saved.observations.push_back({index_of.at(o.keyframe), static_cast<std::uint32_t>(o.index)});
    }
  }
  return content;
}

std::vector<std::uint8_t> EncodeMap(const MapFileContent& content) {
  std::vector<std::uint8_t> out(kMagic.begin(), kMagic.end());
  Writer w(out);
  w.Put<std::uint32_t>(kMapFormatVersion);
  const core::CameraIntrinsics& k = content.camera.intrinsics;
  for (const double value : {k.fx, k.fy, k.cx, k.cy, k.k1, k.k2, k.p1, k.p2, k.k3}) w.F64(value);
  w.Put(static_cast<std::uint32_t>(k.width));
  w.Put(static_cast<std::uint32_t>(k.height));
  w.F64(content.camera.bf);
  w.F64(content.camera.close_depth);
  w.Put(static_cast<std::uint32_t>(content.camera.pyramid_levels));
  w.F32(content.camera.scale_factor);
  std::array<std::uint8_t, kIdentityBytes> identity{};
  std::copy_n(content.vocabulary.begin(), std::min(content.vocabulary.size(), kIdentityBytes), identity.begin());
  w.Raw(identity.data(), identity.size());

  w.Put(static_cast<std::uint32_t>(content.keyframes.size()));
  for (const MapFileKeyFrame& keyframe : content.keyframes) {
    w.Put(keyframe.frame_id);
    w.F64(keyframe.timestamp);
    PutPose(w, keyframe.T_cw);
    w.Put(keyframe.parent < 0 ? kNoParent : static_cast<std::uint32_t>(keyframe.parent));
    w.Put(static_cast<std::uint32_t>(keyframe.keypoints.size()));
    for (std::size_t i = 0; i < keyframe.keypoints.size(); ++i) {
      const cv::KeyPoint& kp = keyframe.keypoints[i];
      for (const float value : {kp.pt.x, kp.pt.y, kp.size, kp.angle, kp.response}) w.F32(value);
      w.Put(static_cast<std::uint32_t>(kp.octave));
      w.F32(keyframe.depth[i]);
      w.Raw(keyframe.colors[i].val, 3);
      w.Raw(keyframe.descriptors.ptr(static_cast<int>(i)), bow::kDescriptorBytes);
    }
  }
  w.Put(static_cast<std::uint32_t>(content.loop_edges.size()));
  for (const auto& [a, b] : content.loop_edges) {
    w.Put(a);
    w.Put(b);
  }
  w.Put(static_cast<std::uint32_t>(content.points.size()));
  for (const MapFilePoint& point : content.points) {
    for (int c = 0; c < 3; ++c) w.F64(point.position(c));
    w.Raw(point.color.val, 3);
    w.Put(point.reference);
    w.Put(static_cast<std::uint32_t>(point.observations.size()));
    for (const MapFilePoint::Observation& o : point.observations) {
      w.Put(o.keyframe);
      w.Put(o.keypoint);
    }
  }
  w.Put(bow::Fnv1a64(out));
  return out;
}

MapFileContent DecodeMap(std::span<const std::uint8_t> bytes, const std::string& source) {
  Reader header(bytes, source);
  const std::size_t magic_bytes = std::min(bytes.size(), kMagic.size());
  if (!std::equal(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(magic_bytes), kMagic.begin())) {
    throw header.Fail("not a hoidslam map file (it does not begin with the magic bytes HOIDMAP\\x1a)");
  }
  header.Raw(kMagic.size(), "the magic");
  if (const auto version = header.Get<std::uint32_t>("the header"); version != kMapFormatVersion) {
    throw header.Fail(fmt::format("unsupported format version {} (this hoidslam reads version {})", version,
                                  kMapFormatVersion));
  }
  header.Need(bow::kChecksumBytes, "the checksum");
  const std::span<const std::uint8_t> payload = bytes.first(bytes.size() - bow::kChecksumBytes);
  if (const std::uint64_t stored = bow::StoredChecksum(bytes), computed = bow::Fnv1a64(payload); stored != computed) {
    throw header.Fail(fmt::format("truncated or corrupt: the checksum {:016x} does not match the content's {:016x}", stored,
                                  computed));
  }

  Reader r(payload, source);
  r.Raw(kMagic.size() + 4, "the header");
  MapFileContent content;
  content.camera = GetCamera(r);
  const std::uint8_t* identity = r.Raw(kIdentityBytes, "the vocabulary identity");
  content.vocabulary.assign(identity, identity + kIdentityBytes);

  const std::uint32_t keyframes = r.Count(kMinKeyFrameBytes, "keyframes");
  content.keyframes.reserve(keyframes);
  std::vector<std::vector<std::uint8_t>> used;  // per keyframe and keypoint: a point is on it
  for (std::uint32_t i = 0; i < keyframes; ++i) {
    content.keyframes.push_back(GetKeyFrame(r, content.camera, i));
    used.emplace_back(content.keyframes.back().keypoints.size(), 0);
  }
  CheckTree(content.keyframes, r);

  const std::uint32_t edges = r.Count(kLoopEdgeBytes, "loop edges");
  for (std::uint32_t i = 0; i < edges; ++i) {
    const auto a = r.Get<std::uint32_t>("a loop edge");
    const auto b = r.Get<std::uint32_t>("a loop edge");
    if (!(a < b && b < keyframes)) {
      throw r.Fail(fmt::format("loop edge {}: keyframes {} and {} (of {}) are not two in increasing order", i, a, b,
                               keyframes));
    }
    if (!content.loop_edges.empty() && content.loop_edges.back() >= std::pair(a, b)) {
      throw r.Fail(fmt::format("loop edge {}: edges not in increasing order", i));
    }
    content.loop_edges.emplace_back(a, b);
  }

  const std::uint32_t points = r.Count(kMinPointBytes, "points");
  content.points.reserve(points);
  for (std::uint32_t i = 0; i < points; ++i) content.points.push_back(GetPoint(r, content.keyframes, used, i));
  if (r.left() > 0) throw r.Fail(fmt::format("{} bytes past the end of the map", r.left()));
  return content;
}

void RebuildMap(const MapFileContent& content, const std::shared_ptr<const Sensor>& sensor,
                const bow::Vocabulary& vocabulary, Map& map) {
  std::vector<KeyFrame*> keyframes;
  keyframes.reserve(content.keyframes.size());
  for (const MapFileKeyFrame& saved : content.keyframes) {
    auto keypoints = std::make_shared<const KeypointSet>(sensor, saved.keypoints, saved.descriptors.clone(),
                                                         saved.depth, saved.colors);
    keyframes.push_back(map.CreateKeyFrame(saved.frame_id, saved.timestamp, std::move(keypoints), saved.T_cw));
  }
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const std::int64_t parent = content.keyframes[i].parent;
    if (parent >= 0) map.SetParent(keyframes[i], keyframes[static_cast<std::size_t>(parent)]);
  }
  for (const auto& [a, b] : content.loop_edges) map.AddLoopEdge(keyframes[a], keyframes[b]);
  for (const MapFilePoint& saved : content.points) {
    const MapFilePoint::Observation& reference = saved.observations[saved.reference];
    MapPoint* point = map.CreateMapPoint(saved.position, keyframes[reference.keyframe],
                                         static_cast<int>(reference.keypoint), saved.color);
    for (const MapFilePoint::Observation& o : saved.observations) {
      map.AddObservation(point, keyframes[o.keyframe], static_cast<int>(o.keypoint));
    }
    map.UpdatePoint(point);
  }
  for (KeyFrame* keyframe : keyframes) {
    map.UpdateConnections(keyframe);
    map.IndexKeyFrame(keyframe, DescribePlace(vocabulary, keyframe->keypoints()));
  }
}

void SaveMap(const Map& map, MapId map_id, const Sensor& sensor, const bow::Vocabulary& vocabulary,
             const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = EncodeMap(ContentOf(map, map_id, sensor, vocabulary));
  io::AtomicFile file(path);
  file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  file.Commit();
}

void LoadMap(const std::filesystem::path& path, const std::shared_ptr<const Sensor>& sensor,
             const bow::Vocabulary& vocabulary, Map& map) {
  const MapFileContent content = DecodeMap(io::ReadBinaryFile(path, "map file"), path.string());
  if (const MapFileCamera camera = MapFileCamera::Of(*sensor); !(content.camera == camera)) {
    throw core::InputError::InFile(path, fmt::format("the map was made with another camera ({}) than this run's ({})",
                                                     Describe(content.camera), Describe(camera)));
  }
  if (content.vocabulary != vocabulary.identity()) {
    throw core::InputError::InFile(path, fmt::format("the map was made with another vocabulary ({}) than this run's "
                                                     "({})",
                                                     content.vocabulary, vocabulary.identity()));
  }
  RebuildMap(content, sensor, vocabulary, map);
}

}  // namespace hoidslam::slam
