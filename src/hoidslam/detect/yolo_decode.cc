#include "hoidslam/detect/yolo_decode.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include <fmt/format.h>
#include <opencv2/dnn/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"

namespace hoidslam::detect {
namespace {

constexpr std::array<int, 3> kStrides = {8, 16, 32};

// YOLO11 models share the YOLOv8 output layout; the first name of a value is the one printed.
constexpr core::EnumNames<YoloLayout, 5> kLayoutNames = {{
    {YoloLayout::kAuto, "auto"},
    {YoloLayout::kYolox, "yolox"},
    {YoloLayout::kYolov5, "yolov5"},
    {YoloLayout::kYolov8, "yolov8"},
    {YoloLayout::kYolov8, "yolo11"},
}};

// exp() of a raw YOLOX log-size is capped here so that a wild value gives a huge but finite box (clipped to
// the image later) instead of inf/NaN coordinates.
constexpr float kMaxLogSize = 10.0F;

cv::Rect2f FromCentre(float cx, float cy, float w, float h) { return {cx - w / 2, cy - h / 2, w, h}; }

// The best class of one anchor point: scores[k * step] for k in [0, count).
std::pair<int, float> BestClass(const float* scores, int count, int step) {
  int best = 0;
  for (int k = 1; k < count; ++k) {
    if (scores[k * step] > scores[best * step]) best = k;
  }
  return {best, scores[best * step]};
}

}  // namespace

std::string_view ToString(YoloLayout layout) { return core::EnumName(kLayoutNames, layout); }

YoloLayout ParseYoloLayout(std::string_view text, const std::string& parameter) {
  return core::ParseEnumName(kLayoutNames, text, parameter, "layout");
}

int AnchorPointCount(cv::Size input) {
  int count = 0;
  for (const int stride : kStrides) count += (input.width / stride) * (input.height / stride);
  return count;
}

std::optional<OutputFormat> MatchOutputShape(const std::vector<int>& shape, cv::Size input, YoloLayout requested) {
  if (shape.size() != 3 || shape[0] != 1) return std::nullopt;
  const int anchors = AnchorPointCount(input);
  const auto wanted = [requested](YoloLayout layout) { return requested == YoloLayout::kAuto || requested == layout; };
  if (wanted(YoloLayout::kYolox) && shape[1] == anchors && shape[2] > 5) {
    return OutputFormat{YoloLayout::kYolox, shape[2] - 5};
  }
  if (wanted(YoloLayout::kYolov5) && shape[1] == 3 * anchors && shape[2] > 5) {
    return OutputFormat{YoloLayout::kYolov5, shape[2] - 5};
  }
  if (wanted(YoloLayout::kYolov8) && shape[2] == anchors && shape[1] > 4) {
    return OutputFormat{YoloLayout::kYolov8, shape[1] - 4};
  }
  return std::nullopt;
}

std::string ShapeToString(const std::vector<int>& shape) { return fmt::format("{}", fmt::join(shape, "×")); }

std::string ExpectedShapes(cv::Size input, YoloLayout requested) {
  const int anchors = AnchorPointCount(input);
  std::vector<std::string> shapes;
  if (requested == YoloLayout::kAuto || requested == YoloLayout::kYolox) {
    shapes.push_back(fmt::format("1×{}×(5+C) for YOLOX", anchors));
  }
  if (requested == YoloLayout::kAuto || requested == YoloLayout::kYolov5) {
    shapes.push_back(fmt::format("1×{}×(5+C) for YOLOv5", 3 * anchors));
  }
  if (requested == YoloLayout::kAuto || requested == YoloLayout::kYolov8) {
    shapes.push_back(fmt::format("1×(4+C)×{} for YOLOv8/YOLO11", anchors));
  }
  return fmt::format("{} with a {}×{} input", fmt::join(shapes, ", "), input.width, input.height);
}

std::vector<Candidate> DecodeOutput(const cv::Mat& output, const OutputFormat& format, cv::Size input,
                                    float min_score) {
  const std::vector<int> shape(output.size.p, output.size.p + output.dims);
  const std::optional<OutputFormat> found = MatchOutputShape(shape, input, format.layout);
  if (output.type() != CV_32F || !output.isContinuous() || !found || found->num_classes != format.num_classes) {
    throw core::Error(fmt::format("DecodeOutput: a float tensor of {} is not a {} output with {} classes",
                                  ShapeToString(shape), ToString(format.layout), format.num_classes));
  }
  const float* data = output.ptr<float>();
  const int classes = format.num_classes;
  std::vector<Candidate> candidates;

  if (format.layout == YoloLayout::kYolox) {
    const int row_size = 5 + classes;
    const float* row = data;
    for (const int stride : kStrides) {
      const int grid_width = input.width / stride;
      const int grid_height = input.height / stride;
      for (int gy = 0; gy < grid_height; ++gy) {
        for (int gx = 0; gx < grid_width; ++gx, row += row_size) {
          if (!(row[4] >= min_score)) continue;  // score <= objectness; written so that NaN fails too
          const auto [class_id, class_score] = BestClass(row + 5, classes, 1);
          const float score = row[4] * class_score;
          if (!(score >= min_score)) continue;
          const auto s = static_cast<float>(stride);
          const float w = std::exp(std::min(row[2], kMaxLogSize)) * s;
          const float h = std::exp(std::min(row[3], kMaxLogSize)) * s;
          candidates.push_back({FromCentre((row[0] + gx) * s, (row[1] + gy) * s, w, h), class_id, score});
        }
      }
    }
  } else if (format.layout == YoloLayout::kYolov5) {
    const int row_size = 5 + classes;
    for (int i = 0; i < shape[1]; ++i) {
      const float* row = data + static_cast<std::size_t>(i) * row_size;
      if (!(row[4] >= min_score)) continue;
      const auto [class_id, class_score] = BestClass(row + 5, classes, 1);
      const float score = row[4] * class_score;
      if (!(score >= min_score)) continue;
      candidates.push_back({FromCentre(row[0], row[1], row[2], row[3]), class_id, score});
    }
  } else {
    // YOLOv8: one column per anchor point, rows cx, cy, w, h, class scores. `>=` rejects NaN scores.
    const int anchors = shape[2];
    for (int i = 0; i < anchors; ++i) {
      const float* column = data + i;
      const auto [class_id, score] = BestClass(column + 4 * anchors, classes, anchors);
      if (!(score >= min_score)) continue;
      candidates.push_back(
          {FromCentre(column[0], column[anchors], column[2 * anchors], column[3 * anchors]), class_id, score});
    }
  }
  return candidates;
}

cv::Rect2f LetterboxTransform::ToImage(const cv::Rect2f& box) const {
  return {(box.x - offset.x) / scale, (box.y - offset.y) / scale, box.width / scale, box.height / scale};
}

cv::Mat Letterbox(const cv::Mat& image, cv::Size input, LetterboxPlacement placement, LetterboxTransform& transform) {
  const float scale = std::min(static_cast<float>(input.width) / static_cast<float>(image.cols),
                               static_cast<float>(input.height) / static_cast<float>(image.rows));
  // At least one pixel, so that a sliver of an image still resizes.
  const cv::Size resized_size(std::clamp(static_cast<int>(std::lround(image.cols * scale)), 1, input.width),
                              std::clamp(static_cast<int>(std::lround(image.rows * scale)), 1, input.height));
  cv::Point offset(0, 0);
  if (placement == LetterboxPlacement::kCentre) {
    offset = {(input.width - resized_size.width) / 2, (input.height - resized_size.height) / 2};
  }
  cv::Mat boxed(input, image.type(), cv::Scalar::all(114));
  cv::resize(image, boxed(cv::Rect(offset, resized_size)), resized_size, 0, 0, cv::INTER_LINEAR);
  transform.scale = scale;
  transform.offset = cv::Point2f(static_cast<float>(offset.x), static_cast<float>(offset.y));
  return boxed;
}

std::vector<std::size_t> ClassWiseNms(const std::vector<Candidate>& candidates, float iou_threshold) {
  std::map<int, std::vector<std::size_t>> by_class;
  for (std::size_t i = 0; i < candidates.size(); ++i) by_class[candidates[i].class_id].push_back(i);

  std::vector<std::size_t> kept;
  std::vector<cv::Rect2d> boxes;
  std::vector<float> scores;
  std::vector<int> survivors;
  for (const auto& [class_id, members] : by_class) {
    boxes.clear();
    scores.clear();
    for (const std::size_t i : members) {
      boxes.emplace_back(candidates[i].box);
      scores.push_back(candidates[i].score);
    }
    // No score threshold here (OpenCV keeps scores above 0): DecodeOutput already applied the user's.
    cv::dnn::NMSBoxes(boxes, scores, 0.0F, iou_threshold, survivors);
    for (const int s : survivors) kept.push_back(members[static_cast<std::size_t>(s)]);
  }
  std::stable_sort(kept.begin(), kept.end(),
                   [&candidates](std::size_t a, std::size_t b) { return candidates[a].score > candidates[b].score; });
  return kept;
}

}  // namespace hoidslam::detect
