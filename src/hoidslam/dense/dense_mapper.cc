#include "hoidslam/dense/dense_mapper.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <optional>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "hoidslam/core/stopwatch.h"
#include "hoidslam/dense/floor.h"
#include "hoidslam/dense/fusible_depth.h"
#include "hoidslam/dense/occupancy.h"
#include "hoidslam/dense/static_world.h"
#include "hoidslam/io/ply_file.h"

namespace hoidslam::dense {

namespace {

constexpr double kDepthUnitsPerMetre = 2000.0;  // the kept depth's unit: half a millimetre, up to 32 m
constexpr int kJpegQuality = 95;
// Timestamps of the same frame are the same double; a keyframe is found within a microsecond all the same.
constexpr double kStampTolerance = 1e-6;
constexpr std::size_t kFloorSampleStep = 4;

// Depth (CV_32FC1, metres) as a 16-bit PNG in half-millimetres. Lossless and fast at level 1: on the 3,600-frame
// loop the keyframes held took 207 MB raw, and the build's peak memory is the volume's plus theirs. Depth beyond
// `far` is held as the largest value, 32.8 m: there only the ray's direction counts (OccupancyMap::InsertDepth cuts
// it at the depth trusted), and one value compresses to almost nothing — kept as measured, it doubled what was held.
void EncodeDepth(const cv::Mat& metres, std::vector<unsigned char>& png,
                 double far = std::numeric_limits<double>::infinity()) {
  cv::Mat units;
  metres.convertTo(units, CV_16U, kDepthUnitsPerMetre);
  if (std::isfinite(far)) units.setTo(std::numeric_limits<std::uint16_t>::max(), metres > far);
  cv::imencode(".png", units, png, {cv::IMWRITE_PNG_COMPRESSION, 1});
}

cv::Mat DecodeDepth(const std::vector<unsigned char>& png) {
  cv::Mat metres;
  cv::imdecode(png, cv::IMREAD_UNCHANGED).convertTo(metres, CV_32F, 1.0 / kDepthUnitsPerMetre);
  return metres;
}

}  // namespace

DenseMapper::DenseMapper(const DenseOptions& options, const core::CameraIntrinsics& camera)
    : options_(options), camera_(camera) {
  options_.Check();
  if (camera.HasDistortion()) {
    // The volume and the rays take a pinhole camera: a keyframe is undistorted onto the same intrinsics first.
    const cv::Matx33d K(camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0);
    const cv::Vec<double, 5> distortion(camera.k1, camera.k2, camera.p1, camera.p2, camera.k3);
    cv::initUndistortRectifyMap(K, distortion, cv::noArray(), K, cv::Size(camera.width, camera.height), CV_32FC1,
                                undistort_x_, undistort_y_);
    camera_.k1 = camera_.k2 = camera_.p1 = camera_.p2 = camera_.k3 = 0.0;
  }
  thread_ = std::thread([this] { Work(); });
}

DenseMapper::~DenseMapper() { Stop(); }

void DenseMapper::Stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DenseMapper::AddKeyFrame(const core::RgbdFrame& frame, const cv::Mat& left_out,
                              const std::optional<core::Pose>& T_wc, const std::vector<cv::Rect>& people) {
  // Copies: the caller's buffers (a program's own, through the API) may be reused once the frame is tracked.
  Pending pending{frame.timestamp, frame.rgb.clone(), frame.depth.clone(), left_out.clone(), T_wc, {}};
  const cv::Rect image(0, 0, frame.depth.cols, frame.depth.rows);
  for (const cv::Rect& box : people) {
    if (const cv::Rect inside = box & image; !inside.empty()) pending.people.push_back(inside);
  }
  {
    std::lock_guard lock(mutex_);
    if (stopping_) throw std::logic_error("DenseMapper::AddKeyFrame after Build");
    queue_.push_back(std::move(pending));
  }
  wake_.notify_one();
}

void DenseMapper::TakeKeyFrame(const pipeline::Session& session, const core::RgbdFrame& frame,
                               const pipeline::FrameOutcome& outcome, detect::Detector* detector) {
  if (!outcome.result.keyframe) return;
  std::optional<core::Pose> T_wc;
  if (outcome.result.T_cw) T_wc = outcome.result.T_cw->inverse();
  // The session's own detector runs in its thread whenever the mode judges boxes: then only the session asks it.
  const bool session_detects = session.options().exclusion.NeedsDetections() || session.options().exclusion.oracle;
  std::vector<core::Detection> detected;
  const std::vector<core::Detection>* boxes = &outcome.boxes.detections;
  if (boxes->empty() && !session_detects && detector != nullptr) {
    detected = detector->Detect(frame.timestamp, frame.rgb);
    boxes = &detected;
  }
  std::vector<cv::Rect> people;
  for (const core::Detection& detection : *boxes) {
    if (detection.label == session.options().exclusion.hoid.person_class) people.push_back(detection.box);
  }
  AddKeyFrame(frame, session.StaticMapExclusion(frame, {options_.depth_extent, options_.box_margin}), T_wc, people);
}

void DenseMapper::FollowPreview(const PreviewOptions& preview, std::function<void(io::TriangleMesh)> show) {
  const std::lock_guard lock(mutex_);
  if (stopping_) throw std::logic_error("DenseMapper::FollowPreview after Build");
  if (preview_) throw std::logic_error("DenseMapper::FollowPreview: already following");
  preview_ = std::make_unique<DensePreview>(options_, preview, camera_, std::move(show));
}

void DenseMapper::Work() {
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, and nothing left
    const Pending pending = std::move(queue_.front());
    queue_.pop_front();
    DensePreview* preview = pending.T_wc ? preview_.get() : nullptr;
    lock.unlock();
    const View view = Fusible(pending);
    // The preview gets copies of its own: OpenCV counts a shared image's owners in its library, where the thread
    // sanitizer cannot see it, and the last owner of a shared image could free it while the other thread reads.
    if (preview != nullptr) preview->Add(view.bgr.clone(), view.depth.clone(), *pending.T_wc);
    Prepared prepared = Compress(view);
    prepared.people = PersonCrops(pending);
    lock.lock();
    prepared_[pending.timestamp] = std::move(prepared);
  }
}

DenseMapper::View DenseMapper::Fusible(const Pending& pending) const {
  cv::Mat depth = FusibleDepth(pending.depth, pending.left_out, options_);
  cv::Mat bgr = pending.bgr;
  if (!undistort_x_.empty()) {
    // Depth by its nearest pixel: interpolating across an edge would invent surfaces between foreground and back.
    cv::remap(depth, depth, undistort_x_, undistort_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0.0);
    cv::remap(bgr, bgr, undistort_x_, undistort_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  }
  return {bgr, depth};
}

DenseMapper::Prepared DenseMapper::Compress(const View& view) const {
  Prepared prepared;
  EncodeDepth(view.depth, prepared.png, options_.max_depth);
  cv::imencode(".jpg", view.bgr, prepared.jpeg, {cv::IMWRITE_JPEG_QUALITY, kJpegQuality});
  return prepared;
}

std::vector<DenseMapper::PersonCrop> DenseMapper::PersonCrops(const Pending& pending) const {
  std::vector<PersonCrop> crops;
  if (pending.people.empty()) return crops;
  cv::Mat measured = pending.depth;
  if (!undistort_x_.empty()) {
    cv::remap(measured, measured, undistort_x_, undistort_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0.0);
  }
  for (const cv::Rect& box : pending.people) {
    PersonCrop& crop = crops.emplace_back(PersonCrop{box, {}});
    EncodeDepth(measured(box), crop.png);
  }
  return crops;
}

DenseSummary DenseMapper::Build(const core::Trajectory& keyframes, const std::filesystem::path& folder) {
  Stop();  // every keyframe handed over is prepared once the thread has ended
  preview_.reset();  // the final map replaces it, and its thread would take cores from the build
  // In a thread of the mapper's own, so that the caller's OpenMP setting stays as it was (UseOneOpenMPThread).
  DenseSummary summary;
  std::exception_ptr failure;
  std::thread builder([&] {
    UseOneOpenMPThread();
    try {
      const core::Stopwatch clock;
      summary = Fuse(keyframes, folder);
      // Once the volume is gone: the check reads the mesh back, and the build's peak memory is the volume's.
      if (summary.written) summary.people = CheckPeople(keyframes, folder);
      summary.seconds = clock.ElapsedSeconds();
    } catch (...) {
      failure = std::current_exception();
    }
  });
  builder.join();
  if (failure) std::rethrow_exception(failure);
  return summary;
}

DenseMapper::Prepared* DenseMapper::Held(double timestamp) {
  const auto found = prepared_.lower_bound(timestamp - kStampTolerance);
  if (found == prepared_.end() || found->first > timestamp + kStampTolerance) return nullptr;
  return &found->second;
}

DenseSummary DenseMapper::Fuse(const core::Trajectory& keyframes, const std::filesystem::path& folder) {
  DenseSummary summary;
  for (const auto& [stamp, prepared] : prepared_) {
    std::size_t bytes = prepared.png.size() + prepared.jpeg.size();
    for (const PersonCrop& crop : prepared.people) bytes += crop.png.size();
    summary.held_megabytes += static_cast<double>(bytes) / (1024.0 * 1024.0);
  }
  StaticWorld world(options_, camera_);
  std::optional<core::Pose> first_T_wc;
  for (const core::StampedPose& keyframe : keyframes) {
    Prepared* prepared = Held(keyframe.timestamp);
    if (prepared == nullptr) {
      ++summary.keyframes_without_images;
      continue;
    }
    const cv::Mat depth = DecodeDepth(prepared->png);
    const cv::Mat bgr = cv::imdecode(prepared->jpeg, cv::IMREAD_COLOR);
    const core::Stopwatch fuse;
    world.Fuse(bgr, depth, keyframe.T_wc);
    summary.fuse_ms.push_back(fuse.ElapsedMilliseconds());
    // Fused: only the person crops are read again (CheckPeople), and the build's peak comes at its end.
    std::vector<unsigned char>().swap(prepared->png);
    std::vector<unsigned char>().swap(prepared->jpeg);
    if (!first_T_wc) first_T_wc = keyframe.T_wc;
    ++summary.keyframes;
  }
  summary.volume_blocks = world.volume().Blocks();
  summary.volume_megabytes = static_cast<double>(world.volume().MemoryBytes()) / (1024.0 * 1024.0);
  if (summary.volume_blocks == 0) {
    // No keyframe, or nothing in any of them the sensor model trusts: no surface, so no file rather than empty ones.
    spdlog::warn("dense: nothing to fuse ({} keyframes with images); no dense outputs", summary.keyframes);
    return summary;
  }
  summary.mesh = world.WriteMesh(folder / "mesh.ply");
  if (summary.mesh.vertices == 0) {
    spdlog::warn("dense: later keyframes saw through all of the fused surface; no dense outputs");
    return summary;
  }
  summary.cloud_points = world.WriteCloud(folder / "cloud.ply");
  world.occupancy().WriteBinary(folder / "occupancy.bt");
  summary.occupied_cells = world.occupancy().OccupiedLeaves();
  const FloorFrame floor =
      EstimateFloor(world.volume().SamplePoints(kFloorSampleStep), first_T_wc.value_or(core::Pose::Identity()));
  summary.floor_found = floor.found;
  WriteOccupancyGrid(world.occupancy().Project(floor.T_fw), folder / "occupancy.pgm", folder / "occupancy.yaml");
  summary.written = true;
  return summary;
}

std::optional<eval::PersonSurface> DenseMapper::CheckPeople(const core::Trajectory& keyframes,
                                                            const std::filesystem::path& folder) {
  std::vector<eval::PersonView> views;
  for (const core::StampedPose& keyframe : keyframes) {
    const Prepared* prepared = Held(keyframe.timestamp);
    if (prepared == nullptr) continue;
    for (const PersonCrop& crop : prepared->people) views.push_back({keyframe.T_wc, crop.box, DecodeDepth(crop.png)});
  }
  if (views.empty()) return std::nullopt;
  return eval::MeasurePersonSurface(io::ReadPlyMesh(folder / "mesh.ply").vertices, options_.voxel_size, views,
                                    camera_);
}

}  // namespace hoidslam::dense
