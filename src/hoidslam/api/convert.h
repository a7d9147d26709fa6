#pragma once
// Between the public API's plain types (hoidslam.h) and the modules' own: the caller's buffers checked and wrapped
// as cv::Mat, detections, verdicts and poses translated. Every check names the argument it fails on.

#include <span>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "hoidslam/hoidslam.h"
#include "hoidslam/core/detection.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/hoid/hoidplus.h"

namespace hoidslam::api {

// `image` as a CV_8UC3 BGR image of `width` × `height` (0, 0: any size): the caller's buffer itself when it is BGR,
// a converted copy for RGB and grey. Throws InputError naming `name` for a depth format, a null buffer, another
// size or a stride shorter than a row.
cv::Mat ColourMat(const ImageView& image, int width, int height, const std::string& name);
// `depth` as CV_32FC1 metres of `width` × `height`: the caller's buffer itself for float metres, uint16 units
// divided by `depth_factor` (as a recording's depth PNGs are read). Throws InputError naming `name` like ColourMat,
// and for a colour format.
cv::Mat DepthMetres(const ImageView& depth, int width, int height, double depth_factor, const std::string& name);

// Throws InputError naming `name` (and the index) for an empty label, a score outside [0, 1] or a box with a
// negative or non-finite size.
std::vector<core::Detection> ToCoreDetections(std::span<const Detection> detections, const std::string& name);
std::vector<Detection> ToApiDetections(std::span<const core::Detection> detections);
std::vector<JudgedBox> ToJudgedBoxes(const hoid::JudgedBoxes& boxes);
StampedPose ToStampedPose(const core::StampedPose& pose);

}  // namespace hoidslam::api
