#pragma once
// The detector's command-line options, shared by every command that runs a detector: the ONNX model's options,
// and, for the commands that run the HOID filter (run, masks), the choice among a model, a detections file and
// none.

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "sequence_options.h"
#include "hoidslam/detect/file_detector.h"
#include "hoidslam/detect/make_detector.h"
#include "hoidslam/detect/onnx_detector.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/pipeline/exclusion.h"

namespace hoidslam::apps {

struct OnnxArgs {
  std::string model;
  float conf = detect::OnnxDetectorOptions{}.confidence_threshold;
  float nms = detect::OnnxDetectorOptions{}.nms_threshold;
  int input_size = 0;
  std::string layout = "auto";
  std::string names;

  detect::OnnxDetectorOptions ToOptions() const;
};

// Adds --model (required when `model_required`), --conf, --nms, --input-size, --layout, --names.
void AddOnnxOptions(CLI::App& command, OnnxArgs& args, bool model_required);

struct DetectorArgs {
  std::string kind;        // --detector: none | onnx | file; empty: chosen from the other options
  OnnxArgs onnx;
  std::string detections;  // --detections; default <dataset>/detections.jsonl
};

// Adds --detector, the ONNX options (--model optional) and --detections.
void AddDetectorOptions(CLI::App& command, DetectorArgs& args);

// The detector the options ask for, ready for `sequence`. Without --detector: onnx when a model is given, the
// detections file when one is given or the dataset has detections.jsonl (and the filter needs boxes, or
// `boxes_wanted`: the dense map's person check asks for them in any mode), else none.
// Throws InputError naming the parameter when a filter that needs boxes gets no detector, or --detector file no
// file, and naming the file when a detections file is meant for another sequence (one that lacks a few frames is
// only reported: those frames reuse the previous frame's detections).
std::unique_ptr<detect::Detector> OpenDetector(const DetectorArgs& args, const SequenceArgs& sequence_args,
                                               const pipeline::ExclusionOptions& exclusion,
                                               const io::RgbdSequence& sequence, bool boxes_wanted = false);

}  // namespace hoidslam::apps
