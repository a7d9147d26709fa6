// `hoidslam detect`: runs an ONNX detector over every frame of a sequence and writes its detections file, so
// that SLAM runs (and anyone else) can replay the detections without running the network again. With
// --explain / --annotate it also shows what the HOID filter makes of each frame's detections.
#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "detector_options.h"
#include "sequence_options.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/interrupt.h"
#include "hoidslam/core/progress.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/detect/onnx_detector.h"
#include "hoidslam/eval/statistics.h"
#include "hoidslam/hoid/explain.h"
#include "hoidslam/hoid/filter.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/detections_file.h"
#include "hoidslam/io/files.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/report/annotate.h"

namespace hoidslam::apps {
namespace {

namespace fs = std::filesystem;

struct DetectArgs {
  SequenceArgs sequence;
  OnnxArgs onnx;
  std::string out;  // empty: <dataset>/detections.jsonl
  std::string settings;  // ORB-SLAM3-style settings file: HOID.* and DepthMapFactor
  std::string mode;      // overrides HOID.mode
  std::string annotate;  // folder for annotated frames
  bool explain = false;
  bool force = false;  // replace an existing --annotate folder
};

// Shows the HOID filter's verdict on each frame's detections: one line per detection on stdout (--explain)
// and/or the frame with red (dropped) and green (kept) boxes in a folder (--annotate).
class HoidExplainer {
 public:
  // The annotation folder appears complete or not at all; an existing one is replaced only with `replace`.
  HoidExplainer(const core::HoidOptions& options, const std::string& annotate_folder, bool replace, bool print)
      : options_(options), print_(print) {
    options_.Check();
    if (!annotate_folder.empty()) {
      annotate_folder_.emplace(annotate_folder, replace, "--annotate", "use --force to replace it");
    }
  }

  bool active() const { return print_ || annotate_folder_.has_value(); }
  // Only hoid3d reads depth; the other modes need no depth image at all.
  bool needs_depth() const { return active() && options_.mode == core::FilterMode::kHoid3d; }

  void Explain(std::size_t index, const core::RgbdFrame& frame, const std::vector<core::Detection>& detections) {
    hoid::ClassifyDetections(detections, options_, frame.depth, decisions_);
    if (print_) {
      fmt::print("frame {} ({:.6f}), mode {}:\n", index, frame.timestamp, core::ToString(options_.mode));
      for (std::size_t i = 0; i < detections.size(); ++i) {
        fmt::print("  #{:<2} {}\n", i, hoid::DescribeDecision(detections, decisions_, i));
      }
    }
    if (!annotate_folder_) return;
    std::vector<report::BoxAnnotation> annotations;
    annotations.reserve(detections.size());
    for (std::size_t i = 0; i < detections.size(); ++i) {
      annotations.push_back(
          {detections[i].box, hoid::CaptionDecision(detections[i], decisions_[i]), decisions_[i].dynamic});
    }
    io::WriteImageAtomically(annotate_folder_->temporary() / fmt::format("{:.6f}.png", frame.timestamp),
                             report::DrawBoxAnnotations(frame.rgb, annotations));
  }

  // Publishes the annotated frames.
  void Commit() {
    if (annotate_folder_) annotate_folder_->Commit();
  }

 private:
  core::HoidOptions options_;
  std::optional<io::AtomicFolder> annotate_folder_;
  bool print_;
  std::vector<hoid::Decision> decisions_;
};

struct RunSummary {
  std::size_t frames = 0;
  std::size_t detections = 0;
  std::map<std::string, std::size_t> per_class;
  std::vector<double> milliseconds;  // Detect() time of each frame
};

// Detects in every frame and writes `out`; returns false when Ctrl-C or SIGTERM stopped the run (the file is
// then not written).
bool DetectAll(const io::RgbdSequence& sequence, detect::Detector& detector, const fs::path& out,
               const core::InterruptGuard& interrupts, HoidExplainer& explainer, RunSummary& summary) {
  // The detector needs only colour; depth is decoded only when the HOID explanation needs it.
  const auto load = [&](std::size_t i) {
    if (explainer.needs_depth()) return sequence.LoadFrame(i);
    core::RgbdFrame frame;
    frame.timestamp = sequence.entry(i).rgb_timestamp;
    frame.rgb = io::ReadImage(sequence.entry(i).rgb_path, cv::IMREAD_COLOR, "colour");
    return frame;
  };
  const core::RgbdFrame first = load(0);
  io::DetectionsFileWriter writer(out, {sequence.name(), detector.Name(), first.rgb.cols, first.rgb.rows});
  core::ProgressReporter progress("detect", sequence.size());
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    if (interrupts.requested()) return false;
    const core::RgbdFrame frame = i == 0 ? first : load(i);
    if (frame.rgb.size() != first.rgb.size()) {
      throw core::InputError::InFile(sequence.entry(i).rgb_path,
                                     fmt::format("is {}×{}, unlike the first frame ({}×{})", frame.rgb.cols,
                                                 frame.rgb.rows, first.rgb.cols, first.rgb.rows));
    }
    const core::Stopwatch stopwatch;
    const io::FrameDetections detections{frame.timestamp, detector.Detect(frame.timestamp, frame.rgb)};
    summary.milliseconds.push_back(stopwatch.ElapsedMilliseconds());
    for (const core::Detection& d : detections.detections) ++summary.per_class[d.label];
    summary.detections += detections.detections.size();
    ++summary.frames;
    writer.Write(detections);
    if (explainer.active()) explainer.Explain(i, frame, detections.detections);
    progress.Update(i + 1);
  }
  writer.Commit();
  explainer.Commit();
  return true;
}

void PrintSummary(const fs::path& out, const RunSummary& summary) {
  fmt::print("wrote {}: {} frames, {} detections\n", out.string(), summary.frames, summary.detections);
  std::vector<std::pair<std::string, std::size_t>> classes(summary.per_class.begin(), summary.per_class.end());
  std::stable_sort(classes.begin(), classes.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  for (const auto& [label, count] : classes) fmt::print("  {:<16} {:>8}\n", label, count);
  fmt::print("median {:.1f} ms per frame (detector only)\n", eval::ComputeStatistics(summary.milliseconds).median);
}

void RunDetect(const DetectArgs& args) {
  const io::Settings settings = args.settings.empty() ? io::Settings{} : io::LoadSettings(args.settings);
  core::HoidOptions hoid_options = settings.hoid;
  if (!args.mode.empty()) hoid_options.mode = core::ParseFilterMode(args.mode, "HOID.mode (--mode)");
  HoidExplainer explainer(hoid_options, args.annotate, args.force, args.explain);

  const io::RgbdSequence sequence =
      OpenSequence(args.sequence, args.settings.empty() ? std::nullopt : std::optional(settings.depth_map_factor));

  detect::OnnxDetector detector(args.onnx.ToOptions());
  spdlog::info("{}: {}×{} input, {} layout, {} classes; {} frames of {}", detector.Name(), detector.input_size().width,
               detector.input_size().height, detect::ToString(detector.output_format().layout),
               detector.output_format().num_classes, sequence.size(), sequence.name());

  const fs::path out = args.out.empty() ? SequenceFolder(args.sequence) / "detections.jsonl" : fs::path(args.out);
  RunSummary summary;
  core::InterruptGuard interrupts;
  if (!DetectAll(sequence, detector, out, interrupts, explainer, summary)) {
    spdlog::warn("interrupted after {} of {} frames; {} was not written", summary.frames, sequence.size(),
                 out.string());
    interrupts.Reraise();
  }
  PrintSummary(out, summary);
}

}  // namespace

void AddDetectCommand(CLI::App& app) {
  auto args = std::make_shared<DetectArgs>();
  CLI::App* command = app.add_subcommand(
      "detect",
      "Run an ONNX detector (YOLOX, YOLOv5, YOLOv8, YOLO11) on every RGB frame of a TUM-layout sequence "
      "and write its detections file (JSON Lines, docs/detections-file.md)");
  AddSequenceOptions(*command, args->sequence);
  AddOnnxOptions(*command, args->onnx, /*model_required=*/true);
  command->add_option("--out", args->out, "Detections file to write (default: <dataset>/detections.jsonl)");
  command->add_option("--settings", args->settings,
                      "Settings file (e.g. config/TUM3.yaml): its HOID.* section and DepthMapFactor are used");
  command->add_option("--mode", args->mode,
                      "HOID filter mode for --explain/--annotate: none, person, classes, hoid2d, hoid3d or hoidplus "
                      "(default: HOID.mode of the settings, else hoidplus)");
  command->add_flag("--explain", args->explain, "Print the HOID filter's verdict on every detection of every frame");
  command->add_option("--annotate", args->annotate,
                      "Write every frame with its boxes to this folder: red = features dropped, green = kept");
  command->add_flag("--force", args->force, "Replace the --annotate folder when it exists and is not empty");
  command->callback([args] { RunDetect(*args); });
}

}  // namespace hoidslam::apps
