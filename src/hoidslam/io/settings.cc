#include "hoidslam/io/settings.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "hoidslam/core/error.h"
#include "hoidslam/io/files.h"
#include "hoidslam/io/settings_yaml.h"

namespace hoidslam::io {
namespace {

namespace fs = std::filesystem;
using core::InputError;

// ORB-SLAM3 spells some keys differently in files that declare `File.version: "1.0"`.
enum class Spelling { kOriginal, kVersion1 };

struct Key {
  std::string_view original;
  std::string_view version1;

  std::string Name(Spelling spelling) const {
    return std::string(spelling == Spelling::kOriginal ? original : version1);
  }
};

constexpr Key kFx{"Camera.fx", "Camera1.fx"};
constexpr Key kFy{"Camera.fy", "Camera1.fy"};
constexpr Key kCx{"Camera.cx", "Camera1.cx"};
constexpr Key kCy{"Camera.cy", "Camera1.cy"};
constexpr Key kK1{"Camera.k1", "Camera1.k1"};
constexpr Key kK2{"Camera.k2", "Camera1.k2"};
constexpr Key kP1{"Camera.p1", "Camera1.p1"};
constexpr Key kP2{"Camera.p2", "Camera1.p2"};
constexpr Key kK3{"Camera.k3", "Camera1.k3"};
constexpr Key kThDepth{"ThDepth", "Stereo.ThDepth"};
constexpr Key kDepthMapFactor{"DepthMapFactor", "RGBD.DepthMapFactor"};
constexpr Key kBf{"Camera.bf", "Stereo.b"};  // Stereo.b is the baseline alone: bf = Stereo.b * fx
constexpr std::array kSpelledKeys = {kFx, kFy, kCx, kCy, kK1, kK2, kP1, kP2, kK3, kThDepth, kDepthMapFactor, kBf};

constexpr std::array<std::string_view, 6> kHoidKeys = {"HOID.mode",           "HOID.minInteractionArea",
                                                       "HOID.depthThreshold", "HOID.sampleBoxSize",
                                                       "HOID.personClass",    "HOID.dynamicClasses"};
constexpr std::array<std::string_view, 16> kHoidPlusKeys = {
    "HOIDplus.depthRefinement", "HOIDplus.depthBin",         "HOIDplus.valley",  "HOIDplus.depthExtent", "HOIDplus.foregroundShare",         "HOIDplus.edgeMargin",
    "HOIDplus.boxMargin",       "HOIDplus.sizeCheck",        "HOIDplus.memory",  "HOIDplus.associationIoU", "HOIDplus.relabelIoU",
    "HOIDplus.maxMissedSeconds", "HOIDplus.stillSeconds",    "HOIDplus.stillDistance",  "HOIDplus.safetyNet",
    "HOIDplus.movingPointOutliers"};

void RequirePositive(const std::string& name, double value) {
  if (!(value > 0.0 && std::isfinite(value))) {
    throw InputError::ForParameter(name, fmt::format("must be > 0, got {}", value));
  }
}

// Settings::Check with the parameter names of the file the settings came from.
void CheckSettings(const Settings& settings, Spelling spelling) {
  const core::CameraIntrinsics& camera = settings.camera;
  RequirePositive(kFx.Name(spelling), camera.fx);
  RequirePositive(kFy.Name(spelling), camera.fy);
  if (camera.width < 1) {
    throw InputError::ForParameter("Camera.width", fmt::format("must be >= 1, got {}", camera.width));
  }
  if (camera.height < 1) {
    throw InputError::ForParameter("Camera.height", fmt::format("must be >= 1, got {}", camera.height));
  }
  // A principal point outside the image means swapped or mistyped values.
  if (!(camera.cx >= 0.0 && camera.cx <= camera.width)) {
    throw InputError::ForParameter(kCx.Name(spelling),
                                   fmt::format("must be in [0, Camera.width={}], got {}", camera.width, camera.cx));
  }
  if (!(camera.cy >= 0.0 && camera.cy <= camera.height)) {
    throw InputError::ForParameter(kCy.Name(spelling),
                                   fmt::format("must be in [0, Camera.height={}], got {}", camera.height, camera.cy));
  }
  for (const auto& [key, value] : {std::pair{kK1, camera.k1}, std::pair{kK2, camera.k2}, std::pair{kP1, camera.p1},
                                   std::pair{kP2, camera.p2}, std::pair{kK3, camera.k3}}) {
    if (!std::isfinite(value)) {
      throw InputError::ForParameter(key.Name(spelling), fmt::format("must be a finite number, got {}", value));
    }
  }
  RequirePositive("Camera.fps", settings.fps);
  RequirePositive(kDepthMapFactor.Name(spelling), settings.depth_map_factor);
  RequirePositive(kThDepth.Name(spelling), settings.th_depth);
  // Files of version 1.0 give Stereo.b, which is checked where it is read.
  RequirePositive(kBf.Name(Spelling::kOriginal), settings.bf);
  RequirePositive("Depth.noiseFactor", settings.depth_noise.factor);
  settings.orb.Check();
  settings.hoid.Check();
}

// What a value holds, for messages about a value of the wrong type.
std::string Describe(const yaml::Value& value) {
  switch (value.kind) {
    case yaml::Value::Kind::kText: return fmt::format("the text \"{}\"", value.text);
    case yaml::Value::Kind::kInteger: return fmt::format("the integer {}", value.integer);
    case yaml::Value::Kind::kReal: return fmt::format("the number {}", value.real);
    case yaml::Value::Kind::kList: return "a list";
    case yaml::Value::Kind::kMapping: return "a mapping";
    case yaml::Value::Kind::kNone: break;
  }
  return "no value";
}

bool IsNumber(const yaml::Value& value) {
  return value.kind == yaml::Value::Kind::kInteger || value.kind == yaml::Value::Kind::kReal;
}

// Overloads that read one value into a field when the key is present (`value` is not null), leaving the default
// otherwise.
void Read(const yaml::Value* value, const std::string& name, double& field) {
  if (value == nullptr) return;
  if (!IsNumber(*value)) {
    throw InputError::ForParameter(name, fmt::format("must be a number, found {}", Describe(*value)));
  }
  field = value->real;
}

void Read(const yaml::Value* value, const std::string& name, int& field) {
  if (value == nullptr) return;
  // ORB-SLAM3 files sometimes write integers as 1000.0.
  if (!IsNumber(*value) || value->real != std::floor(value->real)) {
    throw InputError::ForParameter(name, fmt::format("must be an integer, found {}", Describe(*value)));
  }
  if (std::abs(value->real) > std::numeric_limits<int>::max()) {
    constexpr int kLargest = std::numeric_limits<int>::max();
    throw InputError::ForParameter(
        name, fmt::format("must be an integer from -{} to {}, found {}", kLargest, kLargest, Describe(*value)));
  }
  field = static_cast<int>(value->real);
}

void Read(const yaml::Value* value, const std::string& name, bool& field) {
  if (value == nullptr) return;
  if (!IsNumber(*value) || (value->real != 0.0 && value->real != 1.0)) {
    throw InputError::ForParameter(name, fmt::format("must be 0 or 1, found {}", Describe(*value)));
  }
  field = value->real == 1.0;
}

void Read(const yaml::Value* value, const std::string& name, std::string& field) {
  if (value == nullptr) return;
  if (value->kind != yaml::Value::Kind::kText) {
    throw InputError::ForParameter(name, fmt::format("must be a text, found {}", Describe(*value)));
  }
  field = value->text;
}

void Read(const yaml::Value* value, const std::string& name, std::vector<std::string>& field) {
  if (value == nullptr) return;
  if (value->kind != yaml::Value::Kind::kList) {
    throw InputError::ForParameter(
        name, fmt::format("must be a list of class names such as [person, cup], found {}", Describe(*value)));
  }
  std::vector<std::string> names;
  for (const yaml::Value& item : value->items) {
    if (item.kind != yaml::Value::Kind::kText) {
      throw InputError::ForParameter(
          name, fmt::format("element {} must be a class name, found {}", names.size() + 1, Describe(item)));
    }
    names.push_back(item.text);
  }
  field = std::move(names);
}

void Read(const yaml::Value* value, const std::string& name, core::FilterMode& field) {
  std::string text;
  Read(value, name, text);
  if (value != nullptr) field = core::ParseFilterMode(text, name);
}

// Rejects typos in our own HOID sections, whose keys would otherwise be ignored without a word. (Repeated keys
// are refused by the YAML reader.)
void CheckHoidKeyNames(const yaml::Value& root) {
  for (const yaml::Entry& entry : root.entries) {
    const std::string& name = entry.key;
    if (name.starts_with("HOID.") && std::find(kHoidKeys.begin(), kHoidKeys.end(), name) == kHoidKeys.end()) {
      throw InputError::ForParameter(name,
                                     fmt::format("unknown key (the HOID section has {})", fmt::join(kHoidKeys, ", ")));
    }
    if (name.starts_with("HOIDplus.") &&
        std::find(kHoidPlusKeys.begin(), kHoidPlusKeys.end(), name) == kHoidPlusKeys.end()) {
      throw InputError::ForParameter(
          name, fmt::format("unknown key (the HOIDplus section has {})", fmt::join(kHoidPlusKeys, ", ")));
    }
  }
}

// The spelling the file declares, after making sure it does not mix in keys of the other one (they would be
// ignored, and their defaults used without a word).
Spelling FileSpelling(const yaml::Value& root) {
  Spelling spelling = Spelling::kOriginal;
  if (const yaml::Value* version = root.Find("File.version")) {
    const bool is_1_0 = (version->kind == yaml::Value::Kind::kText && version->text == "1.0") ||
                        (version->kind == yaml::Value::Kind::kReal && version->real == 1.0);
    if (!is_1_0) {
      throw InputError::ForParameter("File.version",
                                     fmt::format("only \"1.0\" is supported, found {}", Describe(*version)));
    }
    spelling = Spelling::kVersion1;
  }
  const Spelling other = spelling == Spelling::kOriginal ? Spelling::kVersion1 : Spelling::kOriginal;
  for (const Key& key : kSpelledKeys) {
    if (root.Find(key.Name(other)) == nullptr) continue;
    throw InputError::ForParameter(
        key.Name(other),
        spelling == Spelling::kOriginal
            ? fmt::format("is read only in files with File.version: \"1.0\"; add that line, or "
                          "write {}",
                          key.Name(spelling))
            : fmt::format("is not read in files with File.version: \"1.0\"; write {}", key.Name(spelling)));
  }
  return spelling;
}

// Every key of a settings file but the camera model, the four required intrinsics and the baseline (whose
// spellings differ in more than the name), with its field, in the order of a settings file: reading a file and
// writing what a run used go through this one list. `SettingsT` is Settings or const Settings.
template <typename SettingsT, typename Visit>
void ForEachOptionalKey(SettingsT& settings, Spelling spelling, Visit visit) {
  const auto spelled = [&](const Key& key, auto& field) { visit(key.Name(spelling), field); };
  auto& camera = settings.camera;
  spelled(kK1, camera.k1);
  spelled(kK2, camera.k2);
  spelled(kP1, camera.p1);
  spelled(kP2, camera.p2);
  spelled(kK3, camera.k3);
  visit("Camera.width", camera.width);
  visit("Camera.height", camera.height);
  visit("Camera.fps", settings.fps);
  visit("Camera.RGB", settings.rgb_order);
  spelled(kDepthMapFactor, settings.depth_map_factor);
  spelled(kThDepth, settings.th_depth);
  visit("Depth.noiseFactor", settings.depth_noise.factor);
  visit("Depth.checkUnits", settings.check_depth_units);

  auto& orb = settings.orb;
  visit("ORBextractor.nFeatures", orb.n_features);
  visit("ORBextractor.scaleFactor", orb.scale_factor);
  visit("ORBextractor.nLevels", orb.n_levels);
  visit("ORBextractor.iniThFAST", orb.ini_th_fast);
  visit("ORBextractor.minThFAST", orb.min_th_fast);
  visit("ORBextractor.dimMean", orb.dim_mean);
  visit("ORBextractor.maxGain", orb.max_gain);

  auto& hoid = settings.hoid;
  visit("HOID.mode", hoid.mode);
  visit("HOID.minInteractionArea", hoid.min_interaction_area);
  visit("HOID.depthThreshold", hoid.depth_threshold);
  visit("HOID.sampleBoxSize", hoid.sample_box_size);
  visit("HOID.personClass", hoid.person_class);
  visit("HOID.dynamicClasses", hoid.dynamic_classes);
  auto& plus = hoid.plus;
  visit("HOIDplus.depthRefinement", plus.depth);
  visit("HOIDplus.depthBin", plus.depth_bin);
  visit("HOIDplus.valley", plus.valley);
  visit("HOIDplus.depthExtent", plus.depth_extent);
  visit("HOIDplus.foregroundShare", plus.foreground_share);
  visit("HOIDplus.edgeMargin", plus.edge_margin);
  visit("HOIDplus.boxMargin", plus.box_margin);
  visit("HOIDplus.memory", plus.memory);
  visit("HOIDplus.associationIoU", plus.association_iou);
  visit("HOIDplus.relabelIoU", plus.relabel_iou);
  visit("HOIDplus.maxMissedSeconds", plus.max_missed_seconds);
  visit("HOIDplus.stillSeconds", plus.still_seconds);
  visit("HOIDplus.stillDistance", plus.still_distance);
  visit("HOIDplus.safetyNet", plus.safety_net);
  visit("HOIDplus.sizeCheck", plus.size_check);
  visit("HOIDplus.movingPointOutliers", plus.moving_point_outliers);
}

Settings ReadSettings(const yaml::Value& root) {
  CheckHoidKeyNames(root);
  const Spelling spelling = FileSpelling(root);
  const auto read = [&](const std::string& name, auto& field) { Read(root.Find(name), name, field); };

  if (const yaml::Value* type = root.Find("Camera.type");
      type != nullptr && !(type->kind == yaml::Value::Kind::kText && type->text == "PinHole")) {
    throw InputError::ForParameter("Camera.type",
                                   fmt::format("only \"PinHole\" cameras are supported, found {}", Describe(*type)));
  }
  for (const Key& key : {kFx, kFy, kCx, kCy}) {
    if (root.Find(key.Name(spelling)) == nullptr) {
      throw InputError::ForParameter(key.Name(spelling), "is required (the camera intrinsics have no default)");
    }
  }

  Settings settings;
  core::CameraIntrinsics& camera = settings.camera;
  read(kFx.Name(spelling), camera.fx);
  read(kFy.Name(spelling), camera.fy);
  read(kCx.Name(spelling), camera.cx);
  read(kCy.Name(spelling), camera.cy);
  ForEachOptionalKey(settings, spelling, read);
  if (spelling == Spelling::kOriginal) {
    read(kBf.Name(spelling), settings.bf);
  } else if (const std::string name = kBf.Name(spelling); root.Find(name) != nullptr) {
    double baseline = 0.0;
    read(name, baseline);
    RequirePositive(name, baseline);
    settings.bf = baseline * camera.fx;
  }
  CheckSettings(settings, spelling);
  return settings;
}

}  // namespace

void Settings::Check() const { CheckSettings(*this, Spelling::kOriginal); }

nlohmann::ordered_json SettingsToJson(const Settings& settings) {
  nlohmann::ordered_json json;
  const core::CameraIntrinsics& camera = settings.camera;
  for (const auto& [key, value] : {std::pair{kFx, camera.fx}, std::pair{kFy, camera.fy}, std::pair{kCx, camera.cx},
                                   std::pair{kCy, camera.cy}, std::pair{kBf, settings.bf}}) {
    json[key.Name(Spelling::kOriginal)] = value;
  }
  ForEachOptionalKey(settings, Spelling::kOriginal, [&json](const std::string& name, const auto& field) {
    if constexpr (std::is_same_v<std::decay_t<decltype(field)>, core::FilterMode>) {
      json[name] = core::ToString(field);
    } else {
      json[name] = field;
    }
  });
  return json;
}

fs::path ShippedSettingsForFolder(const fs::path& folder, const fs::path& config_dir) {
  std::string name = NormalFolder(folder).filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  // TUM names its downloads rgbd_dataset_freiburg1_rpy; the shared recordings and many users shorten it to fr1_rpy.
  for (const auto& [key, file] : {std::pair{"freiburg1", "TUM1.yaml"}, std::pair{"freiburg2", "TUM2.yaml"},
                                  std::pair{"freiburg3", "TUM3.yaml"}, std::pair{"fr1_", "TUM1.yaml"},
                                  std::pair{"fr2_", "TUM2.yaml"}, std::pair{"fr3_", "TUM3.yaml"},
                                  std::pair{"bonn", "Bonn.yaml"}}) {
    if (name.find(key) != std::string::npos && fs::exists(config_dir / file)) return config_dir / file;
  }
  return {};
}

std::string SettingsChoice::Describe() const {
  switch (reason) {
    case Reason::kGiven: return file.string();
    case Reason::kFolderName:
      return fmt::format("{} (by the sequence folder's name, {}; --settings to choose another)", file.string(),
                         folder_name);
    case Reason::kDefault: break;
  }
  return "the defaults: the TUM fr3 camera, 640x480, depth 5000 units a metre (--settings to give your camera's)";
}

std::string_view ToString(SettingsChoice::Reason reason) {
  switch (reason) {
    case SettingsChoice::Reason::kGiven: return "given";
    case SettingsChoice::Reason::kFolderName: return "folder_name";
    case SettingsChoice::Reason::kDefault: break;
  }
  return "default";
}

SettingsChoice ChooseSettings(const fs::path& given, const fs::path& sequence_folder, const fs::path& config_dir) {
  SettingsChoice choice;
  if (!given.empty()) {
    choice.file = given;
    choice.reason = SettingsChoice::Reason::kGiven;
  } else if (!sequence_folder.empty()) {
    choice.file = ShippedSettingsForFolder(sequence_folder, config_dir);
    if (!choice.file.empty()) {
      choice.reason = SettingsChoice::Reason::kFolderName;
      choice.folder_name = NormalFolder(sequence_folder).filename().string();
    }
  }
  if (!choice.file.empty()) choice.settings = LoadSettings(choice.file);
  return choice;
}

Settings LoadSettings(const std::filesystem::path& path) {
  if (!fs::is_regular_file(path)) throw InputError::InFile(path, "settings file does not exist");
  // A settings file is a few kB; anything far larger is the wrong file, and is not read into memory.
  constexpr std::uintmax_t kMaxBytes = 1 << 20;
  std::error_code error;
  const std::uintmax_t bytes = fs::file_size(path, error);
  if (error) throw InputError::InFile(path, "cannot read: " + error.message());
  if (bytes > kMaxBytes) {
    throw InputError::InFile(path, fmt::format("not a settings file: {} bytes (settings files are a few kB)", bytes));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError::InFile(path, "cannot open for reading");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError::InFile(path, "read error");
  const yaml::Value root = yaml::Parse(text, path);
  try {
    return ReadSettings(root);
  } catch (const InputError& e) {
    throw InputError::InFile(path, e.what());
  }
}

}  // namespace hoidslam::io
