#include "hoidslam/io/settings.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "hoidslam/core/error.h"

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
constexpr std::array<std::string_view, 15> kHoidPlusKeys = {
    "HOIDplus.depthRefinement", "HOIDplus.depthBin",         "HOIDplus.valley",  "HOIDplus.depthExtent", "HOIDplus.foregroundShare",         "HOIDplus.edgeMargin",
    "HOIDplus.boxMargin",       "HOIDplus.memory",           "HOIDplus.associationIoU", "HOIDplus.relabelIoU",
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
  settings.orb.Check();
  settings.hoid.Check();
}

// What a node holds, for messages about a value of the wrong type.
std::string Describe(const cv::FileNode& node) {
  if (node.isString()) return fmt::format("the text \"{}\"", node.string());
  if (node.isInt()) return fmt::format("the integer {}", static_cast<int>(node));
  if (node.isReal()) return fmt::format("the number {}", node.real());
  if (node.isSeq()) return "a list";
  if (node.isMap()) return "a mapping";
  return "no value";
}

// Overloads that read one value into a field when the key is present, leaving the default otherwise.
void Read(const cv::FileNode& node, const std::string& name, double& value) {
  if (node.empty()) return;
  if (!node.isInt() && !node.isReal()) {
    throw InputError::ForParameter(name, fmt::format("must be a number, found {}", Describe(node)));
  }
  value = node.real();
}

void Read(const cv::FileNode& node, const std::string& name, int& value) {
  if (node.empty()) return;
  if (node.isInt()) {
    value = static_cast<int>(node);
    return;
  }
  // ORB-SLAM3 files sometimes write integers as 1000.0.
  const bool integral = node.isReal() && node.real() == std::floor(node.real()) &&
                        std::abs(node.real()) <= std::numeric_limits<int>::max();
  if (!integral) throw InputError::ForParameter(name, fmt::format("must be an integer, found {}", Describe(node)));
  value = static_cast<int>(node.real());
}

void Read(const cv::FileNode& node, const std::string& name, bool& value) {
  if (node.empty()) return;
  if (!node.isInt() || (static_cast<int>(node) != 0 && static_cast<int>(node) != 1)) {
    throw InputError::ForParameter(name, fmt::format("must be 0 or 1, found {}", Describe(node)));
  }
  value = static_cast<int>(node) == 1;
}

void Read(const cv::FileNode& node, const std::string& name, std::string& value) {
  if (node.empty()) return;
  if (!node.isString()) throw InputError::ForParameter(name, fmt::format("must be a text, found {}", Describe(node)));
  value = node.string();
}

void Read(const cv::FileNode& node, const std::string& name, std::vector<std::string>& value) {
  if (node.empty()) return;
  if (!node.isSeq()) {
    throw InputError::ForParameter(
        name, fmt::format("must be a list of class names such as [person, cup], found {}", Describe(node)));
  }
  std::vector<std::string> names;
  for (const cv::FileNode& item : node) {
    if (!item.isString()) {
      throw InputError::ForParameter(
          name, fmt::format("element {} must be a class name, found {}", names.size() + 1, Describe(item)));
    }
    names.push_back(item.string());
  }
  value = std::move(names);
}

void Read(const cv::FileNode& node, const std::string& name, core::FilterMode& value) {
  std::string text;
  Read(node, name, text);
  if (!node.empty()) value = core::ParseFilterMode(text, name);
}

// Rejects what cv::FileStorage would silently resolve: repeated keys, and typos in our own HOID section.
void CheckKeyNames(const cv::FileNode& root) {
  std::set<std::string> seen;
  for (const cv::FileNode& node : root) {
    const std::string name = node.name();
    if (!seen.insert(name).second) throw InputError::ForParameter(name, "is given more than once");
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
Spelling FileSpelling(const cv::FileNode& root) {
  Spelling spelling = Spelling::kOriginal;
  if (const cv::FileNode version = root["File.version"]; !version.empty()) {
    const bool is_1_0 =
        (version.isString() && version.string() == "1.0") || (version.isReal() && version.real() == 1.0);
    if (!is_1_0) {
      throw InputError::ForParameter("File.version",
                                     fmt::format("only \"1.0\" is supported, found {}", Describe(version)));
    }
    spelling = Spelling::kVersion1;
  }
  const Spelling other = spelling == Spelling::kOriginal ? Spelling::kVersion1 : Spelling::kOriginal;
  for (const Key& key : kSpelledKeys) {
    if (root[key.Name(other)].empty()) continue;
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

Settings ReadSettings(const cv::FileNode& root) {
  CheckKeyNames(root);
  const Spelling spelling = FileSpelling(root);
  const auto read = [&](const std::string& name, auto& field) { Read(root[name], name, field); };
  const auto read_spelled = [&](const Key& key, auto& field) { read(key.Name(spelling), field); };

  if (const cv::FileNode type = root["Camera.type"];
      !type.empty() && !(type.isString() && type.string() == "PinHole")) {
    throw InputError::ForParameter("Camera.type",
                                   fmt::format("only \"PinHole\" cameras are supported, found {}", Describe(type)));
  }
  for (const Key& key : {kFx, kFy, kCx, kCy}) {
    if (root[key.Name(spelling)].empty()) {
      throw InputError::ForParameter(key.Name(spelling), "is required (the camera intrinsics have no default)");
    }
  }

  Settings settings;
  core::CameraIntrinsics& camera = settings.camera;
  read_spelled(kFx, camera.fx);
  read_spelled(kFy, camera.fy);
  read_spelled(kCx, camera.cx);
  read_spelled(kCy, camera.cy);
  read_spelled(kK1, camera.k1);
  read_spelled(kK2, camera.k2);
  read_spelled(kP1, camera.p1);
  read_spelled(kP2, camera.p2);
  read_spelled(kK3, camera.k3);
  read("Camera.width", camera.width);
  read("Camera.height", camera.height);
  read("Camera.fps", settings.fps);
  read("Camera.RGB", settings.rgb_order);
  read_spelled(kDepthMapFactor, settings.depth_map_factor);
  read_spelled(kThDepth, settings.th_depth);
  if (spelling == Spelling::kOriginal) {
    read_spelled(kBf, settings.bf);
  } else if (const std::string name = kBf.Name(spelling); !root[name].empty()) {
    double baseline = 0.0;
    read(name, baseline);
    RequirePositive(name, baseline);
    settings.bf = baseline * camera.fx;
  }

  core::OrbOptions& orb = settings.orb;
  read("ORBextractor.nFeatures", orb.n_features);
  read("ORBextractor.scaleFactor", orb.scale_factor);
  read("ORBextractor.nLevels", orb.n_levels);
  read("ORBextractor.iniThFAST", orb.ini_th_fast);
  read("ORBextractor.minThFAST", orb.min_th_fast);

  core::HoidOptions& hoid = settings.hoid;
  read("HOID.mode", hoid.mode);
  read("HOID.minInteractionArea", hoid.min_interaction_area);
  read("HOID.depthThreshold", hoid.depth_threshold);
  read("HOID.sampleBoxSize", hoid.sample_box_size);
  read("HOID.personClass", hoid.person_class);
  read("HOID.dynamicClasses", hoid.dynamic_classes);
  core::HoidPlusOptions& plus = hoid.plus;
  read("HOIDplus.depthRefinement", plus.depth);
  read("HOIDplus.depthBin", plus.depth_bin);
  read("HOIDplus.valley", plus.valley);
  read("HOIDplus.depthExtent", plus.depth_extent);
  read("HOIDplus.foregroundShare", plus.foreground_share);
  read("HOIDplus.edgeMargin", plus.edge_margin);
  read("HOIDplus.boxMargin", plus.box_margin);
  read("HOIDplus.memory", plus.memory);
  read("HOIDplus.associationIoU", plus.association_iou);
  read("HOIDplus.relabelIoU", plus.relabel_iou);
  read("HOIDplus.maxMissedSeconds", plus.max_missed_seconds);
  read("HOIDplus.stillSeconds", plus.still_seconds);
  read("HOIDplus.stillDistance", plus.still_distance);
  read("HOIDplus.safetyNet", plus.safety_net);
  read("HOIDplus.movingPointOutliers", plus.moving_point_outliers);

  CheckSettings(settings, spelling);
  return settings;
}

// cv::FileStorage reports a syntax error as "<file>(<line>): <what>" in Exception::func.
InputError SyntaxError(const fs::path& path, const cv::Exception& e) {
  const std::string& where = e.func;
  const std::size_t close = where.find("): ");
  const std::size_t open = close == std::string::npos ? std::string::npos : where.rfind('(', close);
  std::size_t line = 0;
  if (open != std::string::npos) {
    const auto [end, error] = std::from_chars(where.data() + open + 1, where.data() + close, line);
    if (error == std::errc() && end == where.data() + close && line > 0) {
      return InputError::AtLine(path, line, "YAML syntax error: " + where.substr(close + 3));
    }
  }
  return InputError::InFile(path, "YAML syntax error: " + where);
}

InputError NotSettingsFile(const fs::path& path) {
  // OpenCV's own wording here ("Input file is invalid", "buf") would not help the user.
  return InputError::InFile(
      path, "not a settings file: it must be YAML beginning with the line %YAML:1.0, as ORB-SLAM3 settings files do");
}

// Checks the file before cv::FileStorage reads it, against crashes and hangs of OpenCV 4.6 that fuzzing found
// (fuzz/regressions/settings). FileStorage also reads XML and JSON, chosen by the first bytes, and its XML
// reader crashes on some malformed files; its YAML reader never returns from some lines with NUL bytes, nor
// from a document marker followed by a list on its line ("--- - a"). Settings files are YAML text with
// `key: value` lines, so none of that is lost.
void CheckIsYamlText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError::InFile(path, "read error");
  if (!text.starts_with("%YAML")) throw NotSettingsFile(path);
  std::size_t line_number = 1;
  for (std::size_t begin = 0; begin < text.size(); ++line_number) {
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    const std::string_view line = std::string_view(text).substr(begin, end - begin);
    if (line.find('\0') != std::string_view::npos) {
      throw InputError::AtLine(path, line_number, "a NUL byte: a settings file is text");
    }
    if (const std::size_t after = line.find_first_not_of(" \t\r", 3);
        line.starts_with("---") && after != std::string_view::npos && line[after] != '#') {
      throw InputError::AtLine(path, line_number, "the document marker --- must stand alone on its line");
    }
    begin = end + 1;
  }
}

}  // namespace

void Settings::Check() const { CheckSettings(*this, Spelling::kOriginal); }

Settings LoadSettings(const std::filesystem::path& path) {
  if (!fs::is_regular_file(path)) throw InputError::InFile(path, "settings file does not exist");
  CheckIsYamlText(path);
  cv::FileStorage storage;
  try {
    storage.open(path.string(), cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    if (e.code == cv::Error::StsParseError) throw SyntaxError(path, e);
    throw NotSettingsFile(path);
  }
  if (!storage.isOpened()) throw InputError::InFile(path, "cannot open for reading");
  const cv::FileNode root = storage.root();
  if (!root.empty() && !root.isMap()) {
    throw InputError::InFile(path, "not a settings file: expected 'key: value' lines at the top level");
  }
  try {
    return ReadSettings(root);
  } catch (const InputError& e) {
    throw InputError::InFile(path, e.what());
  }
}

}  // namespace hoidslam::io
