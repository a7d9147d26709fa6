#pragma once
// HOID's dynamic regions as one mask image per frame, for SLAM systems that take a feature mask instead of
// hoidslam's own tracker (stella_vslam's feed_RGBD_frame, DynaSLAM's mask folder; docs/masks.md).
//
// A mask marks the pixels where `hoidslam run`, with the same options, drops keypoints: the boxes of the
// detections the HOID filter judges dynamic, or, in mode oracle, the sequence's ground-truth moving pixels.
//
// Lookup convention: a keypoint at (x, y) belongs to pixel (floor(x), floor(y)), the pixel whose area
// [c, c + 1) × [r, r + 1) holds it. That is how stella_vslam and DynaSLAM read their masks (they convert the
// float position to int). Rasterisation: a pixel is marked when its centre (c + 0.5, r + 0.5) lies inside a
// dynamic box, inside being half-open as for the keypoints (x0 <= x < x0 + w). So a keypoint is dropped by run
// exactly when its pixel is marked, except a keypoint within 0.5 px of a box edge that falls at a fraction
// of a pixel; with whole-pixel box edges the two agree everywhere. The oracle's masks are copied as they are:
// run looks them up at (round(x), round(y)), so a keypoint with a fraction of 0.5 or more that sits within
// 0.5 px of the edge of a moving region may differ; keypoints found at the pyramid's first level lie on whole
// pixels and never do.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>

#include <opencv2/core/mat.hpp>

#include "hoidslam/core/detection.h"
#include "hoidslam/detect/detector.h"
#include "hoidslam/hoid/filter.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/pipeline/exclusion.h"

namespace hoidslam::pipeline {

// How a mask file encodes its pixels, for the tool that reads it.
enum class MaskFormat {
  kHoidslam,  // 255 dynamic, 0 static: easy to look at
  kStella,    // 0 dynamic, 255 static: stella_vslam extracts no feature where its mask is 0
  kDynaslam,  // 1 dynamic, 0 static: what DynaSLAM's Mask R-CNN stage writes into and reads from its mask folder
};

std::string_view ToString(MaskFormat format);
// "hoidslam", "stella" or "dynaslam"; throws InputError naming `parameter` otherwise.
MaskFormat ParseMaskFormat(std::string_view text, const std::string& parameter = "--format");

// The byte a format writes on dynamic and on static pixels.
struct MaskValues {
  std::uint8_t dynamic = 255;
  std::uint8_t clear = 0;
};
MaskValues ValuesOf(MaskFormat format);

// A `size` CV_8UC1 image, 255 on every pixel whose centre lies inside the box of a detection whose decision is
// dynamic, 0 elsewhere; boxes are clipped to the image and a box with a NaN edge marks nothing (run drops no
// keypoint for it either). Throws std::invalid_argument unless `decisions` has one entry per detection.
cv::Mat PaintDynamicBoxes(std::span<const core::Detection> detections, std::span<const hoid::Decision> decisions,
                          cv::Size size);

// Grows the non-zero regions of `mask` (CV_8UC1) by `pixels` in every direction, a square at a time, so a box
// becomes a box `pixels` wider on each side (clipped to the image). 0 leaves the mask as it is.
void DilateMask(cv::Mat& mask, int pixels);

// `marked` (non-zero = dynamic) in the values of `format`.
cv::Mat EncodeMask(const cv::Mat& marked, MaskFormat format);

struct MaskExportOptions {
  ExclusionOptions exclusion;                 // what is masked: the HOID mode and rules, or oracle
  core::CameraIntrinsics camera;              // the sequence's camera (hoidplus places objects with it)
  MaskFormat format = MaskFormat::kHoidslam;  // --format
  int dilate = 0;                             // --dilate: pixels every masked region grows by, >= 0
  std::size_t max_frames = 0;                 // --frames: 0 for the whole sequence
  std::filesystem::path out;                  // the folder to create (as io::AtomicFolder takes it)
  bool force = false;                         // replace `out` when it exists and is not empty
  // Polled before each frame; when it returns true the export stops, leaves no folder behind and throws
  // core::Interrupted. Empty: never stop.
  std::function<bool()> stop_requested;

  // Throws InputError naming the parameter ("--dilate", or the HOID.* setting).
  void Check() const;
};

struct MaskExportSummary {
  std::size_t frames = 0;
  std::size_t detector_failures = 0;  // frames whose detections could not be had (the previous ones were used)
  double mean_masked_share = 0.0;     // the share of a frame's pixels that are masked, averaged over the frames
};

// Writes options.out: one mask PNG (8-bit, one channel, the frame's size) per frame, named as the frame's
// colour image with the extension .png, and masks.txt, a TUM-style list of `timestamp file` lines (the colour
// image's timestamp, the path relative to the folder). The folder appears complete or not at all. Frames are
// treated as `hoidslam run` treats them: a detector that fails on a frame is logged and the previous frame's
// detections are used. Throws InputError for bad options or input (naming the parameter or file; the same
// errors as run for a missing ground-truth mask folder), and for format dynaslam when a colour image is not
// a PNG (DynaSLAM looks masks up by the colour image's own file name).
MaskExportSummary ExportMasks(const io::RgbdSequence& sequence, detect::Detector& detector,
                              const MaskExportOptions& options);

}  // namespace hoidslam::pipeline
