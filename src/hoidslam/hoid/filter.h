#pragma once
// The HOID interaction filter: decides, for every detection of one frame, whether the features inside its box
// are dynamic (dropped before tracking) or static, and says why. Pure functions of their arguments: no I/O, no
// state, and no heap allocation once the caller's output vectors have grown to size (for depth sample boxes up
// to 64×64 px; larger ones take a temporary buffer).
//
// The rules, per HoidOptions::mode (docs/hoid.md has the full account):
//   none     nothing is dynamic.
//   person   detections labelled options.person_class are dynamic; nothing else is.
//   classes  persons and every detection whose label is in options.dynamic_classes are dynamic.
//   hoid2d   persons are dynamic; an object O of a potentially dynamic class is dynamic when, for some person P,
//            area(O ∩ P) / area(O) >= options.min_interaction_area (the person with the largest ratio is
//            reported). An object with zero area is static.
//   hoid3d   as hoid2d, and an object that passes the 2D rule is dynamic only if the median depth in a
//            sample_box_size² box at the centre of O and at the centre of some interacting P differ by less than
//            options.depth_threshold. When no interacting person's depth agrees but some pair could not be
//            compared (no valid depth pixel in either box, or no depth image), the 2D verdict stands: the object
//            stays dynamic (Reason::kDepthUnavailable). Dropping the features of a possibly handled object costs
//            a few static features; keeping those of a moving one corrupts the pose.
//   hoidplus as hoid2d here; hoid::HoidPlusFilter (hoidplus.h) adds depth, memory and their reasons.
// Objects whose label is not in options.dynamic_classes are static in every mode.

#include <cstdint>
#include <limits>
#include <span>
#include <string_view>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/detection.h"
#include "hoidslam/core/options.h"

namespace hoidslam::hoid {

// Why a detection was judged dynamic or static.
enum class Reason : std::uint8_t {
  kPerson,                 // dynamic: labelled options.person_class (every mode but none)
  kModeKeepsAll,           // static: mode none
  kNotPotentiallyDynamic,  // static: label not in options.dynamic_classes
  kPersonsOnly,            // static: mode person, and this is a potentially dynamic object, not a person
  kClassPrior,             // dynamic: mode classes, label in options.dynamic_classes
  kNoInteraction,          // static: hoid2d/hoid3d, no person overlaps min_interaction_area of the box (or zero area)
  kInteraction,            // dynamic: hoid2d, the 2D rule passed
  kDepthConfirmed,         // dynamic: hoid3d, 2D passed and an interacting person's depth agrees
  kDepthRejected,          // static: hoid3d, 2D passed but every interacting person's depth differs by >= threshold
  kDepthUnavailable,       // dynamic: hoid3d, 2D passed, no depth agrees, and some pair had no valid depth
  kCarried,                // dynamic: hoidplus, a person (or handled object) the detector missed, box carried
  kRecentlyHandled,        // dynamic: hoidplus, an object a person handled, not yet seen still long enough
  kSeenStill,              // static: hoidplus, a handled (or touched) object memory saw still for the set time
  kTooLargeToHandle,       // static: hoidplus, 2D passed but the box, at the object's depth, is larger than anything
                           // of its class a person handles (a desk taken for a laptop)
};

// "person", "mode_keeps_all", "not_potentially_dynamic", ... (snake case of the enumerator, for logs).
std::string_view ToString(Reason reason);

// The verdict on one detection.
struct Decision {
  bool dynamic = false;
  Reason reason = Reason::kModeKeepsAll;
  // The person detection the verdict refers to (index into the detections), -1 if none: for the 2D reasons the
  // person with the largest overlap ratio (also reported for kNoInteraction when some overlap is > 0); for the
  // depth reasons the person whose depth decided (the best-ratio agreeing one for kDepthConfirmed, else the
  // best-ratio one that could not be compared for kDepthUnavailable, else the best-ratio one).
  int person_index = -1;
  // area(O ∩ P) / area(O) with that person; 0 when person_index is -1.
  float interaction_ratio = 0.0F;
  // Mode hoid3d only, NaN otherwise: the median valid depth (metres) in the sample box at this detection's
  // centre, at person_index's centre, and their absolute difference. Only objects that pass the 2D rule and the
  // persons they overlap are sampled; NaN also means the box held no valid pixel.
  float depth = std::numeric_limits<float>::quiet_NaN();
  float person_depth = std::numeric_limits<float>::quiet_NaN();
  float depth_difference = std::numeric_limits<float>::quiet_NaN();
  // Mode hoidplus, for an object that passed the 2D rule and has a foreground depth, NaN otherwise: the longer
  // side of its box in metres at that depth.
  float extent = std::numeric_limits<float>::quiet_NaN();
};

// Classifies every detection; the result has one Decision per detection, in the same order. `depth` is the
// frame's depth image (CV_32FC1, metres, 0 or non-finite = invalid); it is read only in mode hoid3d and may be
// empty (then every 2D interaction is kDepthUnavailable). Throws core::InputError when the options fail Check(),
// std::invalid_argument when a non-empty depth image is not CV_32FC1.
std::vector<Decision> ClassifyDetections(std::span<const core::Detection> detections,
                                         const core::HoidOptions& options, const cv::Mat& depth = {});
// The same, writing into `decisions` (resized to detections.size()) so a per-frame caller reuses its buffer.
void ClassifyDetections(std::span<const core::Detection> detections, const core::HoidOptions& options,
                        const cv::Mat& depth, std::vector<Decision>& decisions);

// A depth value (metres) is valid when it is > 0 and finite. Non-short-circuit `&`: loops over scattered sensor
// holes stay branch-free.
inline bool IsValidDepth(float d) { return (d > 0.0F) & (d < std::numeric_limits<float>::infinity()); }

// Throws std::invalid_argument naming `function` unless `depth` is empty or CV_32FC1 (metres).
void CheckDepthImage(const cv::Mat& depth, std::string_view function);

// The centre of a box, (x + w/2, y + h/2).
inline cv::Point2f BoxCentre(const cv::Rect2f& box) { return {box.x + box.width * 0.5F, box.y + box.height * 0.5F}; }

// Median of the valid (> 0, finite) depths in the size×size pixel box centred on `centre` (pixels
// [floor(centre - size/2), floor(centre - size/2) + size) on each axis), clipped to the image; the mean of the
// two middle values for an even count. NaN when the box holds no valid pixel or `depth` is empty.
// Throws std::invalid_argument unless `depth` is empty or CV_32FC1 and size >= 1.
float SampleDepth(const cv::Mat& depth, cv::Point2f centre, int size);

// keep[i] = 0 when keypoints[i] lies inside the box of a detection whose decision is dynamic, else 1; `keep`
// is resized to keypoints.size(). Inside means box.x <= x < box.x + box.width and box.y <= y < box.y +
// box.height (half-open, as cv::Rect2f::contains). Throws std::invalid_argument unless `decisions` has one entry per
// detection.
void MarkKeypointsToKeep(std::span<const cv::KeyPoint> keypoints, std::span<const core::Detection> detections,
                         std::span<const Decision> decisions, std::vector<std::uint8_t>& keep);
void MarkKeypointsToKeep(std::span<const cv::Point2f> keypoints, std::span<const core::Detection> detections,
                         std::span<const Decision> decisions, std::vector<std::uint8_t>& keep);

}  // namespace hoidslam::hoid
