#pragma once
// An imperfect detector, simulated: ground-truth boxes with misses, jittered boxes, false positives and
// confused classes, so that results can also be given for detectors that are not perfect. All rates default
// to 0 (the detections are the ground truth).

#include <cstdint>
#include <string>
#include <vector>

#include "hoidslam/core/detection.h"

namespace hoidslam::synth {

struct DetectorNoiseOptions {
  double miss_rate = 0.0;             // [0, 1]: chance that a true box is dropped
  double box_jitter = 0.0;            // [0, 1]: std of each box edge's shift, as a fraction of the box size
  double false_positive_rate = 0.0;   // >= 0: mean number of invented boxes per frame
  double class_confusion_rate = 0.0;  // [0, 1]: chance that a true box gets another class's label
  std::uint64_t seed = 0;             // mixed with the scenario seed and the frame index

  bool Any() const;
  // A one-line description for the detections-file header, e.g. "synthetic ground truth" or
  // "synthetic ground truth + noise (miss 0.1, jitter 0.05, false positives 0.2/frame, confusion 0.05)".
  std::string Describe() const;
  // Throws InputError naming the parameter, prefixed with `prefix` ("detector_noise.miss_rate").
  void Check(const std::string& prefix = "detector_noise") const;
};

// The labels detector noise draws from (confusion and false positives): the COCO classes the office holds.
const std::vector<std::string>& SyntheticLabels();

// Applies the noise to `truth` (boxes in an image of `width` x `height`), deterministically from `seed`. With
// no noise configured, returns `truth` unchanged. Noisy boxes are clipped to the image; true boxes keep
// score 1 without noise and get a score in [0.5, 1] with it; false positives score in [0.3, 0.8].
std::vector<core::Detection> ApplyDetectorNoise(const std::vector<core::Detection>& truth,
                                                const DetectorNoiseOptions& options, std::uint64_t seed, int width,
                                                int height);

}  // namespace hoidslam::synth
