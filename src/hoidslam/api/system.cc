// The public API's System: the caller's buffers wrapped as a frame (no copy where the layout allows), handed to
// the per-frame work `hoidslam run` does (pipeline::Session), the outcome translated into the API's plain types.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "hoidslam/hoidslam.h"
#include "hoidslam/version.h"
#include "hoidslam/api/convert.h"
#include "hoidslam/core/shipped_dir.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/dense/dense_mapper.h"
#include "hoidslam/dense/display_mesh.h"
#include "hoidslam/detect/make_detector.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/pipeline/session.h"
#include "hoidslam/pipeline/summary_json.h"
#include "hoidslam/report/html_report.h"
#include "hoidslam/viewer/viewer.h"

namespace hoidslam {
namespace {

// Throws InputError naming the value of a camera no program could have meant.
void CheckCamera(const Camera& camera) {
  const auto require = [](bool ok, const char* name, const std::string& what) {
    if (!ok) throw InputError::ForParameter(std::string("camera.") + name, what);
  };
  const auto positive = [&](double value, const char* name) {
    require(value > 0.0 && std::isfinite(value), name, fmt::format("must be > 0, got {}", value));
  };
  positive(camera.fx, "fx");
  positive(camera.fy, "fy");
  require(camera.width >= 1, "width", fmt::format("must be >= 1, got {}", camera.width));
  require(camera.height >= 1, "height", fmt::format("must be >= 1, got {}", camera.height));
  require(camera.cx >= 0.0 && camera.cx <= camera.width, "cx",
          fmt::format("must be in [0, width={}], got {}", camera.width, camera.cx));
  require(camera.cy >= 0.0 && camera.cy <= camera.height, "cy",
          fmt::format("must be in [0, height={}], got {}", camera.height, camera.cy));
  for (const double k : camera.distortion) {
    require(std::isfinite(k), "distortion", fmt::format("must be finite numbers, got {}", k));
  }
  positive(camera.depth_scale, "depth_scale");
  positive(camera.baseline, "baseline");
}

// The settings file's values (or the defaults), with the program's camera in place of the file's.
io::Settings SettingsOf(const Options& options) {
  io::Settings settings = options.settings.empty() ? io::Settings{} : io::LoadSettings(options.settings);
  if (!options.camera) return settings;
  const Camera& camera = *options.camera;
  CheckCamera(camera);
  const std::array<double, 5>& k = camera.distortion;
  settings.camera = {camera.fx, camera.fy, camera.cx, camera.cy, k[0], k[1], k[2], k[3], k[4],
                     camera.width, camera.height};
  settings.depth_map_factor = 1.0 / camera.depth_scale;
  settings.bf = camera.baseline * camera.fx;
  return settings;
}

pipeline::RunOptions ToRunOptions(const Options& options, const io::Settings& settings) {
  pipeline::RunOptions run = pipeline::RunOptions::FromSettings(settings);
  if (!options.filter.empty()) pipeline::SetFilterMode(options.filter, run.exclusion, "filter");
  if (run.exclusion.oracle) {
    throw InputError::ForParameter("filter", "oracle needs a synthetic sequence's moving masks; use hoidslam run");
  }
  run.keypoint_budget = pipeline::ParseKeypointBudget(options.keypoint_budget, "keypoint_budget");
  run.system.deterministic = options.deterministic;
  if (!options.vocabulary.empty()) run.system.vocabulary = options.vocabulary;
  run.realtime.enabled = options.realtime;
  run.snapshots = 0;
  if (options.localization && options.load_map.empty()) {
    throw InputError::ForParameter("localization", "needs a map to track against (load_map)");
  }
  run.system.load_map = options.load_map;
  run.system.localization = options.localization;
  if (options.detector == DetectorKind::kNone && run.exclusion.NeedsDetections()) {
    throw InputError::ForParameter(
        "detector", fmt::format("filter {} needs detections: give them per frame (DetectorKind::kGiven), a model "
                                "(kOnnx), or use filter none",
                                run.exclusion.ModeName()));
  }
  run.Check();
  return run;
}

std::unique_ptr<detect::Detector> MakeDetector(const Options& options) {
  if (options.detector != DetectorKind::kOnnx) {
    if (!options.model.empty()) {
      throw InputError::ForParameter("model", "a model is run only with the ONNX detector (DetectorKind::kOnnx)");
    }
    return nullptr;
  }
  if (options.model.empty()) throw InputError::ForParameter("model", "the ONNX detector needs a model file");
  detect::DetectorOptions detector;
  detector.kind = detect::DetectorKind::kOnnx;
  detector.onnx.model = options.model;
  return detect::MakeDetector(detector);
}

Matrix4 ToMatrix(const core::Pose& pose) {
  Matrix4 m{};
  const Eigen::Matrix4d matrix = pose.matrix();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m[static_cast<std::size_t>(4 * r + c)] = matrix(r, c);
  }
  return m;
}

std::vector<StampedPose> ToStampedPoses(const core::Trajectory& trajectory) {
  std::vector<StampedPose> poses;
  poses.reserve(trajectory.size());
  for (const core::StampedPose& p : trajectory) poses.push_back(api::ToStampedPose(p));
  return poses;
}

// The dynamic box that dropped a keypoint: the first that holds it, else the one whose edge is nearest.
int DroppingBox(const cv::KeyPoint& keypoint, const hoid::JudgedBoxes& boxes) {
  int nearest = -1;
  float nearest_distance = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < boxes.detections.size(); ++i) {
    if (!boxes.decisions[i].dynamic) continue;
    const cv::Rect2f& box = boxes.detections[i].box;
    const float dx = std::max({box.x - keypoint.pt.x, 0.0F, keypoint.pt.x - (box.x + box.width)});
    const float dy = std::max({box.y - keypoint.pt.y, 0.0F, keypoint.pt.y - (box.y + box.height)});
    const float distance = dx * dx + dy * dy;
    if (distance == 0.0F) return static_cast<int>(i);
    if (distance < nearest_distance) {
      nearest_distance = distance;
      nearest = static_cast<int>(i);
    }
  }
  return nearest;
}

FrameResult ToFrameResult(std::size_t index, double timestamp, const pipeline::FrameOutcome& outcome) {
  FrameResult r;
  r.index = index;
  r.timestamp = timestamp;
  const slam::TrackResult& track = outcome.result;
  switch (track.state) {
    case slam::TrackingState::kOk: r.state = TrackingState::kOk; break;
    case slam::TrackingState::kProvisional: r.state = TrackingState::kProvisional; break;
    case slam::TrackingState::kLost: r.state = TrackingState::kLost; break;
    case slam::TrackingState::kNotInitialized: r.state = TrackingState::kNotInitialized; break;
  }
  if (track.T_cw) r.T_wc = ToMatrix(track.T_cw->inverse());
  r.method = slam::ToString(track.method);
  if (track.failure != slam::TrackingFailure::kNone) r.failure = slam::ToString(track.failure);
  if (track.rejection != slam::PoseRejection::kNone) r.rejection = slam::ToString(track.rejection);
  r.withdrawn.assign(track.withdrawn.begin(), track.withdrawn.end());
  r.keyframe = track.keyframe;
  if (track.T_cw) r.map = track.map;
  r.boxes = api::ToJudgedBoxes(outcome.boxes);
  const std::vector<cv::KeyPoint>& keypoints = outcome.features.keypoints;
  r.keypoints.xy.resize(2 * keypoints.size());
  r.keypoints.kept.assign(outcome.keep.begin(), outcome.keep.end());
  r.keypoints.box.assign(keypoints.size(), -1);
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    r.keypoints.xy[2 * i] = keypoints[i].pt.x;
    r.keypoints.xy[2 * i + 1] = keypoints[i].pt.y;
    if (outcome.keep[i] == 0) r.keypoints.box[i] = DroppingBox(keypoints[i], outcome.boxes);
  }
  r.extracted = outcome.extracted;
  r.dropped = outcome.dropped;
  r.matched = track.matched;
  r.inliers = track.inliers;
  const pipeline::StageTimes& t = outcome.times;
  r.milliseconds = t.extract + t.detect + t.filter + t.track;
  return r;
}

}  // namespace

std::string Version() { return HOIDSLAM_VERSION; }

std::filesystem::path ShippedDir() { return core::ShippedDir(); }

std::filesystem::path SettingsForSequence(const std::filesystem::path& folder) {
  return io::ShippedSettingsForFolder(folder, core::ShippedDir() / "config");
}

std::string_view ToString(TrackingState state) {
  switch (state) {
    case TrackingState::kOk: return "ok";
    case TrackingState::kLost: return "lost";
    case TrackingState::kNotInitialized: return "not_initialized";
    case TrackingState::kProvisional: return "provisional";
  }
  return "unknown";
}

std::string_view FrameResult::DropReason(std::size_t i) const {
  if (i >= keypoints.size() || keypoints.kept[i] != 0) return {};
  const int b = keypoints.box[i];
  return b < 0 ? std::string_view("mask") : std::string_view(boxes[static_cast<std::size_t>(b)].reason);
}

class System::Impl {
 public:
  explicit Impl(const Options& options)
      : options_(options),
        settings_(SettingsOf(options)),
        run_options_(ToRunOptions(options, settings_)),
        detector_(MakeDetector(options)),
        session_(std::make_unique<pipeline::Session>(run_options_, detector_.get(), std::filesystem::path())),
        given_(options.detector == DetectorKind::kGiven),
        viewer_(MakeViewer(options, run_options_)),
        dense_(MakeDenseMapper(options, run_options_)) {
    if (viewer_) viewer_->FollowSession(*session_);
  }

  FrameResult Track(const ImageView& rgb, const ImageView& depth, double timestamp,
                    std::span<const Detection> detections, double depth_delay) {
    if (!std::isfinite(timestamp)) throw InputError::ForParameter("timestamp", "must be a finite number of seconds");
    if (!(std::abs(depth_delay) < 1.0)) {
      throw InputError::ForParameter("depth_delay",
                                     fmt::format("must be under a second either way, got {}: colour and depth this far "
                                                 "apart are of different moments (two cameras, or two clocks)",
                                                 depth_delay));
    }
    if (index_ > 0 && !(timestamp > last_timestamp_)) {
      throw InputError::ForParameter(
          "timestamp", fmt::format("frames must come in time order: {:.6f} s after {:.6f} s", timestamp,
                                   last_timestamp_));
    }
    if (!given_ && !detections.empty()) {
      throw InputError::ForParameter("detections", "the system runs its own detector: pass no detections");
    }
    const core::CameraIntrinsics& camera = run_options_.system.camera;
    core::RgbdFrame frame;
    frame.timestamp = timestamp;
    frame.depth_delay = depth_delay;
    frame.rgb = api::ColourMat(rgb, camera.width, camera.height, "rgb");
    frame.depth = api::DepthMetres(depth, camera.width, camera.height, settings_.depth_map_factor, "depth");
    std::optional<std::vector<core::Detection>> boxes;
    if (given_) boxes = api::ToCoreDetections(detections, "detections");
    if (index_ == 0) clock_.Restart();
    const pipeline::FrameOutcome& outcome = session_->Track(index_, frame, boxes ? &*boxes : nullptr);
    if (viewer_) {
      viewer::FrameSnapshot snapshot = viewer::SnapshotOf(index_, frame, outcome);
      snapshot.image = snapshot.image.clone();  // it may be the program's memory, which it reuses after Track
      viewer_->Publish(std::move(snapshot));
    }
    if (dense_) dense_->TakeKeyFrame(*session_, frame, outcome);
    last_timestamp_ = timestamp;
    frame_log_.push_back(outcome.entry.dump());
    return ToFrameResult(index_++, timestamp, outcome);
  }

  void Finish() {
    if (session_->finished()) return;
    seconds_ = index_ == 0 ? 0.0 : clock_.ElapsedMilliseconds() / 1000.0;
    session_->Finish();
    if (viewer_) {
      viewer_->FinalMapOf(*session_);
      viewer_->RunFinished();
    }
  }

  // Every file `hoidslam run` writes for a sequence without ground truth, each complete or absent.
  void Save(const std::filesystem::path& folder) {
    Finish();
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) throw InputError::InFile(folder, "cannot create the folder to save into: " + error.message());
    session_->WriteOutputs(folder);
    {
      io::AtomicFile log(folder / "frames.jsonl");
      for (const std::string& line : frame_log_) log.stream() << line << '\n';
      log.Commit();
    }
    pipeline::RunSummary& summary = session_->summary();
    summary.seconds = seconds_;
    nlohmann::json json = pipeline::RunSummaryJson(summary, "api", run_options_.exclusion.ModeName(),
                                                   detector_ ? detector_->Name() : (given_ ? "given" : "none"),
                                                   run_options_.realtime);
    std::optional<io::TriangleMesh> dense_display;  // the dense map as the report shows it
    if (dense_) {
      const dense::DenseSummary dense_summary = dense_->Build(session_->system().KeyFrameTrajectory(), folder);
      json["dense"] = dense::DenseSummaryJson(dense_summary, dense_->options());
      if (dense_summary.written) {
        dense_display = dense::ReadMeshForDisplay(folder / "mesh.ply", report::kReportDenseTriangles);
      }
    }
    json["provenance"] = pipeline::ProvenanceJson(
        {.version = HOIDSLAM_VERSION,
         .settings_file = options_.settings,
         .settings_chosen = options_.camera ? "camera" : options_.settings.empty() ? "default" : "given",
         .settings = settings_,
         .vocabulary = run_options_.system.vocabulary,
         .vocabulary_identity = summary.vocabulary_identity,
         .detector_source = detector_ ? detector_->Source() : std::filesystem::path()});
    {
      io::AtomicFile file(folder / "summary.json");
      file.stream() << json.dump(2) << '\n';
      file.Commit();
    }
    report::WriteRunReport(folder, {}, folder / "report.html", {}, std::move(dense_display));
  }

  void SaveMap(const std::filesystem::path& path) {
    io::CheckWritableFile(path, "path");
    Finish();
    session_->system().SaveMap(path);
  }

  // Back to no frames: the session and its maps are dropped (a loaded map is loaded again).
  void Reset() {
    Finish();  // the viewer stops reading the session before it goes
    session_.reset();  // its threads stop before the next one's start
    session_ = std::make_unique<pipeline::Session>(run_options_, detector_.get(), std::filesystem::path());
    index_ = 0;
    last_timestamp_ = 0.0;
    seconds_ = 0.0;
    frame_log_.clear();
    if (viewer_) viewer_->FollowSession(*session_);
    dense_ = MakeDenseMapper(options_, run_options_);  // the keyframes kept were the old session's
  }

  std::string ViewerUrl() const { return viewer_ ? viewer_->url() : std::string(); }

  const pipeline::Session& session() const { return *session_; }
  const io::Settings& settings() const { return settings_; }
  const pipeline::RunOptions& run_options() const { return run_options_; }
  // Held by every call that tracks, finishes or reads the session: frames are tracked one at a time, in the order
  // the calls take it, and the trajectory and map are read between frames (local mapping's own threads lock the
  // map themselves).
  std::mutex& mutex() const { return mutex_; }

 private:
  static std::unique_ptr<viewer::Viewer> MakeViewer(const Options& options, const pipeline::RunOptions& run_options) {
    if (!options.view) return nullptr;
    viewer::ViewerOptions view;
    view.address = options.view->address;
    view.port = options.view->port;
    // The program gives the frames: the page cannot pause them.
    return std::make_unique<viewer::Viewer>(view, viewer::ViewerHello{"api", 0, run_options.system.camera}, nullptr);
  }

  static std::unique_ptr<dense::DenseMapper> MakeDenseMapper(const Options& options,
                                                             const pipeline::RunOptions& run_options) {
    if (!options.dense) return nullptr;
    dense::DenseOptions dense;
    dense.voxel_size = options.dense->voxel_size;
    dense.truncation = 4.0 * dense.voxel_size;  // the command's default ratio
    dense.max_depth = options.dense->max_depth;
    dense.occupancy.resolution = options.dense->occupancy_resolution;
    dense.occupancy.band_low = options.dense->band_low;
    dense.occupancy.band_high = options.dense->band_high;
    dense.keep_seen_through = options.dense->keep_seen_through;
    return std::make_unique<dense::DenseMapper>(dense, run_options.system.camera);
  }

  mutable std::mutex mutex_;
  Options options_;
  io::Settings settings_;
  pipeline::RunOptions run_options_;
  std::unique_ptr<detect::Detector> detector_;  // before the session, whose detector thread uses it
  std::unique_ptr<pipeline::Session> session_;
  bool given_;
  std::size_t index_ = 0;
  double last_timestamp_ = 0.0;
  core::Stopwatch clock_;  // from the first frame, for summary.json's seconds and frames per second
  double seconds_ = 0.0;
  // Each frame's line of frames.jsonl, as `hoidslam run` writes it (a few hundred bytes a frame).
  std::vector<std::string> frame_log_;
  std::unique_ptr<viewer::Viewer> viewer_;  // after the session: it stops reading the session before it goes
  std::unique_ptr<dense::DenseMapper> dense_;
};

System::System(const Options& options) : impl_(std::make_unique<Impl>(options)) {}
System::~System() = default;
System::System(System&&) noexcept = default;
System& System::operator=(System&&) noexcept = default;

FrameResult System::Track(const ImageView& rgb, const ImageView& depth, double timestamp,
                          std::span<const Detection> detections, double depth_delay) {
  const std::lock_guard lock(impl_->mutex());
  return impl_->Track(rgb, depth, timestamp, detections, depth_delay);
}

void System::Finish() {
  const std::lock_guard lock(impl_->mutex());
  impl_->Finish();
}

std::vector<StampedPose> System::Trajectory() const {
  const std::lock_guard lock(impl_->mutex());
  return ToStampedPoses(impl_->session().system().FrameTrajectory());
}

std::vector<StampedPose> System::KeyFrames() const {
  const std::lock_guard lock(impl_->mutex());
  return ToStampedPoses(impl_->session().system().KeyFrameTrajectory());
}

std::vector<MapPoint> System::MapPoints() const {
  const std::lock_guard lock(impl_->mutex());
  std::vector<MapPoint> points;
  for (const slam::MapPointSample& p : impl_->session().system().MapPoints()) {
    points.push_back({{p.position.x(), p.position.y(), p.position.z()}, {p.color[2], p.color[1], p.color[0]},
                      p.observations});
  }
  return points;
}

void System::Save(const std::filesystem::path& folder) {
  const std::lock_guard lock(impl_->mutex());
  impl_->Save(folder);
}

void System::SaveMap(const std::filesystem::path& path) {
  const std::lock_guard lock(impl_->mutex());
  impl_->SaveMap(path);
}

void System::Reset() {
  const std::lock_guard lock(impl_->mutex());
  impl_->Reset();
}

int System::width() const { return impl_->run_options().system.camera.width; }
int System::height() const { return impl_->run_options().system.camera.height; }
double System::depth_factor() const { return impl_->settings().depth_map_factor; }
std::string System::filter() const { return impl_->run_options().exclusion.ModeName(); }
std::string System::ViewerUrl() const { return impl_->ViewerUrl(); }

}  // namespace hoidslam
