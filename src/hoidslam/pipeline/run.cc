#include "hoidslam/pipeline/run.h"

#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/progress.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/hoid/explain.h"
#include "hoidslam/report/annotate.h"
#include "hoidslam/pipeline/paced_replay.h"
#include "hoidslam/pipeline/playback.h"
#include "hoidslam/pipeline/session.h"

namespace hoidslam::pipeline {
namespace {

// Whether frame `index` of `total` is one of `count` snapshots: the middles of `count` equal parts of the run.
bool IsSnapshot(std::size_t index, std::size_t total, std::size_t count) {
  for (std::size_t k = 0; k < count && k < total; ++k) {
    if ((2 * k + 1) * total / (2 * count) == index) return true;
  }
  return false;
}

void WriteSnapshot(const std::filesystem::path& path, const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                   const std::vector<cv::KeyPoint>& keypoints, const std::vector<std::uint8_t>& keep) {
  std::vector<report::BoxAnnotation> annotations;
  annotations.reserve(boxes.detections.size());
  for (std::size_t i = 0; i < boxes.detections.size(); ++i) {
    annotations.push_back({boxes.detections[i].box, hoid::CaptionDecision(boxes.detections[i], boxes.decisions[i]),
                           boxes.decisions[i].dynamic});
  }
  cv::Mat image = report::DrawBoxAnnotations(frame.rgb, annotations);
  report::DrawKeptAndDropped(image, keypoints, keep);
  io::WriteImageAtomically(path, image);
}

constexpr core::EnumNames<KeypointBudget, 2> kBudgetNames = {{
    {KeypointBudget::kStatic, "static"},
    {KeypointBudget::kImage, "image"},
}};

}  // namespace

std::string_view ToString(KeypointBudget budget) { return core::EnumName(kBudgetNames, budget); }

KeypointBudget ParseKeypointBudget(std::string_view text, const std::string& parameter) {
  return core::ParseEnumName(kBudgetNames, text, parameter, "keypoint budget");
}

void RealTimeOptions::Check() const {
  if (preload_megabytes < 1 || preload_megabytes > (std::size_t{1} << 20)) {
    throw core::InputError::ForParameter("--preload-mb",
                                         fmt::format("must be in [1, 1048576] MB, got {}", preload_megabytes));
  }
  if (!(detector_latency_ms >= 0.0 && detector_latency_ms <= 60000.0)) {
    throw core::InputError::ForParameter("--detector-latency",
                                         fmt::format("must be in [0, 60000] ms, got {}", detector_latency_ms));
  }
  late_detections.Check();
}

void RunOptions::Check() const {
  system.Check();
  realtime.Check();
  if (realtime.enabled && system.deterministic) {
    throw core::InputError::ForParameter(
        "--realtime", "cannot go with --deterministic: the age of the detections each frame gets depends on timing");
  }
}

RunOptions RunOptions::FromSettings(const io::Settings& settings) {
  RunOptions options;
  options.system.camera = settings.camera;
  options.system.bf = settings.bf;
  options.system.close_depth = settings.CloseDepthThreshold();
  options.system.final_adjustment.enabled = true;  // run and the API alike (docs/slam.md, "The final adjustment")
  options.system.final_adjustment.depth_noise = settings.depth_noise;
  options.system.orb = settings.orb;
  options.exclusion.hoid = settings.hoid;
  options.depth_factor = settings.depth_map_factor;
  options.check_depth_units = settings.check_depth_units;
  return options;
}

std::string OtherMapTrajectoryName(slam::MapId map) { return fmt::format("trajectory-map{}.txt", map); }

std::optional<std::string> DetectOrKeepPrevious(detect::Detector& detector, const core::RgbdFrame& frame,
                                                std::size_t index, std::vector<core::Detection>& detections) {
  try {
    detections = detector.Detect(frame.timestamp, frame.rgb);
    return std::nullopt;
  } catch (const std::exception& e) {
    spdlog::warn("frame {} ({:.6f}): detector failed, using the previous frame's detections: {}", index,
                 frame.timestamp, e.what());
    return e.what();
  }
}

std::size_t FramesToPlay(std::size_t max_frames, std::size_t frames) {
  return max_frames == 0 ? frames : std::min(max_frames, frames);
}

void CheckImageSize(const core::RgbdFrame& frame, const RunOptions& options) {
  const core::CameraIntrinsics& camera = options.system.camera;
  if (frame.rgb.cols == camera.width && frame.rgb.rows == camera.height) return;
  throw core::InputError::InFile(
      frame.rgb_path, fmt::format("the image is {}x{}, but the camera settings say {}x{} (Camera.width, Camera.height "
                                  "of {}): give this camera's settings with --settings",
                                  frame.rgb.cols, frame.rgb.rows, camera.width, camera.height, options.settings_source));
}

RunSummary RunSequence(const io::RgbdSequence& sequence, detect::Detector& detector, const RunOptions& options,
                       const std::filesystem::path& folder, const RunHooks& hooks) {
  Session session(options, &detector, sequence.root());
  const std::function<bool()>& stop_requested = hooks.stop_requested;
  const RealTimeOptions& realtime = options.realtime;
  spdlog::info("{}: {} frames, filter {}, detector {}{}{}{}", sequence.name(), sequence.size(),
               options.exclusion.ModeName(), detector.Name(), realtime.enabled ? ", real time" : "",
               realtime.pace ? ", paced" : "", options.system.deterministic ? ", deterministic" : "");
  spdlog::info("settings: {}", options.settings_source);
  io::AtomicFile log(folder / "frames.jsonl");
  if (options.snapshots > 0) std::filesystem::create_directories(folder / "snapshots");

  const std::size_t total = FramesToPlay(options.max_frames, sequence.size());
  RunSummary& summary = session.summary();
  summary.times.reserve(total);
  // A paced replay decodes its first frames before the run's clock starts, as a camera is ready before it streams.
  std::optional<PacedReplay> paced;
  if (realtime.pace) paced.emplace(sequence, total, realtime.preload_megabytes << 20);
  core::ProgressReporter progress("run", total);
  if (hooks.started) hooks.started(session);
  try {
    Playback* const playback = paced ? nullptr : hooks.playback;
    double held_seconds = 0.0;  // waiting for the playback's turn: not the system's time
    const core::Stopwatch run_clock;
    for (std::optional<std::size_t> previous; true;) {
      const std::optional<std::size_t> next =
          paced ? paced->Next(previous, stop_requested) : std::optional(previous ? *previous + 1 : 0);
      if (stop_requested && stop_requested()) {
        summary.interrupted = true;
        break;
      }
      if (!next || *next >= total) break;
      const std::size_t index = *next;
      if (playback != nullptr) {
        const core::Stopwatch wait;
        const bool go = playback->WaitForTurn(sequence.entry(index).rgb_timestamp, stop_requested);
        held_seconds += wait.ElapsedMilliseconds() / 1000.0;
        if (!go) {
          summary.interrupted = true;
          break;
        }
      }
      const std::size_t dropped_before = paced ? paced->dropped() - summary.dropped : 0;
      previous = index;

      const core::Stopwatch clock;
      const core::RgbdFrame frame = paced ? paced->Take(index) : sequence.LoadFrame(index);
      CheckImageSize(frame, options);
      const FrameOutcome& outcome = session.Track(index, frame, nullptr, clock.ElapsedMilliseconds(), dropped_before);
      if (IsSnapshot(index, total, options.snapshots)) {
        WriteSnapshot(folder / "snapshots" / fmt::format("{:06d}.jpg", index), frame, outcome.boxes,
                      outcome.features.keypoints, outcome.keep);
      }
      log.stream() << outcome.entry.dump() << '\n';
      if (hooks.frame_tracked) hooks.frame_tracked(index, frame, outcome);
      progress.Update(index + 1);
    }
    summary.seconds = run_clock.ElapsedMilliseconds() / 1000.0 - (paced ? paced->held_seconds() : held_seconds);
    session.Finish();
    session.WriteOutputs(folder);
    log.Commit();
  } catch (...) {
    if (hooks.finished) hooks.finished(session);  // whoever follows the session lets go of it before it goes
    throw;
  }
  if (hooks.finished) hooks.finished(session);
  return summary;
}

}  // namespace hoidslam::pipeline
