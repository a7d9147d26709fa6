#include "hoidslam/api/convert.h"

#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/hoid/filter.h"

namespace hoidslam::api {
namespace {

// The caller's buffer as a cv::Mat of `type` (no copy), after checking it against the expected size.
cv::Mat Wrap(const void* data, int width, int height, std::size_t stride, int type, int expected_width,
             int expected_height, const std::string& name) {
  if (data == nullptr) throw InputError::ForParameter(name, "no image data");
  if (width <= 0 || height <= 0) {
    throw InputError::ForParameter(name, fmt::format("size must be positive, got {}x{}", width, height));
  }
  if (expected_width > 0 && (width != expected_width || height != expected_height)) {
    throw InputError::ForParameter(name, fmt::format("is {}x{} but the camera's images are {}x{} (the camera's width "
                                                     "and height, or Camera.width and Camera.height of the settings)",
                                                     width, height, expected_width, expected_height));
  }
  const std::size_t row = static_cast<std::size_t>(width) * CV_ELEM_SIZE(type);
  if (stride == 0) stride = row;
  if (stride < row) {
    throw InputError::ForParameter(name, fmt::format("stride {} bytes is shorter than a row of {} bytes", stride, row));
  }
  return cv::Mat(height, width, type, const_cast<void*>(data), stride);  // read only, never written
}

}  // namespace

cv::Mat ColourMat(const ImageView& image, int width, int height, const std::string& name) {
  switch (image.format) {
    case PixelFormat::kBgr:
      return Wrap(image.data, image.width, image.height, image.stride, CV_8UC3, width, height, name);
    case PixelFormat::kRgb: {
      cv::Mat bgr;
      cv::cvtColor(Wrap(image.data, image.width, image.height, image.stride, CV_8UC3, width, height, name), bgr,
                   cv::COLOR_RGB2BGR);
      return bgr;
    }
    case PixelFormat::kGray: {
      cv::Mat bgr;
      cv::cvtColor(Wrap(image.data, image.width, image.height, image.stride, CV_8UC1, width, height, name), bgr,
                   cv::COLOR_GRAY2BGR);
      return bgr;
    }
    case PixelFormat::kDepthUint16:
    case PixelFormat::kDepthFloat32:
      break;
  }
  throw InputError::ForParameter(name, "must be a colour image (format bgr, rgb or gray), got a depth format");
}

cv::Mat DepthMetres(const ImageView& depth, int width, int height, double depth_factor, const std::string& name) {
  switch (depth.format) {
    case PixelFormat::kDepthFloat32:
      return Wrap(depth.data, depth.width, depth.height, depth.stride, CV_32FC1, width, height, name);
    case PixelFormat::kDepthUint16: {
      cv::Mat metres;
      // As io::RgbdSequence reads a depth PNG: 0 (no measurement) stays 0.
      Wrap(depth.data, depth.width, depth.height, depth.stride, CV_16UC1, width, height, name)
          .convertTo(metres, CV_32F, 1.0 / depth_factor);
      return metres;
    }
    case PixelFormat::kBgr:
    case PixelFormat::kRgb:
    case PixelFormat::kGray:
      break;
  }
  throw InputError::ForParameter(name, "must be a depth image (format depth_uint16 or depth_float32), got a colour "
                                       "format");
}

std::vector<core::Detection> ToCoreDetections(std::span<const Detection> detections, const std::string& name) {
  std::vector<core::Detection> out;
  out.reserve(detections.size());
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    const std::string which = fmt::format("{}[{}]", name, i);
    if (d.label.empty()) throw InputError::ForParameter(which, "has no label");
    if (!(d.score >= 0.0F && d.score <= 1.0F)) {
      throw InputError::ForParameter(which, fmt::format("score must be in [0, 1], got {}", d.score));
    }
    const Box& b = d.box;
    if (!std::isfinite(b.x) || !std::isfinite(b.y) || !(b.width >= 0.0F) || !(b.height >= 0.0F) ||
        !std::isfinite(b.width) || !std::isfinite(b.height)) {
      throw InputError::ForParameter(
          which, fmt::format("box must be finite with a size >= 0, got [{}, {}, {}, {}]", b.x, b.y, b.width, b.height));
    }
    out.push_back({d.class_id, d.label, d.score, cv::Rect2f(b.x, b.y, b.width, b.height)});
  }
  return out;
}

std::vector<Detection> ToApiDetections(std::span<const core::Detection> detections) {
  std::vector<Detection> out;
  out.reserve(detections.size());
  for (const core::Detection& d : detections) {
    out.push_back({d.label, d.score, {d.box.x, d.box.y, d.box.width, d.box.height}, d.class_id});
  }
  return out;
}

std::vector<JudgedBox> ToJudgedBoxes(const hoid::JudgedBoxes& boxes) {
  const std::vector<Detection> detections = ToApiDetections(boxes.detections);
  std::vector<JudgedBox> out;
  out.reserve(detections.size());
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const hoid::Decision& decision = boxes.decisions[i];
    JudgedBox box;
    box.detection = detections[i];
    box.dynamic = decision.dynamic;
    box.reason = hoid::ToString(decision.reason);
    if (decision.person_index != static_cast<int>(i)) {
      box.person = decision.person_index;
      box.interaction = decision.interaction_ratio;
    }
    out.push_back(std::move(box));
  }
  return out;
}

StampedPose ToStampedPose(const core::StampedPose& pose) {
  const Eigen::Vector3d t = pose.T_wc.translation();
  const Eigen::Quaterniond q(pose.T_wc.rotation());
  return {pose.timestamp, {t.x(), t.y(), t.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

}  // namespace hoidslam::api
