#pragma once
// OpenCV overloads beside the public API (hoidslam.h): cv::Mat in, viewed without a copy. Header-only, so that
// libhoidslam asks no OpenCV of a program that passes raw buffers; a program that includes this links OpenCV's
// core itself.

#include <span>
#include <string>

#include <opencv2/core/mat.hpp>

#include "hoidslam/hoidslam.h"

namespace hoidslam {

// A colour image as a view: CV_8UC3 in the channel order `colour` says (BGR, as cv::imread gives it, by default),
// CV_8UC1 as grey. Throws InputError naming `name` for another type.
inline ImageView ToImageView(const cv::Mat& image, PixelFormat colour = PixelFormat::kBgr,
                             const std::string& name = "rgb") {
  if (image.type() == CV_8UC1) return {image.data, image.cols, image.rows, image.step[0], PixelFormat::kGray};
  if (image.type() != CV_8UC3 || colour == PixelFormat::kGray) {
    throw InputError::ForParameter(name, "must be CV_8UC3 colour (" +
                                             std::string(colour == PixelFormat::kRgb ? "RGB" : "BGR") +
                                             ") or CV_8UC1 grey, got type " + std::to_string(image.type()));
  }
  return {image.data, image.cols, image.rows, image.step[0], colour};
}

// A depth image as a view: CV_16UC1 in units of 1 / DepthMapFactor metres (a depth PNG as cv::IMREAD_UNCHANGED
// reads it), CV_32FC1 in metres. Throws InputError naming `name` for another type.
inline ImageView ToDepthView(const cv::Mat& depth, const std::string& name = "depth") {
  if (depth.type() == CV_16UC1) return {depth.data, depth.cols, depth.rows, depth.step[0], PixelFormat::kDepthUint16};
  if (depth.type() == CV_32FC1) return {depth.data, depth.cols, depth.rows, depth.step[0], PixelFormat::kDepthFloat32};
  throw InputError::ForParameter(name, "must be CV_16UC1 (depth units) or CV_32FC1 (metres), got type " +
                                           std::to_string(depth.type()));
}

// System::Track with OpenCV images.
inline FrameResult Track(System& system, const cv::Mat& rgb, const cv::Mat& depth, double timestamp,
                         std::span<const Detection> detections = {}, PixelFormat colour = PixelFormat::kBgr,
                         double depth_delay = 0.0) {
  return system.Track(ToImageView(rgb, colour), ToDepthView(depth), timestamp, detections, depth_delay);
}

}  // namespace hoidslam
