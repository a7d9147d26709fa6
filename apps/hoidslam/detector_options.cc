#include "detector_options.h"

#include <filesystem>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "hoidslam/core/error.h"

namespace hoidslam::apps {

namespace fs = std::filesystem;

detect::OnnxDetectorOptions OnnxArgs::ToOptions() const {
  detect::OnnxDetectorOptions options;
  options.model = model;
  options.confidence_threshold = conf;
  options.nms_threshold = nms;
  options.input_size = input_size;
  options.layout = detect::ParseYoloLayout(layout, "Detector.layout (--layout)");
  options.class_names = names;
  return options;
}

void AddOnnxOptions(CLI::App& command, OnnxArgs& args, bool model_required) {
  CLI::Option* model = command.add_option("--model", args.model, "Detector model (.onnx)");
  if (model_required) model->required();
  command.add_option("--conf", args.conf, "Minimum detection score, in (0, 1)")->capture_default_str();
  command.add_option("--nms", args.nms, "IoU above which a box suppresses a weaker one of its class, in (0, 1]")
      ->capture_default_str();
  command.add_option("--input-size", args.input_size,
                     "Network input side in pixels, a multiple of 32; only for models without a fixed input size "
                     "(default: the model's, else 640)");
  command.add_option("--layout", args.layout, "Output layout: auto, yolox, yolov5, yolov8 or yolo11")
      ->capture_default_str();
  command.add_option("--names", args.names, "Class names file, one per line in model order (default: COCO-80)");
}

void AddDetectorOptions(CLI::App& command, DetectorArgs& args) {
  command.add_option("--detector", args.kind,
                     "none, onnx (--model) or file (--detections); default: onnx with --model, else the detections "
                     "file when there is one, else none")
      ->check(CLI::IsMember({"none", "onnx", "file"}));
  AddOnnxOptions(command, args.onnx, /*model_required=*/false);
  command.add_option("--detections", args.detections,
                     "Detections file to replay (default: detections.jsonl of the dataset folder, when present)");
}

namespace {

detect::DetectorOptions ChooseDetector(const DetectorArgs& args, const SequenceArgs& sequence,
                                       const pipeline::ExclusionOptions& exclusion, bool boxes_wanted) {
  detect::DetectorOptions options;
  options.onnx = args.onnx.ToOptions();
  fs::path detections = args.detections;
  if (detections.empty() && !sequence.dataset.empty()) {
    const fs::path beside = fs::path(sequence.dataset) / "detections.jsonl";
    if (fs::exists(beside)) detections = beside;
  }
  options.detections_file = detections;
  if (!args.kind.empty()) {
    options.kind = detect::ParseDetectorKind(args.kind, "--detector");
  } else if (!args.onnx.model.empty()) {
    options.kind = detect::DetectorKind::kOnnx;
  } else if (!detections.empty() && (exclusion.NeedsDetections() || boxes_wanted)) {
    options.kind = detect::DetectorKind::kFile;
  }
  if (options.kind == detect::DetectorKind::kFile && detections.empty()) {
    throw core::InputError::ForParameter("--detections", "--detector file needs a detections file");
  }
  if (options.kind == detect::DetectorKind::kNone && exclusion.NeedsDetections()) {
    throw core::InputError::ForParameter(
        "--filter", fmt::format("mode {} needs detections: give --model M.onnx or --detections F.jsonl (or use "
                                "--filter none)",
                                exclusion.ModeName()));
  }
  return options;
}

void CheckDetectionsFile(const detect::FileDetector& detector, const io::RgbdSequence& sequence) {
  std::size_t missing = 0;
  for (const double t : sequence.Timestamps()) missing += detector.file().Find(t) == nullptr ? 1 : 0;
  if (missing == sequence.size()) detector.CheckCovers(sequence.Timestamps(), sequence.name());  // throws
  if (missing > 0) {
    spdlog::warn("{}: no detections for {} of the {} frames; those frames use the previous frame's detections",
                 detector.file().path().string(), missing, sequence.size());
  }
}

}  // namespace

std::unique_ptr<detect::Detector> OpenDetector(const DetectorArgs& args, const SequenceArgs& sequence_args,
                                               const pipeline::ExclusionOptions& exclusion,
                                               const io::RgbdSequence& sequence, bool boxes_wanted) {
  std::unique_ptr<detect::Detector> detector =
      detect::MakeDetector(ChooseDetector(args, sequence_args, exclusion, boxes_wanted));
  if (const auto* file = dynamic_cast<const detect::FileDetector*>(detector.get())) CheckDetectionsFile(*file, sequence);
  return detector;
}

}  // namespace hoidslam::apps
