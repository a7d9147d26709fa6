#pragma once
// The model-independent half of running a YOLO-family detector: letterboxing the image into the network input,
// recognising the output tensor's layout from its shape, decoding it into boxes, and class-wise non-maximum
// suppression. Pure functions, so that each layout can be tested on small hand-made tensors.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace hoidslam::detect {

// How a model lays out its output (per anchor point: box, optional objectness, class scores).
enum class YoloLayout {
  kAuto,    // recognise from the output shape
  kYolox,   // 1×N×(5+C), N = Σ_s (W/s)(H/s) over strides 8, 16, 32; raw grid offsets and log sizes
  kYolov5,  // 1×3N×(5+C): three anchors per grid cell, already decoded to input pixels
  kYolov8,  // 1×(4+C)×N (YOLOv8, YOLO11): decoded cx, cy, w, h then class scores, no objectness
};

std::string_view ToString(YoloLayout layout);
// Parses "auto", "yolox", "yolov5", "yolov8" (also "yolo11", the same layout); throws InputError naming
// `parameter` otherwise.
YoloLayout ParseYoloLayout(std::string_view text, const std::string& parameter);

// Σ_s (W/s)(H/s) over the strides 8, 16 and 32 (3549 for 416×416, 8400 for 640×640).
int AnchorPointCount(cv::Size input);

// A recognised output tensor: its layout (never kAuto) and its number of classes C.
struct OutputFormat {
  YoloLayout layout = YoloLayout::kYolox;
  int num_classes = 0;
};

// The format of an output tensor of shape `shape` for a network input of size `input`, trying only `requested`
// unless it is kAuto (then YOLOX, YOLOv5, YOLOv8 in turn); nullopt when nothing matches.
std::optional<OutputFormat> MatchOutputShape(const std::vector<int>& shape, cv::Size input, YoloLayout requested);

// "1×3549×85".
std::string ShapeToString(const std::vector<int>& shape);
// The shapes MatchOutputShape accepts for `input` and `requested`, for error messages.
std::string ExpectedShapes(cv::Size input, YoloLayout requested);

// One decoded box, before non-maximum suppression.
struct Candidate {
  cv::Rect2f box;  // pixels of the network input (or of the image, once mapped back)
  int class_id = 0;
  float score = 0.0F;  // YOLOX, YOLOv5: objectness × best class score; YOLOv8: best class score
};

// Decodes a float output tensor of format `format` (as MatchOutputShape found it for `input`), keeping the best
// class of each anchor point when its score is at least `min_score`. Throws core::Error when the tensor does not
// have that format.
std::vector<Candidate> DecodeOutput(const cv::Mat& output, const OutputFormat& format, cv::Size input, float min_score);

// Where the image sits inside the letterboxed network input: input = image * scale + offset.
struct LetterboxTransform {
  float scale = 1.0F;
  cv::Point2f offset{0.0F, 0.0F};

  // Maps a box from network-input pixels back to image pixels (not clipped).
  cv::Rect2f ToImage(const cv::Rect2f& box) const;
};

enum class LetterboxPlacement {
  kTopLeft,  // image in the top-left corner, padding right and below (how YOLOX prepares images)
  kCentre,   // image centred, padding split on both sides (how YOLOv5 / YOLOv8 prepare images)
};

// Resizes `image` to fit `input` keeping its aspect ratio and pads with grey 114; `transform` receives the mapping.
cv::Mat Letterbox(const cv::Mat& image, cv::Size input, LetterboxPlacement placement, LetterboxTransform& transform);

// Indices of the candidates kept by non-maximum suppression run separately for each class (a box suppresses
// only boxes of its own class overlapping it by IoU > iou_threshold), best score first.
std::vector<std::size_t> ClassWiseNms(const std::vector<Candidate>& candidates, float iou_threshold);

}  // namespace hoidslam::detect
