#include "hoidslam/synth/sequence_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "hoidslam/core/error.h"
#include "hoidslam/core/progress.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/detections_file.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/synth/office.h"
#include "hoidslam/synth/random.h"
#include "hoidslam/synth/renderer.h"
#include "hoidslam/synth/sensor_noise.h"
#include "hoidslam/synth/static_geometry.h"
#include "hoidslam/synth/world.h"

namespace hoidslam::synth {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Purposes of the per-frame seeds (random.h FrameSeed).
enum SeedPurpose : std::uint64_t { kRgbNoise = 1, kDepthNoise = 2, kDetectorNoise = 3 };

// What a rendered frame leaves for the in-order writers of the list files.
struct FrameResult {
  std::vector<core::Detection> truth;
  std::vector<core::Detection> detections;
};

// PNG settings: level 1 and Huffman coding only for the noisy colour and depth images (string matching finds
// little in sensor noise; this is about a third faster than the default at a smaller size), run-length coding
// for the masks, which are mostly empty.
const std::vector<int> kNoisyPng = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                    cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY};
const std::vector<int> kMaskPng = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                   cv::IMWRITE_PNG_STRATEGY_RLE};

void WritePng(const fs::path& path, const cv::Mat& image, const std::vector<int>& params) {
  if (!cv::imwrite(path.string(), image, params)) {
    throw core::InputError::InFile(path, "cannot write image");
  }
}

// Grey level of a covered lens: a little light leaks in, so the sensor noise is not all clipped away at black.
constexpr double kCoveredLensLevel = 4.0;

// What a covered lens sees: a dark image, no depth, no instance.
RenderOutput CoveredLensImage(const core::CameraIntrinsics& camera) {
  const cv::Size size(camera.width, camera.height);
  return {cv::Mat(size, CV_8UC3, cv::Scalar::all(kCoveredLensLevel)), cv::Mat::zeros(size, CV_32F),
          cv::Mat(size, CV_32S, cv::Scalar(kNoInstance))};
}

// The colour image under lights dimmed to `level` of their brightness (the image itself when they are not).
cv::Mat Dimmed(const cv::Mat& bgr, double level) {
  if (level >= 1.0) return bgr;
  cv::Mat dimmed;
  bgr.convertTo(dimmed, -1, level);
  return dimmed;
}

double RoundToMicroseconds(double seconds) { return std::round(seconds * 1e6) / 1e6; }

json EventJson(const WorldEvent& event, double time_origin) {
  json line = {{"time", RoundToMicroseconds(time_origin + event.time)}, {"person", event.person},
               {"action", event.action}};
  if (!event.object.empty()) line["object"] = event.object;
  auto point = [](const Eigen::Vector3d& p) {
    return json::array({std::round(p.x() * 1e4) / 1e4, std::round(p.y() * 1e4) / 1e4, std::round(p.z() * 1e4) / 1e4});
  };
  if (event.from) line["from"] = point(*event.from);
  if (event.to) line["to"] = point(*event.to);
  return line;
}

// The lines of the event log, in time order: what the people do; when the lens is covered and uncovered, and when
// the lights dim and come back, each with the index of the first frame written covered (dark) and of the first
// written uncovered (lit) again (left out when the sequence ends before it).
std::string EventLog(const World& world, const Scenario& scenario, const std::vector<CameraFrame>& frames) {
  const double time_origin = frames.front().timestamp;
  std::vector<std::pair<double, json>> lines;
  for (const WorldEvent& event : world.events()) lines.emplace_back(event.time, EventJson(event, time_origin));
  auto stretch_event = [&](double time, const char* action, const std::function<bool(double)>& frame_matches,
                           json line = json::object()) {
    line["time"] = RoundToMicroseconds(time_origin + time);
    line["action"] = action;
    const auto first = std::find_if(frames.begin(), frames.end(), [&](const CameraFrame& frame) {
      return frame_matches(frame.timestamp - time_origin);
    });
    if (first != frames.end()) line["frame"] = first - frames.begin();
    lines.emplace_back(time, std::move(line));
  };
  for (const CoveredStretch& stretch : scenario.covered) {
    stretch_event(stretch.from, "cover_lens", [&](double t) { return stretch.Covers(t); });
    stretch_event(stretch.end(), "uncover_lens",
                  [&](double t) { return t >= stretch.end() && !scenario.LensCoveredAt(t); });
  }
  for (const DarkStretch& stretch : scenario.dark) {
    stretch_event(stretch.from, "dark", [&](double t) { return stretch.Covers(t); }, {{"level", stretch.level}});
    stretch_event(stretch.end(), "undark",
                  [&](double t) { return t >= stretch.end() && scenario.LightLevelAt(t) == 1.0; });
  }
  std::stable_sort(lines.begin(), lines.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string log;
  for (const auto& [time, line] : lines) log += line.dump() + "\n";
  return log;
}

// The scenario document with the values actually used (seed, frame limit, detector noise).
json RenderedScenario(const Scenario& scenario) {
  json document = scenario.document;
  document["seed"] = scenario.seed;
  document["frames"] = scenario.max_frames;
  const DetectorNoiseOptions& n = scenario.detector_noise;
  document["detector_noise"] = {{"miss_rate", n.miss_rate},
                                {"box_jitter", n.box_jitter},
                                {"false_positive_rate", n.false_positive_rate},
                                {"class_confusion_rate", n.class_confusion_rate},
                                {"seed", n.seed}};
  return document;
}

void WriteText(const fs::path& path, const std::string& text) {
  io::AtomicFile file(path);
  file.stream() << text;
  file.Commit();
}

void WriteLists(const fs::path& folder, const Scenario& scenario, const std::vector<CameraFrame>& frames) {
  std::string rgb =
      fmt::format("# color images\n# hoidslam synth scenario '{}'\n# timestamp filename\n", scenario.name);
  std::string depth =
      fmt::format("# depth maps\n# hoidslam synth scenario '{}'\n# timestamp filename\n", scenario.name);
  std::string associations;
  for (const CameraFrame& frame : frames) {
    const std::string t = StampText(frame.timestamp);
    const std::string d = StampText(frame.depth_timestamp);
    rgb += fmt::format("{} rgb/{}.png\n", t, t);
    depth += fmt::format("{} depth/{}.png\n", d, d);
    associations += fmt::format("{} rgb/{}.png {} depth/{}.png\n", t, t, d, d);
  }
  WriteText(folder / "rgb.txt", rgb);
  WriteText(folder / "depth.txt", depth);
  WriteText(folder / "associations.txt", associations);
}

void WriteDetections(const fs::path& file, const std::string& sequence, const std::string& detector,
                     const std::vector<CameraFrame>& frames, const std::vector<FrameResult>& results, bool truth) {
  const core::CameraIntrinsics camera;
  io::DetectionsFileWriter writer(file, {sequence, detector, camera.width, camera.height});
  for (std::size_t i = 0; i < results.size(); ++i) {
    writer.Write({frames[i].timestamp, truth ? results[i].truth : results[i].detections});
  }
  writer.Commit();
}

// 255 where the instance drawn is one `marked` picks, else 0 (CV_8U).
cv::Mat InstanceMask(const cv::Mat& instance, const SceneSnapshot& snapshot,
                     const std::function<bool(const SceneInstance&)>& marked) {
  CV_Assert(instance.type() == CV_32S);
  int max_id = 0;
  for (const SceneInstance& s : snapshot.instances) max_id = std::max(max_id, s.id);
  std::vector<unsigned char> value(static_cast<std::size_t>(max_id) + 1, 0);
  for (const SceneInstance& s : snapshot.instances) {
    if (marked(s)) value[static_cast<std::size_t>(s.id)] = 255;
  }
  cv::Mat mask(instance.size(), CV_8U);
  for (int v = 0; v < instance.rows; ++v) {
    const int* in = instance.ptr<int>(v);
    unsigned char* out = mask.ptr<unsigned char>(v);
    for (int u = 0; u < instance.cols; ++u) {
      const int id = in[u];
      out[u] = id > kNoInstance && id <= max_id ? value[static_cast<std::size_t>(id)] : 0;
    }
  }
  return mask;
}

}  // namespace

void SynthOptions::Check() const {
  if (out.empty()) throw core::InputError::ForParameter("--out", "no output folder given");
  if (threads < 1 || threads > 64) throw core::InputError::ForParameter("--threads", "must be in [1, 64]");
  if (frame_step < 1) throw core::InputError::ForParameter("--frame-step", "must be >= 1");
  if (min_box_pixels < 1) throw core::InputError::ForParameter("min_box_pixels", "must be >= 1");
}

CameraPath ScenarioCameraPath(const Scenario& scenario, const fs::path& tum_dir) {
  if (scenario.camera.tum.empty()) {
    ProceduralPathOptions options = scenario.camera.procedural;
    if (scenario.max_frames > 0) options.frames = std::min(options.frames, scenario.max_frames);
    return CameraPath::Procedural(options);
  }
  const std::string file = scenario.camera.tum + ".txt";
  if (!fs::exists(tum_dir / "groundtruth" / file)) {
    throw core::InputError::InFile(tum_dir / "groundtruth" / file,
                                   fmt::format("no TUM camera path '{}' here (give the folder holding groundtruth/ and "
                                               "associations/ with --data-dir, or set HOIDSLAM_SHARED_DIR)",
                                               scenario.camera.tum));
  }
  return CameraPath::FromTum(tum_dir / "groundtruth" / file, tum_dir / "associations" / file, scenario.camera.T_anchor,
                             scenario.max_frames);
}

std::vector<core::Detection> GroundTruthBoxes(const cv::Mat& instance, const SceneSnapshot& snapshot, int min_pixels) {
  CV_Assert(instance.type() == CV_32S);
  int max_id = 0;
  for (const SceneInstance& s : snapshot.instances) max_id = std::max(max_id, s.id);
  struct Extent {
    int x0 = INT32_MAX, y0 = INT32_MAX, x1 = -1, y1 = -1, count = 0;
  };
  std::vector<Extent> extents(static_cast<std::size_t>(max_id) + 1);
  for (int v = 0; v < instance.rows; ++v) {
    const int* row = instance.ptr<int>(v);
    for (int u = 0; u < instance.cols; ++u) {
      const int id = row[u];
      if (id <= kNoInstance || id > max_id) continue;
      Extent& e = extents[static_cast<std::size_t>(id)];
      e.x0 = std::min(e.x0, u);
      e.x1 = std::max(e.x1, u);
      e.y0 = std::min(e.y0, v);
      e.y1 = std::max(e.y1, v);
      ++e.count;
    }
  }
  std::vector<const SceneInstance*> labelled;
  for (const SceneInstance& s : snapshot.instances) {
    if (!s.label.empty()) labelled.push_back(&s);
  }
  std::sort(labelled.begin(), labelled.end(), [](const auto* a, const auto* b) { return a->id < b->id; });
  std::vector<core::Detection> boxes;
  for (const SceneInstance* s : labelled) {
    const Extent& e = extents[static_cast<std::size_t>(s->id)];
    if (e.count < min_pixels) continue;
    boxes.push_back({CocoClassId(s->label), s->label, 1.0F,
                     cv::Rect2f(static_cast<float>(e.x0), static_cast<float>(e.y0), static_cast<float>(e.x1 - e.x0 + 1),
                                static_cast<float>(e.y1 - e.y0 + 1))});
  }
  return boxes;
}

cv::Mat MovingMask(const cv::Mat& instance, const SceneSnapshot& snapshot) {
  return InstanceMask(instance, snapshot, [](const SceneInstance& s) { return s.moving; });
}

cv::Mat PeopleMask(const cv::Mat& instance, const SceneSnapshot& snapshot) {
  return InstanceMask(instance, snapshot, [](const SceneInstance& s) { return s.label == "person"; });
}

SynthResult WriteSequence(const Scenario& scenario, const SynthOptions& options) {
  const core::Stopwatch stopwatch;
  options.Check();
  scenario.detector_noise.Check();
  // Checked and created before the expensive work; removed again by whatever fails below.
  io::AtomicFolder output(options.out, options.force, "--out", "use --force to replace it");
  const CameraPath path = ScenarioCameraPath(scenario, options.tum_dir);
  TextureOptions texture_options = scenario.textures;
  texture_options.photo_folder = options.textures_dir;
  const TextureSet textures(texture_options);
  const World world(scenario, textures);
  const Renderer renderer(core::CameraIntrinsics{}, textures);
  const core::CameraIntrinsics& camera = renderer.intrinsics();

  std::error_code error;
  for (const char* sub : {"rgb", "depth", "mask", "people"}) {
    if (!error) fs::create_directories(output.temporary() / sub, error);
  }
  if (error) throw core::InputError::InFile(output.temporary(), "cannot create the output folder: " + error.message());

  std::vector<CameraFrame> frames;
  for (std::size_t i = 0; i < path.size(); i += static_cast<std::size_t>(options.frame_step)) {
    frames.push_back(path.frames()[i]);
  }
  core::Trajectory trajectory;
  for (const CameraFrame& frame : frames) trajectory.push_back({frame.timestamp, frame.T_wc});
  const double time_origin = frames.front().timestamp;
  SequenceGeometry geometry(world.Snapshot(0.0));
  std::vector<FrameResult> results(frames.size());
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex progress_mutex;
  std::size_t done = 0;
  std::optional<core::ProgressReporter> progress;
  if (options.progress) progress.emplace("synth " + scenario.name, frames.size());
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(options.threads));

  auto work = [&](std::size_t worker) {
    try {
      for (std::size_t i = next++; i < frames.size() && !failed; i = next++) {
        if (options.stop_requested && options.stop_requested()) throw core::Interrupted();
        const CameraFrame& frame = frames[i];
        SceneSnapshot snapshot = world.Snapshot(frame.timestamp - time_origin);
        snapshot.timestamp = frame.timestamp;
        geometry.Add(snapshot);
        const double time = frame.timestamp - time_origin;
        const bool covered = scenario.LensCoveredAt(time);
        const RenderOutput rendered = covered ? CoveredLensImage(camera) : renderer.Render(snapshot, frame.T_wc);
        FrameResult& result = results[i];
        result.truth = GroundTruthBoxes(rendered.instance, snapshot, options.min_box_pixels);
        result.detections =
            ApplyDetectorNoise(result.truth, scenario.detector_noise,
                               FrameSeed(scenario.seed ^ Mix64(scenario.detector_noise.seed), i, kDetectorNoise),
                               camera.width, camera.height);
        const std::string t = StampText(frame.timestamp);
        WritePng(output.temporary() / "rgb" / (t + ".png"),
                 ApplyRgbNoise(covered ? rendered.bgr : Dimmed(rendered.bgr, scenario.LightLevelAt(time)),
                               scenario.sensor_noise, FrameSeed(scenario.seed, i, kRgbNoise)),
                 kNoisyPng);
        WritePng(output.temporary() / "depth" / (StampText(frame.depth_timestamp) + ".png"),
                 ApplyDepthNoise(rendered.depth, scenario.sensor_noise, FrameSeed(scenario.seed, i, kDepthNoise)),
                 kNoisyPng);
        WritePng(output.temporary() / "mask" / (t + ".png"), MovingMask(rendered.instance, snapshot), kMaskPng);
        WritePng(output.temporary() / "people" / (t + ".png"), PeopleMask(rendered.instance, snapshot), kMaskPng);
        if (progress) {
          const std::lock_guard lock(progress_mutex);
          progress->Update(++done);
        }
      }
    } catch (...) {
      errors[worker] = std::current_exception();
      failed = true;
    }
  };
  {
    // jthreads join when they go out of scope, also when starting a later one throws: `failed` then stops the
    // started ones at their next frame, and nothing is left running on the locals they use.
    std::vector<std::jthread> workers;
    try {
      for (int w = 1; w < options.threads; ++w) workers.emplace_back(work, static_cast<std::size_t>(w));
    } catch (...) {
      failed = true;
      throw;
    }
    work(0);
  }
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }

  const fs::path& folder = output.temporary();
  WriteLists(folder, scenario, frames);
  io::WriteTumTrajectory(folder / "groundtruth.txt", trajectory);
  const std::string sequence = output.path().filename().string();
  WriteDetections(folder / "detections.jsonl", sequence, scenario.detector_noise.Describe(), frames, results, false);
  if (scenario.detector_noise.Any()) {
    WriteDetections(folder / "detections_truth.jsonl", sequence, DetectorNoiseOptions{}.Describe(), frames, results,
                    true);
  }
  WriteText(folder / "events.jsonl", EventLog(world, scenario, frames));
  WriteText(folder / "scenario.json", RenderedScenario(scenario).dump(2) + "\n");
  io::WritePlyMesh(folder / "static_geometry.ply", geometry.StaticMesh(), "hoidslam static geometry of " + sequence);
  io::WriteVoxelCentresPly(folder / "moving_volume.ply", geometry.MovingVolume());

  output.Commit();
  return {frames.size(), stopwatch.ElapsedSeconds()};
}

}  // namespace hoidslam::synth
