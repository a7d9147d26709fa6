#pragma once
// A pose from a frame's matches alone, when no prediction can be trusted: PnP (EPnP) inside RANSAC.

#include "hoidslam/slam/data/frame.h"

namespace hoidslam::slam {

struct PnpRansacOptions {
  int iterations = 300;
  double max_error = 4.0;   // pixels: a match agreeing with a sample's pose reprojects within this
  double confidence = 0.99;

  void Check() const;
};

// Estimates frame.T_cw from the frame's matches and keeps only the matches consistent with it, whose number it
// returns (0, and the frame untouched, when no pose is found). OpenCV's RANSAC draws its samples from its own
// generator, seeded the same on every call: deterministic.
int EstimatePoseRansac(Frame& frame, const PnpRansacOptions& options);

}  // namespace hoidslam::slam
