#include "detector_options.h"

namespace hoidslam::apps {

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

}  // namespace hoidslam::apps
