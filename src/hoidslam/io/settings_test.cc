#include "hoidslam/io/settings.h"

#include <cctype>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"

namespace hoidslam::io {
namespace {

namespace fs = std::filesystem;
using core::InputError;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

using Lines = std::vector<std::pair<std::string, std::string>>;  // key, value

// A minimal settings file in the original ORB-SLAM3 spelling, without a HOID section.
Lines MinimalOriginal() {
  return {{"Camera.fx", "535.4"}, {"Camera.fy", "539.2"}, {"Camera.cx", "320.1"}, {"Camera.cy", "247.6"}};
}

// `lines` with `key` set to `value` (replaced in place when present, else appended).
Lines With(Lines lines, const std::string& key, const std::string& value) {
  for (auto& [k, v] : lines) {
    if (k == key) {
      v = value;
      return lines;
    }
  }
  lines.emplace_back(key, value);
  return lines;
}

class SettingsFile : public ::testing::Test {
 protected:
  fs::path Write(const std::string& text, const std::string& name = "settings.yaml") {
    const fs::path path = scratch_ / name;
    std::ofstream(path) << text;
    return path;
  }
  fs::path Write(const Lines& lines) {
    std::string text = "%YAML:1.0\n# test settings\n";
    for (const auto& [key, value] : lines) text += key + ": " + value + "\n";
    return Write(text);
  }
  testing::TempDir scratch_;
};

TEST_F(SettingsFile, EveryShippedConfigLoadsAndPassesCheck) {
  std::size_t files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(HOIDSLAM_CONFIG_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(LoadSettings(entry.path()).Check());
    ++files;
  }
  EXPECT_GE(files, 4U);
  for (const char* name : {"TUM1.yaml", "TUM2.yaml", "TUM3.yaml", "Bonn.yaml"}) {
    SCOPED_TRACE(name);
    const Settings settings = LoadSettings(fs::path(HOIDSLAM_CONFIG_DIR) / name);
    EXPECT_EQ(settings.camera.width, 640);
    EXPECT_EQ(settings.camera.height, 480);
    EXPECT_DOUBLE_EQ(settings.fps, 30.0);
    EXPECT_EQ(settings.orb.n_features, 1000);
    EXPECT_EQ(settings.hoid.mode, core::FilterMode::kHoidPlus);
    EXPECT_EQ(settings.hoid.dynamic_classes, core::HoidOptions{}.dynamic_classes);
  }
  const Settings fr1 = LoadSettings(fs::path(HOIDSLAM_CONFIG_DIR) / "TUM1.yaml");
  EXPECT_DOUBLE_EQ(fr1.camera.fx, 517.306408);
  EXPECT_DOUBLE_EQ(fr1.camera.k3, 1.163314);
  const Settings fr2 = LoadSettings(fs::path(HOIDSLAM_CONFIG_DIR) / "TUM2.yaml");
  EXPECT_DOUBLE_EQ(fr2.depth_map_factor, 5208.0);
  EXPECT_DOUBLE_EQ(fr2.camera.p2, -0.000105);
  const Settings fr3 = LoadSettings(fs::path(HOIDSLAM_CONFIG_DIR) / "TUM3.yaml");
  EXPECT_DOUBLE_EQ(fr3.camera.cy, 247.6);
  EXPECT_FALSE(fr3.camera.HasDistortion());
  EXPECT_NEAR(fr3.CloseDepthThreshold(), 40.0 * 40.0 / 535.4, 1e-12);
  const Settings bonn = LoadSettings(fs::path(HOIDSLAM_CONFIG_DIR) / "Bonn.yaml");
  EXPECT_DOUBLE_EQ(bonn.camera.fx, 542.822841);
  EXPECT_DOUBLE_EQ(bonn.camera.k2, -0.099343);
}

TEST_F(SettingsFile, MissingOptionalKeysAndHoidSectionTakeTheDefaults) {
  const Settings settings = LoadSettings(Write(MinimalOriginal()));
  const Settings defaults;
  EXPECT_EQ(settings.camera.width, 640);
  EXPECT_EQ(settings.camera.height, 480);
  EXPECT_FALSE(settings.camera.HasDistortion());
  EXPECT_DOUBLE_EQ(settings.fps, defaults.fps);
  EXPECT_DOUBLE_EQ(settings.depth_map_factor, 5000.0);
  EXPECT_DOUBLE_EQ(settings.th_depth, 40.0);
  EXPECT_DOUBLE_EQ(settings.bf, 40.0);
  EXPECT_DOUBLE_EQ(settings.depth_noise.factor, 2.0);
  EXPECT_TRUE(settings.rgb_order);
  EXPECT_EQ(settings.orb.n_levels, defaults.orb.n_levels);
  EXPECT_EQ(settings.hoid.mode, defaults.hoid.mode);
  EXPECT_DOUBLE_EQ(settings.hoid.min_interaction_area, 0.4);
  EXPECT_DOUBLE_EQ(settings.hoid.depth_threshold, 0.2);
  EXPECT_EQ(settings.hoid.sample_box_size, 20);
  EXPECT_EQ(settings.hoid.person_class, "person");
  EXPECT_EQ(settings.hoid.dynamic_classes, defaults.hoid.dynamic_classes);
}

TEST_F(SettingsFile, ReadsEveryKeyOfTheOriginalSpellingAndTheHoidSection) {
  const Settings settings = LoadSettings(Write(
      "%YAML:1.0\nCamera.fx: 500.0\nCamera.fy: 501.0\nCamera.cx: 330.0\nCamera.cy: 250.0\nCamera.k1: 0.1\n"
      "Camera.k2: -0.2\nCamera.p1: 0.003\nCamera.p2: -0.004\nCamera.k3: 0.5\nCamera.width: 752\nCamera.height: 560\n"
      "Camera.fps: 15\nCamera.RGB: 0\nCamera.bf: 50.0\nThDepth: 35.0\nDepthMapFactor: 1000.0\nDepth.noiseFactor: 3.0\n"
      "ORBextractor.nFeatures: 1500.0\nORBextractor.scaleFactor: 1.3\nORBextractor.nLevels: 6\n"
      "ORBextractor.iniThFAST: 25\nORBextractor.minThFAST: 9\n"
      "HOID.mode: \"hoid3d\"\nHOID.minInteractionArea: 0.3\nHOID.depthThreshold: 0.25\nHOID.sampleBoxSize: 16\n"
      "HOID.personClass: human\nHOID.dynamicClasses:\n  - cup\n  - \"cell phone\"\n"
      "Viewer.KeyFrameSize: 0.05\n"));  // keys hoidslam does not use are ignored
  const core::CameraIntrinsics& c = settings.camera;
  EXPECT_DOUBLE_EQ(c.fx, 500.0);
  EXPECT_DOUBLE_EQ(c.fy, 501.0);
  EXPECT_DOUBLE_EQ(c.cx, 330.0);
  EXPECT_DOUBLE_EQ(c.cy, 250.0);
  EXPECT_DOUBLE_EQ(c.k1, 0.1);
  EXPECT_DOUBLE_EQ(c.k2, -0.2);
  EXPECT_DOUBLE_EQ(c.p1, 0.003);
  EXPECT_DOUBLE_EQ(c.p2, -0.004);
  EXPECT_DOUBLE_EQ(c.k3, 0.5);
  EXPECT_EQ(c.width, 752);
  EXPECT_EQ(c.height, 560);
  EXPECT_DOUBLE_EQ(settings.fps, 15.0);
  EXPECT_FALSE(settings.rgb_order);
  EXPECT_DOUBLE_EQ(settings.bf, 50.0);
  EXPECT_DOUBLE_EQ(settings.th_depth, 35.0);
  EXPECT_DOUBLE_EQ(settings.depth_map_factor, 1000.0);
  EXPECT_DOUBLE_EQ(settings.depth_noise.factor, 3.0);
  EXPECT_DOUBLE_EQ(settings.CloseDepthThreshold(), 35.0 * 50.0 / 500.0);
  EXPECT_EQ(settings.orb.n_features, 1500);
  EXPECT_DOUBLE_EQ(settings.orb.scale_factor, 1.3);
  EXPECT_EQ(settings.orb.n_levels, 6);
  EXPECT_EQ(settings.orb.ini_th_fast, 25);
  EXPECT_EQ(settings.orb.min_th_fast, 9);
  EXPECT_EQ(settings.hoid.mode, core::FilterMode::kHoid3d);
  EXPECT_DOUBLE_EQ(settings.hoid.min_interaction_area, 0.3);
  EXPECT_DOUBLE_EQ(settings.hoid.depth_threshold, 0.25);
  EXPECT_EQ(settings.hoid.sample_box_size, 16);
  EXPECT_EQ(settings.hoid.person_class, "human");
  EXPECT_THAT(settings.hoid.dynamic_classes, ElementsAre("cup", "cell phone"));
}

TEST_F(SettingsFile, ReadsOrbSlam3Version1Files) {
  const Settings settings = LoadSettings(Write(
      "%YAML:1.0\nFile.version: \"1.0\"\nCamera.type: \"PinHole\"\nCamera1.fx: 517.306408\nCamera1.fy: 516.469215\n"
      "Camera1.cx: 318.643040\nCamera1.cy: 255.313989\nCamera1.k1: 0.262383\nCamera1.k2: -0.953104\n"
      "Camera1.p1: -0.005358\nCamera1.p2: 0.002628\nCamera1.k3: 1.163314\nCamera.width: 640\nCamera.height: 480\n"
      "Camera.fps: 30\nCamera.RGB: 1\nStereo.ThDepth: 40.0\nStereo.b: 0.07732\nRGBD.DepthMapFactor: 5000.0\n"
      "HOID.dynamicClasses: [person, cup]\n"));
  EXPECT_DOUBLE_EQ(settings.camera.fx, 517.306408);
  EXPECT_DOUBLE_EQ(settings.camera.cy, 255.313989);
  EXPECT_DOUBLE_EQ(settings.camera.k3, 1.163314);
  EXPECT_DOUBLE_EQ(settings.th_depth, 40.0);
  EXPECT_DOUBLE_EQ(settings.bf, 0.07732 * 517.306408);  // Stereo.b is the baseline alone
  EXPECT_NEAR(settings.CloseDepthThreshold(), 40.0 * 0.07732, 1e-12);
  EXPECT_DOUBLE_EQ(settings.depth_map_factor, 5000.0);
  EXPECT_THAT(settings.hoid.dynamic_classes, ElementsAre("person", "cup"));
}

TEST_F(SettingsFile, RejectsKeysOfTheOtherSpelling) {
  EXPECT_THAT([&] { LoadSettings(Write(With(MinimalOriginal(), "RGBD.DepthMapFactor", "5208.0"))); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("parameter RGBD.DepthMapFactor"), HasSubstr("File.version"))));
  EXPECT_THAT(
      [&] {
        LoadSettings(
            Write("%YAML:1.0\nFile.version: \"1.0\"\nCamera1.fx: 1\nCamera1.fy: 1\n"
                  "Camera1.cx: 1\nCamera1.cy: 1\nDepthMapFactor: 5208.0\n"));
      },
      ThrowsMessage<InputError>(AllOf(HasSubstr("parameter DepthMapFactor"), HasSubstr("RGBD.DepthMapFactor"))));
}

TEST_F(SettingsFile, RequiresTheCameraIntrinsics) {
  EXPECT_THAT([&] { LoadSettings(Write("%YAML:1.0\nCamera.fx: 535.4\nCamera.fy: 539.2\nCamera.cx: 320.1\n")); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr("settings.yaml"), HasSubstr("parameter Camera.cy"), HasSubstr("required"))));
  EXPECT_THAT([&] { LoadSettings(Write("%YAML:1.0\n")); }, ThrowsMessage<InputError>(HasSubstr("parameter Camera.fx")));
}

struct BadValue {
  std::string key;
  std::string value;
  std::string parameter;  // the name the error must give
  std::string reason;     // and a part of its explanation
};

void PrintTo(const BadValue& bad, std::ostream* out) { *out << bad.key << ": " << bad.value; }

class SettingsBadValue : public SettingsFile, public ::testing::WithParamInterface<BadValue> {};

TEST_P(SettingsBadValue, IsRejectedNamingTheFileAndTheParameter) {
  const BadValue& bad = GetParam();
  const fs::path path = Write(With(MinimalOriginal(), bad.key, bad.value));
  EXPECT_THAT([&] { LoadSettings(path); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr(path.string() + ": parameter " + bad.parameter + ": "), HasSubstr(bad.reason))));
}

INSTANTIATE_TEST_SUITE_P(
    EveryKey, SettingsBadValue,
    ::testing::Values(BadValue{"Camera.fx", "-1", "Camera.fx", "must be > 0, got -1"},
                      BadValue{"Camera.fy", "0", "Camera.fy", "must be > 0"},
                      BadValue{"Camera.fx", "\"abc\"", "Camera.fx", "must be a number, found the text \"abc\""},
                      BadValue{"Camera.fx", "[1, 2]", "Camera.fx", "must be a number, found a list"},
                      BadValue{"Camera.cx", "900", "Camera.cx", "must be in [0, Camera.width=640]"},
                      BadValue{"Camera.cy", "-3", "Camera.cy", "must be in [0, Camera.height=480]"},
                      BadValue{"Camera.k1", ".nan", "Camera.k1", "finite"},
                      BadValue{"Camera.k3", ".inf", "Camera.k3", "finite"},
                      BadValue{"Camera.fx", "", "Camera.fx", "must be a number, found no value"},
                      BadValue{"Camera.width", "0", "Camera.width", "must be >= 1"},
                      BadValue{"Camera.width", "4294967936", "Camera.width",
                               "must be an integer from -2147483647 to 2147483647, found the integer 4294967936"},
                      BadValue{"Camera.RGB", "0.5", "Camera.RGB", "must be 0 or 1, found the number 0.5"},
                      BadValue{"Camera.height", "480.5", "Camera.height", "must be an integer"},
                      BadValue{"Camera.fps", "0", "Camera.fps", "must be > 0"},
                      BadValue{"Camera.RGB", "2", "Camera.RGB", "must be 0 or 1"},
                      BadValue{"Camera.bf", "-40", "Camera.bf", "must be > 0"},
                      BadValue{"Camera.type", "\"KannalaBrandt8\"", "Camera.type", "PinHole"},
                      BadValue{"ThDepth", "0", "ThDepth", "must be > 0"},
                      BadValue{"DepthMapFactor", "-5000", "DepthMapFactor", "must be > 0"},
                      BadValue{"Depth.noiseFactor", "0", "Depth.noiseFactor", "must be > 0"},
                      BadValue{"Depth.noiseFactor", ".nan", "Depth.noiseFactor", "must be > 0"},
                      BadValue{"ORBextractor.nFeatures", "0", "ORBextractor.nFeatures", "must be >= 1"},
                      BadValue{"ORBextractor.nFeatures", "1000.5", "ORBextractor.nFeatures", "must be an integer"},
                      BadValue{"ORBextractor.scaleFactor", "1.0", "ORBextractor.scaleFactor", "must be > 1"},
                      BadValue{"ORBextractor.nLevels", "0", "ORBextractor.nLevels", "must be >= 1"},
                      BadValue{"ORBextractor.iniThFAST", "0", "ORBextractor.iniThFAST", "must be >= 1"},
                      BadValue{"ORBextractor.minThFAST", "30", "ORBextractor.minThFAST", "iniThFAST=20"},
                      BadValue{"HOID.mode", "hoid4d", "HOID.mode", "hoid4d"},
                      BadValue{"HOID.mode", "3", "HOID.mode", "must be a text"},
                      BadValue{"HOID.minInteractionArea", "1.5", "HOID.minInteractionArea", "(0, 1]"},
                      BadValue{"HOID.minInteractionArea", "0", "HOID.minInteractionArea", "(0, 1]"},
                      BadValue{"HOID.depthThreshold", "0", "HOID.depthThreshold", "must be > 0"},
                      BadValue{"HOID.sampleBoxSize", "0", "HOID.sampleBoxSize", "must be >= 1"},
                      BadValue{"HOID.personClass", "\"\"", "HOID.personClass", "must not be empty"},
                      BadValue{"HOID.dynamicClasses", "person", "HOID.dynamicClasses", "must be a list"},
                      BadValue{"HOID.dynamicClasses", "[person, 3]", "HOID.dynamicClasses", "element 2"},
                      BadValue{"HOID.minInteractionAreas", "0.3", "HOID.minInteractionAreas", "unknown key"},
                      BadValue{"HOIDplus.valley", "0", "HOIDplus.valley", "(0, 1]"},
                      BadValue{"HOIDplus.edgeMargin", "-1", "HOIDplus.edgeMargin", "must be >= 0"},
                      BadValue{"HOIDplus.memory", "2", "HOIDplus.memory", "must be 0 or 1"},
                      BadValue{"HOIDplus.stillSecond", "1", "HOIDplus.stillSecond", "unknown key"},
                      BadValue{"File.version", "\"2.0\"", "File.version", "only \"1.0\""},
                      BadValue{"Camera1.fx", "500", "Camera1.fx", "File.version"}),
    // Stable, readable test names ("7_Camera_k1") for ctest, instead of the parameter's bytes.
    [](const ::testing::TestParamInfo<BadValue>& info) {
      std::string name = std::to_string(info.index) + "_" + info.param.key;
      for (char& c : name) {
        if (std::isalnum(static_cast<unsigned char>(c)) == 0) c = '_';
      }
      return name;
    });

TEST_F(SettingsFile, ReadsTheHoidPlusSection) {
  const Settings settings = LoadSettings(Write(
      "%YAML:1.0\nCamera.fx: 535.4\nCamera.fy: 539.2\nCamera.cx: 320.1\nCamera.cy: 247.6\nHOID.mode: hoidplus\n"
      "HOIDplus.depthRefinement: 0\nHOIDplus.depthBin: 0.05\nHOIDplus.valley: 0.3\nHOIDplus.depthExtent: 0.4\n"
      "HOIDplus.foregroundShare: 0.2\nHOIDplus.edgeMargin: 4\nHOIDplus.boxMargin: 0.1\nHOIDplus.memory: 1\n"
      "HOIDplus.associationIoU: 0.4\nHOIDplus.relabelIoU: 0.7\nHOIDplus.maxMissedSeconds: 0.3\n"
      "HOIDplus.stillSeconds: 2\nHOIDplus.stillDistance: 0.05\nHOIDplus.safetyNet: 0\n"
      "HOIDplus.movingPointOutliers: 4\n"));
  const core::HoidPlusOptions& plus = settings.hoid.plus;
  EXPECT_EQ(settings.hoid.mode, core::FilterMode::kHoidPlus);
  EXPECT_FALSE(plus.depth);
  EXPECT_DOUBLE_EQ(plus.depth_bin, 0.05);
  EXPECT_DOUBLE_EQ(plus.valley, 0.3);
  EXPECT_DOUBLE_EQ(plus.depth_extent, 0.4);
  EXPECT_DOUBLE_EQ(plus.foreground_share, 0.2);
  EXPECT_EQ(plus.edge_margin, 4);
  EXPECT_DOUBLE_EQ(plus.box_margin, 0.1);
  EXPECT_TRUE(plus.memory);
  EXPECT_DOUBLE_EQ(plus.association_iou, 0.4);
  EXPECT_DOUBLE_EQ(plus.relabel_iou, 0.7);
  EXPECT_DOUBLE_EQ(plus.max_missed_seconds, 0.3);
  EXPECT_DOUBLE_EQ(plus.still_seconds, 2.0);
  EXPECT_DOUBLE_EQ(plus.still_distance, 0.05);
  EXPECT_FALSE(plus.safety_net);
  EXPECT_EQ(plus.moving_point_outliers, 4);
}

TEST_F(SettingsFile, RejectsARepeatedKey) {
  const fs::path path = Write(
      "%YAML:1.0\nCamera.fx: 535.4\nCamera.fy: 539.2\nCamera.cx: 320.1\nCamera.cy: 247.6\n"
      "HOID.mode: none\nHOID.mode: hoid3d\n");
  EXPECT_THAT(
      [&] { LoadSettings(path); },
      ThrowsMessage<InputError>(HasSubstr(path.string() + ":7: HOID.mode is given more than once (first on line 6)")));
}

TEST_F(SettingsFile, RejectsFilesThatAreNotSettingsNamingThem) {
  const fs::path missing = scratch_ / "absent.yaml";
  EXPECT_THAT([&] { LoadSettings(missing); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(missing.string()), HasSubstr("does not exist"))));
  EXPECT_THAT([&] { LoadSettings(scratch_.path()); }, ThrowsMessage<InputError>(HasSubstr(scratch_.path().string())));
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"plain.txt", "fx = 535.4\nthis is not YAML\n"},
           {"no_header.yaml", "Camera.fx: 535.4\n"},
           {"empty.yaml", ""},
           {"binary.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)},
           {"list.yaml", "%YAML:1.0\n- 535.4\n- 539.2\n"}}) {
    SCOPED_TRACE(name);
    const fs::path path = Write(text, name);
    EXPECT_THAT([&] { LoadSettings(path); }, ThrowsMessage<InputError>(HasSubstr(path.string())));
  }
}

// Files in OpenCV's other forms are refused; so are the inputs on which cv::FileStorage, which once read settings
// files, crashed or never returned (fuzz/regressions/settings).
TEST_F(SettingsFile, ReadsOnlyYamlText) {
  const fs::path xml = Write("<?xml version=\"1.0\"?>\n<opencv_storage><Camera.fx>1</Camera.fx></opencv_storage>\n");
  EXPECT_THAT([&] { LoadSettings(xml); }, ThrowsMessage<InputError>(HasSubstr(xml.string() + ": not a settings file")));
  const fs::path json = Write("{\"Camera.fx\": 535.4}\n");
  EXPECT_THAT([&] { LoadSettings(json); },
              ThrowsMessage<InputError>(HasSubstr(json.string() + ": not a settings file")));
  using namespace std::string_literals;  // "..."s keeps the NUL byte
  const fs::path nul = Write("%YAML:1.0\nCamera.fx: 535.4\nHOID.mode: 'a\0'\n"s);
  EXPECT_THAT([&] { LoadSettings(nul); },
              ThrowsMessage<InputError>(HasSubstr(nul.string() + ":3: a NUL byte: a settings file is text")));
  const fs::path marker = Write("%YAML:1.0\n---  # OpenCV writes this line\n--- - s\n-\n");
  EXPECT_THAT([&] { LoadSettings(marker); },
              ThrowsMessage<InputError>(HasSubstr(marker.string() + ":3: the document marker --- must stand alone")));
}

// ORB-SLAM3's files for cameras with an IMU hold OpenCV matrices, which hoidslam does not read but must pass over.
TEST_F(SettingsFile, ReadsAnOrbSlam3FileWithMatrices) {
  const Settings settings = LoadSettings(Write(
      "%YAML:1.0\n\n#--------\n# Camera\n#--------\nFile.version: \"1.0\"\nCamera.type: \"PinHole\"\n"
      "Camera1.fx: 382.613\nCamera1.fy: 382.613\nCamera1.cx: 320.183\nCamera1.cy: 236.455\n"
      "Camera.width: 640\nCamera.height: 480\nCamera.fps: 30\nCamera.RGB: 1.0\nViewer.PointSize:2\nStereo.b: 0.0499585\n"
      "IMU.T_b_c1: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: f\n"
      "   data: [1.0, 0.0, 0.0, 0.0,\n          0.0, 1.0, 0.0, 0.0,\n          0.0, 0.0, 1.0, 0.0,\n"
      "          0.0, 0.0, 0.0, 1.0]\nRGBD.DepthMapFactor: 1000.0\nORBextractor.nFeatures: 1250\n"));
  EXPECT_DOUBLE_EQ(settings.camera.fx, 382.613);
  EXPECT_DOUBLE_EQ(settings.bf, 0.0499585 * 382.613);
  EXPECT_DOUBLE_EQ(settings.depth_map_factor, 1000.0);
  EXPECT_EQ(settings.orb.n_features, 1250);
  EXPECT_TRUE(settings.rgb_order);
}

TEST_F(SettingsFile, RefusesAFileFarLargerThanSettingsWithoutReadingIt) {
  const fs::path path = Write("%YAML:1.0\n" + std::string(2 << 20, '#') + "\n");
  EXPECT_THAT([&] { LoadSettings(path); },
              ThrowsMessage<InputError>(HasSubstr(path.string() + ": not a settings file: 2097163 bytes")));
}

// A quoted value with an escaped line break stays in a one-line message.
TEST_F(SettingsFile, KeepsMessagesOnOneLine) {
  const fs::path path = Write(With(MinimalOriginal(), "HOID.mode", "\"a\\nb\""));
  EXPECT_THAT([&] { LoadSettings(path); },
              ThrowsMessage<InputError>(HasSubstr("parameter HOID.mode: unknown mode 'a\\nb'")));
}

TEST_F(SettingsFile, NamesTheLineOfAYamlSyntaxError) {
  const fs::path path = Write("%YAML:1.0\nCamera.fx: 535.4\nHOID.dynamicClasses: [person, cup\n");
  EXPECT_THAT([&] { LoadSettings(path); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(path.string() + ":3:"), HasSubstr("YAML syntax error"))));
}

TEST_F(SettingsFile, WrittenAsJsonEveryValueReadsBackTheSame) {
  const Settings original = LoadSettings(fs::path(HOIDSLAM_CONFIG_DIR) / "TUM1.yaml");
  const nlohmann::ordered_json json = SettingsToJson(original);
  EXPECT_EQ(json.begin().key(), "Camera.fx");
  EXPECT_EQ(json["HOID.mode"], "hoidplus");
  // The keys and values as a settings file of their own: the same settings again.
  std::string yaml = "%YAML:1.0\n";
  for (const auto& [key, value] : json.items()) {
    if (value.is_boolean()) {
      yaml += fmt::format("{}: {}\n", key, value.get<bool>() ? 1 : 0);
    } else if (value.is_array()) {
      yaml += key + ":\n";
      for (const auto& item : value) yaml += fmt::format("  - \"{}\"\n", item.get<std::string>());
    } else {
      yaml += fmt::format("{}: {}\n", key, value.dump());
    }
  }
  const Settings again = LoadSettings(Write(yaml));
  EXPECT_EQ(SettingsToJson(again), json);
  EXPECT_EQ(again.camera, original.camera);
}

TEST(ShippedSettingsForFolder, PicksTheCameraByTumsLongAndShortNames) {
  const testing::TempDir config;
  for (const char* file : {"TUM1.yaml", "TUM2.yaml", "TUM3.yaml", "Bonn.yaml"}) std::ofstream(config / file) << "";
  EXPECT_EQ(ShippedSettingsForFolder("/data/rgbd_dataset_freiburg1_rpy", config.path()), config / "TUM1.yaml");
  EXPECT_EQ(ShippedSettingsForFolder("/data/fr1_rpy", config.path()), config / "TUM1.yaml");
  EXPECT_EQ(ShippedSettingsForFolder("/data/fr2_desk/", config.path()), config / "TUM2.yaml");
  EXPECT_EQ(ShippedSettingsForFolder("/data/FR3_walking_xyz", config.path()), config / "TUM3.yaml");
  EXPECT_EQ(ShippedSettingsForFolder("/data/rgbd_bonn_crowd", config.path()), config / "Bonn.yaml");
  EXPECT_EQ(ShippedSettingsForFolder("/data/my_office", config.path()), fs::path());
}

TEST(ChooseSettings, TheFileGivenThenTheFolderNameThenTheDefaults) {
  const fs::path config = HOIDSLAM_CONFIG_DIR;
  const SettingsChoice given = ChooseSettings(config / "TUM3.yaml", "/data/rgbd_dataset_freiburg1_xyz", config);
  EXPECT_EQ(given.reason, SettingsChoice::Reason::kGiven);
  EXPECT_EQ(given.file, config / "TUM3.yaml");
  EXPECT_DOUBLE_EQ(given.settings.camera.fx, 535.4);

  const SettingsChoice by_name = ChooseSettings({}, "/data/rgbd_dataset_freiburg1_xyz/", config);
  EXPECT_EQ(by_name.reason, SettingsChoice::Reason::kFolderName);
  EXPECT_EQ(by_name.file, config / "TUM1.yaml");
  EXPECT_DOUBLE_EQ(by_name.settings.camera.fx, 517.306408);
  EXPECT_THAT(by_name.Describe(), HasSubstr("TUM1.yaml (by the sequence folder's name, rgbd_dataset_freiburg1_xyz"));

  const SettingsChoice fallback = ChooseSettings({}, "/data/my_office", config);
  EXPECT_EQ(fallback.reason, SettingsChoice::Reason::kDefault);
  EXPECT_TRUE(fallback.file.empty());
  EXPECT_EQ(fallback.settings.camera, core::CameraIntrinsics{});
  EXPECT_THAT(fallback.Describe(), HasSubstr("the defaults: the TUM fr3 camera"));
  EXPECT_EQ(ToString(SettingsChoice::Reason::kFolderName), "folder_name");
}

TEST(Settings, CheckNamesTheParameterOfAnOutOfRangeValue) {
  EXPECT_NO_THROW(Settings{}.Check());
  Settings settings;
  settings.depth_map_factor = 0.0;
  EXPECT_THAT([&] { settings.Check(); }, ThrowsMessage<InputError>(HasSubstr("parameter DepthMapFactor")));
  settings = {};
  settings.camera.fx = -1.0;
  EXPECT_THAT([&] { settings.Check(); },
              ThrowsMessage<InputError>(HasSubstr("parameter Camera.fx: must be > 0, got -1")));
  settings = {};
  settings.hoid.sample_box_size = 0;
  EXPECT_THAT([&] { settings.Check(); }, ThrowsMessage<InputError>(HasSubstr("parameter HOID.sampleBoxSize")));
  settings = {};
  settings.orb.n_features = 0;
  EXPECT_THAT([&] { settings.Check(); }, ThrowsMessage<InputError>(HasSubstr("parameter ORBextractor.nFeatures")));
}

}  // namespace
}  // namespace hoidslam::io
