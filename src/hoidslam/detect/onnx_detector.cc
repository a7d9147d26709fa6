#include "hoidslam/detect/onnx_detector.h"

#include <optional>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/detect/class_names.h"
#include "hoidslam/detect/onnx_model_info.h"

namespace hoidslam::detect {
namespace {

constexpr int kStrideMultiple = 32;  // the coarsest YOLO stride: input sides must be multiples of it
constexpr int kMaxInputSide = 8192;  // far beyond any detector's input; catches a mistyped size

// The network input size: the model's own when it declares one, else the option, else kDefaultInputSize.
cv::Size ChooseInputSize(const OnnxDetectorOptions& options) {
  const OnnxInputInfo input = ReadOnnxInput(options.model);
  const std::vector<std::int64_t>& dims = input.dims;
  if (dims.size() != 4 || (dims[1] != 3 && dims[1] != -1)) {
    std::vector<int> shown(dims.begin(), dims.end());
    throw core::InputError::InFile(
        options.model, fmt::format("input '{}' has shape {}, expected an image batch 1×3×height×width", input.name,
                                   dims.empty() ? "(none)" : ShapeToString(shown)));
  }
  const std::int64_t height = dims[2];
  const std::int64_t width = dims[3];
  if (height <= 0 || width <= 0) {
    const int side = options.input_size > 0 ? options.input_size : kDefaultInputSize;
    return {side, side};
  }
  if (height % kStrideMultiple != 0 || width % kStrideMultiple != 0 || height > kMaxInputSide ||
      width > kMaxInputSide) {
    throw core::InputError::InFile(options.model, fmt::format("input size {}×{} is not a multiple of {} up to {}", width,
                                                              height, kStrideMultiple, kMaxInputSide));
  }
  if (options.input_size > 0 && (options.input_size != width || options.input_size != height)) {
    throw core::InputError::ForParameter(
        "Detector.inputSize (--input-size)",
        fmt::format("{} takes a fixed {}×{} input, got {}", options.model.filename().string(), width, height,
                    options.input_size));
  }
  return {static_cast<int>(width), static_cast<int>(height)};
}

cv::dnn::Net LoadNet(const std::filesystem::path& model) {
  try {
    cv::dnn::Net net = cv::dnn::readNetFromONNX(model.string());
    if (net.empty()) throw core::InputError::InFile(model, "OpenCV loaded an empty network");
    net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    return net;
  } catch (const cv::Exception& e) {
    throw core::InputError::InFile(model, fmt::format("OpenCV cannot load this ONNX model: {}", e.err));
  }
}

}  // namespace

void OnnxDetectorOptions::Check() const {
  if (model.empty()) throw core::InputError::ForParameter("Detector.model (--model)", "no model file given");
  if (input_size != 0 &&
      (input_size < kStrideMultiple || input_size % kStrideMultiple != 0 || input_size > kMaxInputSide)) {
    throw core::InputError::ForParameter("Detector.inputSize (--input-size)",
                                         fmt::format("must be 0 (from the model) or a multiple of {} up to {}, got {}",
                                                     kStrideMultiple, kMaxInputSide, input_size));
  }
  if (!(confidence_threshold > 0.0F && confidence_threshold < 1.0F)) {
    throw core::InputError::ForParameter("Detector.confThreshold (--conf)",
                                         fmt::format("must be in (0, 1), got {}", confidence_threshold));
  }
  if (!(nms_threshold > 0.0F && nms_threshold <= 1.0F)) {
    throw core::InputError::ForParameter("Detector.nmsThreshold (--nms)",
                                         fmt::format("must be in (0, 1], got {}", nms_threshold));
  }
}

OnnxDetector::OnnxDetector(const OnnxDetectorOptions& options) : options_(options) {
  options_.Check();
  const std::filesystem::path& model = options_.model;
  if (!std::filesystem::is_regular_file(model)) throw core::InputError::InFile(model, "no such model file");
  input_size_ = ChooseInputSize(options_);
  net_ = LoadNet(model);

  // One run on a blank image tells each output's shape (OpenCV cannot always infer them without running).
  LetterboxTransform ignored;
  net_.setInput(Preprocess(cv::Mat(input_size_, CV_8UC3, cv::Scalar::all(114)), ignored));
  const std::vector<std::string> names = net_.getUnconnectedOutLayersNames();
  std::vector<cv::Mat> outputs;
  try {
    net_.forward(outputs, names);
  } catch (const cv::Exception& e) {
    throw core::InputError::InFile(
        model, fmt::format("inference on a {}×{} image failed: {}", input_size_.width, input_size_.height, e.err));
  }
  std::vector<std::string> shapes;
  for (std::size_t i = 0; i < outputs.size() && output_name_.empty(); ++i) {
    const std::vector<int> shape(outputs[i].size.p, outputs[i].size.p + outputs[i].dims);
    if (const std::optional<OutputFormat> format = MatchOutputShape(shape, input_size_, options_.layout)) {
      format_ = *format;
      output_name_ = names[i];
    }
    shapes.push_back(ShapeToString(shape));
  }
  if (output_name_.empty()) {
    throw core::InputError::InFile(
        model, fmt::format("output shape {} matches no known layout (expected {})", fmt::join(shapes, ", "),
                           ExpectedShapes(input_size_, options_.layout)));
  }

  if (options_.class_names.empty()) {
    class_names_ = CocoClassNames();
    if (static_cast<int>(class_names_.size()) != format_.num_classes) {
      throw core::InputError::InFile(model, fmt::format("has {} classes, not the 80 of COCO: give its class names "
                                                        "file (Detector.classNames, --names)",
                                                        format_.num_classes));
    }
  } else {
    class_names_ = ReadClassNames(options_.class_names);
    if (static_cast<int>(class_names_.size()) != format_.num_classes) {
      throw core::InputError::InFile(options_.class_names,
                                     fmt::format("lists {} class names but {} has {} classes", class_names_.size(),
                                                 model.filename().string(), format_.num_classes));
    }
  }
}

cv::Mat OnnxDetector::Preprocess(const cv::Mat& bgr, LetterboxTransform& transform) const {
  // YOLOX is trained on BGR 0..255 placed top-left; Ultralytics models on RGB 0..1, centred.
  // (During the constructor's blank run the layout is not known yet; any preparation gives the shapes.)
  const bool yolox = format_.layout == YoloLayout::kYolox;
  const cv::Mat boxed =
      Letterbox(bgr, input_size_, yolox ? LetterboxPlacement::kTopLeft : LetterboxPlacement::kCentre, transform);
  return cv::dnn::blobFromImage(boxed, yolox ? 1.0 : 1.0 / 255.0, cv::Size(), cv::Scalar(), /*swapRB=*/!yolox,
                                /*crop=*/false, CV_32F);
}

std::vector<core::Detection> OnnxDetector::Detect(double /*timestamp*/, const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw core::Error(fmt::format("OnnxDetector::Detect needs a non-empty 8-bit BGR image, got {}×{} of type {}",
                                  bgr.cols, bgr.rows, bgr.type()));
  }
  LetterboxTransform transform;
  net_.setInput(Preprocess(bgr, transform));
  const cv::Mat output = net_.forward(output_name_);

  const cv::Rect2f image(0.0F, 0.0F, static_cast<float>(bgr.cols), static_cast<float>(bgr.rows));
  std::vector<Candidate> candidates;
  for (Candidate& candidate : DecodeOutput(output, format_, input_size_, options_.confidence_threshold)) {
    candidate.box = transform.ToImage(candidate.box) & image;
    if (candidate.box.area() > 0.0F) candidates.push_back(candidate);
  }

  std::vector<core::Detection> detections;
  for (const std::size_t i : ClassWiseNms(candidates, options_.nms_threshold)) {
    const Candidate& c = candidates[i];
    detections.push_back({c.class_id, class_names_[static_cast<std::size_t>(c.class_id)], c.score, c.box});
  }
  return detections;
}

}  // namespace hoidslam::detect
