#pragma once
// How much of the people a dense map kept, judged without ground truth (docs/dense.md): in the frames it was fused
// from, the pixels of each person box at the person's own depth, and of them those where the map has surface at the
// depth the camera measured there. A map with the people left out has surface there only where something static
// stands at the person's depth (a chair, the floor at their feet); a map with the people fused has it on the people.

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <nlohmann/json.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"

namespace hoidslam::eval {

struct PersonSurfaceOptions {
  double person_band = 0.4;       // m: a box's pixel this near the person's depth is the person's
  double core_fraction = 0.5;     // the middle of the box, this share of its width and height, gives that depth
  double depth_tolerance = 0.05;  // m: map surface this near the depth measured at a pixel is what the camera saw
};

// One person box of a frame the map was fused from.
struct PersonView {
  core::Pose T_wc;  // the frame's pose in the map's frame
  cv::Rect box;     // pixels, inside the image
  cv::Mat depth;    // CV_32FC1, metres, 0 = none: the frame's measured depth inside `box` (box.size())
};

struct PersonSurface {
  std::size_t boxes = 0;          // boxes judged (with measured depth in their middle)
  std::size_t person_pixels = 0;  // their pixels at the person's depth
  std::size_t fused_pixels = 0;   // of those, where the map has surface at the measured depth
  double Share() const {
    return person_pixels > 0 ? static_cast<double>(fused_pixels) / static_cast<double>(person_pixels) : 0.0;
  }
};

// `vertices` are the map's surface samples (a mesh's vertices) about `spacing` m apart, in the frame of the views'
// poses; each stands for the pixels it covers at its depth.
PersonSurface MeasurePersonSurface(const std::vector<Eigen::Vector3f>& vertices, double spacing,
                                   const std::vector<PersonView>& views, const core::CameraIntrinsics& camera,
                                   const PersonSurfaceOptions& options = {});

nlohmann::json PersonSurfaceJson(const PersonSurface& surface, const PersonSurfaceOptions& options);

}  // namespace hoidslam::eval
