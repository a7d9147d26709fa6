#pragma once
// The whole `hoidslam synth` job: simulate a scenario, render every frame of its camera path, add sensor and
// detector noise, and write a sequence in TUM layout with its ground truth:
//
//   <out>/rgb/<t>.png          colour, 640x480, with sensor noise and blur
//   <out>/depth/<t>.png        16-bit depth, 5000 per metre, Kinect-like noise and holes
//   <out>/mask/<t>.png         8-bit, 255 where the pixel belongs to something moving at that instant
//   <out>/people/<t>.png       8-bit, 255 where a person is drawn, moving or not (a still one is static in mask/)
//   <out>/rgb.txt, depth.txt, associations.txt   TUM lists (`%.6f` timestamps)
//   <out>/groundtruth.txt      camera T_wc per frame, TUM format
//   <out>/detections.jsonl     boxes of the visible parts of people and objects (with the detector noise)
//   <out>/detections_truth.jsonl  the clean boxes, written only when detector noise is configured
//   <out>/events.jsonl         who picked up / put down / pushed / sat on what, and when
//   <out>/scenario.json        the scenario as rendered (command-line overrides applied)
//   <out>/static_geometry.ply  triangle mesh (world frame, metres) of the boxes of everything static over the
//                              sequence: not a person, the same parts in every frame (static_geometry.h)
//   <out>/moving_volume.ply    centres of the 0.02 m cells that a person or anything not static filled at a frame
//
// The folder appears complete or not at all: everything goes to a "<out>.partial-<pid>" sibling that is
// renamed at the end. A sequence replaced with `force` is renamed to "<out>.old-<pid>" first and removed once
// the new one is in place (moved back when it cannot be), so `out` always holds one complete sequence. The same
// scenario and seed give byte-identical files whatever the thread count.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "hoidslam/core/detection.h"
#include "hoidslam/synth/camera_path.h"
#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/scene.h"

namespace hoidslam::synth {

struct SynthOptions {
  std::filesystem::path out;           // the sequence folder to create; "seq/" and "seq/." name "seq"; neither
                                       // the working directory nor a folder holding it (replacing removes it)
  bool force = false;                  // replace `out` when it exists and is not empty
  int threads = 2;                     // frames rendered in parallel, in [1, 64]
  std::filesystem::path tum_dir;       // holds groundtruth/<name>.txt and associations/<name>.txt (TUM cameras)
  std::filesystem::path textures_dir;  // optional folder of photos for walls, desks and posters
  bool progress = false;               // report progress on stderr
  // Polled before each frame; when it returns true the job stops, leaves nothing behind and throws
  // core::Interrupted. Empty: never stop.
  std::function<bool()> stop_requested;
  int min_box_pixels = 50;             // smaller visible parts get no ground-truth box, >= 1
  int frame_step = 1;                  // keep every n-th frame of the camera path (quick looks), >= 1

  // Throws InputError naming the parameter ("--out", "--threads", ...).
  void Check() const;
};

struct SynthResult {
  std::size_t frames = 0;
  double seconds = 0.0;  // wall time of the whole job
};

// The scenario's camera path: a TUM path from `tum_dir`, or a procedural one; at most scenario.max_frames.
CameraPath ScenarioCameraPath(const Scenario& scenario, const std::filesystem::path& tum_dir);

// Renders and writes the sequence (see the file comment).
SynthResult WriteSequence(const Scenario& scenario, const SynthOptions& options);

// Ground-truth boxes of the labelled instances in an instance-id image (CV_32S): the bounding box of each
// instance's visible pixels, in pixel-edge coordinates (a pixel (u, v) spans [u, u + 1) x [v, v + 1)), score 1,
// ordered by instance id; instances with fewer than `min_pixels` visible pixels are left out.
std::vector<core::Detection> GroundTruthBoxes(const cv::Mat& instance, const SceneSnapshot& snapshot, int min_pixels);

// 255 where the instance drawn is moving in `snapshot`, else 0 (CV_8U).
cv::Mat MovingMask(const cv::Mat& instance, const SceneSnapshot& snapshot);

// 255 where the instance drawn is a person in `snapshot`, moving or not, else 0 (CV_8U).
cv::Mat PeopleMask(const cv::Mat& instance, const SceneSnapshot& snapshot);

}  // namespace hoidslam::synth
