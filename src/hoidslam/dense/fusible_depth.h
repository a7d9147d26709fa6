#pragma once
// Which depth measurements of a keyframe may enter the static map: none on what the filter judged dynamic (the
// region grown by a margin), none the sensor model does not trust (out of range, on a depth edge).

#include <opencv2/core/mat.hpp>

#include "hoidslam/dense/dense_options.h"

namespace hoidslam::dense {

// `depth` (CV_32FC1, metres, 0 or non-finite = none) with 0 wherever a measurement is left out: where `dropped`
// (CV_8UC1, non-zero = dynamic; empty: nothing) or its growth by options.mask_margin pixels is marked, nearer than
// options.min_depth, and where the 3×3 neighbourhood's depths span more than options.depth_edge of the pixel's own
// (a depth edge). Depth beyond options.max_depth stays: the volume does not fuse it (TsdfVolume::Integrate), the
// occupancy map takes its ray as free space up to max_depth (OccupancyMap::InsertDepth). Throws
// std::invalid_argument for images of another type or size.
cv::Mat FusibleDepth(const cv::Mat& depth, const cv::Mat& dropped, const DenseOptions& options);

}  // namespace hoidslam::dense
