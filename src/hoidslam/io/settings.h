#pragma once
// Settings files in ORB-SLAM3's format (YAML starting with `%YAML:1.0`, read by settings_yaml.h), plus a
// HOID.* section, so that a user's existing ORB-SLAM3 RGB-D settings file works unchanged.
//
// Both ORB-SLAM3 spellings are read: the original one (Camera.fx, ThDepth, Camera.bf, DepthMapFactor) and the
// one of files that declare `File.version: "1.0"` (Camera1.fx, Stereo.ThDepth, Stereo.b, RGBD.DepthMapFactor).
// docs/settings.md lists every key with its default and range.

#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

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
  // Depth.checkUnits: stop when the first frame's depth is spread as no room is (pipeline/depth_units.h): most
  // likely read with the wrong DepthMapFactor. 0 for a scene that really lies within a metre.
  bool check_depth_units = true;
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

// Every value of `settings` under its key, in the original spelling and in a settings file's order (Camera.fx ...
// HOIDplus.movingPointOutliers): what summary.json records of the settings a run used.
nlohmann::ordered_json SettingsToJson(const Settings& settings);

// The shipped settings file in `config_dir` that a TUM or Bonn sequence folder's name calls for: TUM1.yaml, TUM2 or
// TUM3 for freiburg1/2/3 (or the short fr1_, fr2_, fr3_), Bonn.yaml for bonn; empty for any other name.
std::filesystem::path ShippedSettingsForFolder(const std::filesystem::path& folder,
                                               const std::filesystem::path& config_dir);

// Which settings a run over a sequence uses, and why. One rule for `run`, `bench` and the API: the file given,
// else the shipped file the sequence folder's name calls for, else the defaults (the TUM fr3 camera).
struct SettingsChoice {
  enum class Reason { kGiven, kFolderName, kDefault };

  Settings settings;
  std::filesystem::path file;  // empty: the defaults
  Reason reason = Reason::kDefault;
  std::string folder_name;  // with kFolderName: the name that chose the file

  // For a user: "config/TUM1.yaml (by the sequence folder's name, rgbd_dataset_freiburg1_xyz; --settings to
  // choose another)".
  std::string Describe() const;
};
std::string_view ToString(SettingsChoice::Reason reason);  // given, folder_name, default

// Throws InputError naming the file when the chosen file cannot be read.
SettingsChoice ChooseSettings(const std::filesystem::path& given, const std::filesystem::path& sequence_folder,
                              const std::filesystem::path& config_dir);

}  // namespace hoidslam::io
