#pragma once
// Drawings (drawing.h) painted into images with OpenCV, for PNG figures: the same shapes at the same places as
// their SVG, anti-aliased. Text is drawn in OpenCV's own sans-serif stroke font, anchored by its measured width;
// characters outside ASCII are drawn as their nearest ASCII ("×" as "x", "–" as "-"), or as "?".

#include <opencv2/core/mat.hpp>

#include "hoidslam/report/drawing.h"

namespace hoidslam::report {

// An 8-bit BGR image of the drawing's size. Throws std::invalid_argument for a colour that is not "#rrggbb".
cv::Mat RenderImage(const Drawing& drawing);

}  // namespace hoidslam::report
