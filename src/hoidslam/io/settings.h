#pragma once
// Settings files in ORB-SLAM3's format (YAML starting with `%YAML:1.0`, read by settings_yaml.h), plus a
// HOID.* section, so that a user's existing ORB-SLAM3 RGB-D settings file works unchanged.
//
// Both ORB-SLAM3 spellings are read: the original one (Camera.fx, ThDepth, Camera.bf, DepthMapFactor) and the
// one of files that declare `File.version: "1.0"` (Camera1.fx, Stereo.ThDepth, Stereo.b, RGBD.DepthMapFactor).
// docs/settings.md lists every key with its default and range.

#include <filesystem>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/options.h"

namespace hoidslam::io {

struct Settings {
  // Camera.fx, fy, cx, cy (required in a file; > 0, principal point inside the image), Camera.k1, k2, p1, p2, k3
  // (default 0), Camera.width, Camera.height (default 640x480).
  core::CameraIntrinsics camera;
  double fps = 30.0;                 // Camera.fps: frames per second, > 0
  double depth_map_factor = 5000.0;  // DepthMapFactor: depth image units per metre (TUM, Bonn: 5000), > 0
  double th_depth = 40.0;            // ThDepth: the close/far depth threshold, in baselines, > 0
  double bf = 40.0;                  // Camera.bf: baseline (metres) times fx (pixels), > 0
  core::DepthNoiseModel depth_noise;  // Depth.noiseFactor: its factor, > 0 (the final map adjustment's depth weight)
  // Camera.RGB: the images' colour order as ORB-SLAM3 states it (1: RGB, 0: BGR). hoidslam reads images with
  // OpenCV, which always yields BGR, so the key is kept for compatibility and changes nothing.
  bool rgb_order = true;
  core::OrbOptions orb;    // ORBextractor.*
  core::HoidOptions hoid;  // HOID.*

  // Depth (metres) below which a point counts as close, as in ORB-SLAM3: ThDepth * bf / fx, i.e. ThDepth
  // baselines (40 * 40 / 535.4 = 2.99 m with the defaults).
  double CloseDepthThreshold() const { return th_depth * bf / camera.fx; }

  // Throws InputError naming the parameter (e.g. "Camera.fx") when a value is out of range.
  void Check() const;
};

// Reads and checks a settings file. Keys that are absent take the defaults above, except the four required
// Camera intrinsics. Throws InputError naming the file, with the line for what the YAML reader refuses (a syntax
// error, a repeated key), and the parameter for a value of the wrong type or out of range:
// "config/TUM3.yaml: parameter Camera.fx: must be > 0, got -1".
Settings LoadSettings(const std::filesystem::path& path);

}  // namespace hoidslam::io
