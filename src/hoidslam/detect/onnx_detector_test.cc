#include "hoidslam/detect/onnx_detector.h"

#include <algorithm>
#include <fstream>
#include <memory>
#include <set>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/detect/tiny_onnx_model.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::detect {
namespace {

using ::testing::HasSubstr;

OnnxDetectorOptions ForModel(const std::filesystem::path& model) {
  OnnxDetectorOptions options;
  options.model = model;
  return options;
}

// The shared YOLOX-Nano model, loaded once for the whole suite (when present).
class YoloxNano : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::filesystem::path model = hoidslam::testing::SharedPath("models/yolox_nano.onnx");
    if (std::filesystem::exists(model)) detector_ = std::make_unique<OnnxDetector>(ForModel(model));
  }
  static void TearDownTestSuite() { detector_.reset(); }

  void SetUp() override {
    HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
    ASSERT_NE(detector_, nullptr);
  }

  static std::vector<core::Detection> DetectIn(const std::filesystem::path& image_path) {
    const cv::Mat image = cv::imread(image_path.string(), cv::IMREAD_COLOR);
    EXPECT_FALSE(image.empty()) << image_path;
    std::vector<core::Detection> detections = detector_->Detect(0.0, image);
    ExpectInside(detections, image.size());
    return detections;
  }

  static void ExpectInside(const std::vector<core::Detection>& detections, cv::Size size) {
    for (const core::Detection& d : detections) {
      EXPECT_GE(d.box.x, 0.0F) << d.label;
      EXPECT_GE(d.box.y, 0.0F) << d.label;
      EXPECT_GT(d.box.width, 0.0F) << d.label;
      EXPECT_GT(d.box.height, 0.0F) << d.label;
      EXPECT_LE(d.box.x + d.box.width, static_cast<float>(size.width) + 1e-3F) << d.label;
      EXPECT_LE(d.box.y + d.box.height, static_cast<float>(size.height) + 1e-3F) << d.label;
      EXPECT_GE(d.score, 0.25F) << d.label;
      EXPECT_LE(d.score, 1.0F) << d.label;
    }
  }

  static inline std::unique_ptr<OnnxDetector> detector_;
};

// The detections of `label` with a score above 0.5.
std::vector<core::Detection> Confident(const std::vector<core::Detection>& detections, const std::string& label) {
  std::vector<core::Detection> found;
  std::copy_if(detections.begin(), detections.end(), std::back_inserter(found),
               [&label](const core::Detection& d) { return d.label == label && d.score > 0.5F; });
  return found;
}

TEST_F(YoloxNano, TakesItsInputSizeAndLayoutFromTheModel) {
  EXPECT_EQ(detector_->input_size(), cv::Size(416, 416));
  EXPECT_EQ(detector_->output_format().layout, YoloLayout::kYolox);
  EXPECT_EQ(detector_->output_format().num_classes, 80);
  EXPECT_EQ(detector_->Name(), "yolox_nano.onnx");
}

TEST_F(YoloxNano, FindsZidaneOnTheRight) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(photo, "data/photos/zidane.jpg");  // 1280×720, two men standing
  const auto detections = DetectIn(photo);
  const auto people = Confident(detections, "person");
  ASSERT_FALSE(people.empty());
  // Zidane stands in the right half and fills most of the height.
  EXPECT_TRUE(std::any_of(people.begin(), people.end(), [](const core::Detection& d) {
    const cv::Point2f centre = (d.box.tl() + d.box.br()) / 2;
    return centre.x > 640 && centre.x < 1150 && d.box.height > 450;
  }));
  EXPECT_TRUE(std::is_sorted(detections.begin(), detections.end(),
                             [](const core::Detection& a, const core::Detection& b) { return a.score > b.score; }));
}

TEST_F(YoloxNano, FindsPeopleAndTheBusInBusJpg) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(photo, "data/photos/bus.jpg");  // 810×1080, people in front of a bus
  const auto detections = DetectIn(photo);
  const auto people = Confident(detections, "person");
  ASSERT_GE(people.size(), 3U);
  for (const core::Detection& person : people) {
    EXPECT_GT(person.box.height, person.box.width) << "people stand upright";
    EXPECT_GT(person.box.y + person.box.height, 700.0F) << "people stand on the street";
  }
  EXPECT_FALSE(Confident(detections, "bus").empty());
  for (const core::Detection& d : detections) EXPECT_EQ(d.class_id == 0, d.label == "person");
}

TEST_F(YoloxNano, FindsPersonChairAndTvInTheTumFrames) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(folder, "data/tum/fr3_walking_xyz_pair/rgb");
  std::set<std::string> labels;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    for (const core::Detection& d : DetectIn(entry.path())) labels.insert(d.label);
  }
  EXPECT_TRUE(labels.contains("person"));
  EXPECT_TRUE(labels.contains("chair"));
  EXPECT_TRUE(labels.contains("tv"));
}

TEST_F(YoloxNano, RejectsAnImageOfTheWrongType) {
  EXPECT_THROW(detector_->Detect(0.0, cv::Mat()), core::Error);
  EXPECT_THROW(detector_->Detect(0.0, cv::Mat(48, 64, CV_8UC1, cv::Scalar(0))), core::Error);
}

TEST(OnnxDetector, LabelsComeFromTheClassNamesFile) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  HOIDSLAM_SHARED_PATH_OR_SKIP(names, "data/photos/coco.names");  // darknet's names: "tvmonitor"
  HOIDSLAM_SHARED_PATH_OR_SKIP(frame, "data/tum/fr3_walking_xyz_pair/rgb/1341846313.592026.png");
  OnnxDetectorOptions options = ForModel(model);
  options.class_names = names;
  OnnxDetector detector(options);
  const auto detections = detector.Detect(0.0, cv::imread(frame.string(), cv::IMREAD_COLOR));
  EXPECT_TRUE(std::any_of(detections.begin(), detections.end(),
                          [](const core::Detection& d) { return d.label == "tvmonitor" && d.class_id == 62; }));
}

TEST(OnnxDetector, ClassNamesFileOfTheWrongLengthIsNamed) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  hoidslam::testing::TempDir dir;
  std::ofstream(dir / "three.names") << "person\nchair\ntv\n";
  OnnxDetectorOptions options = ForModel(model);
  options.class_names = dir / "three.names";
  try {
    OnnxDetector detector(options);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("three.names"));
    EXPECT_THAT(e.what(), HasSubstr("80 classes"));
  }
}

TEST(OnnxDetector, InputSizeOtherThanTheModelsFixedOneIsNamed) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  OnnxDetectorOptions options = ForModel(model);
  options.input_size = 640;
  try {
    OnnxDetector detector(options);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("Detector.inputSize"));
    EXPECT_THAT(e.what(), HasSubstr("416×416"));
  }
}

TEST(OnnxDetector, RequestedLayoutThatDoesNotFitIsReported) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  OnnxDetectorOptions options = ForModel(model);
  options.layout = YoloLayout::kYolov8;
  try {
    OnnxDetector detector(options);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("yolox_nano.onnx"));
    EXPECT_THAT(e.what(), HasSubstr("1×3549×85 matches no known layout"));
  }
}

// Throws the InputError that loading `model` gives, or fails the test.
std::string LoadError(const std::filesystem::path& model) {
  try {
    OnnxDetector detector(ForModel(model));
  } catch (const core::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError for " << model;
  return "";
}

TEST(OnnxDetector, MissingAndGarbageModelFilesAreNamed) {
  hoidslam::testing::TempDir dir;
  EXPECT_THAT(LoadError(dir / "absent.onnx"), HasSubstr("absent.onnx: no such model file"));
  std::ofstream(dir / "garbage.onnx") << "GIF89a, certainly not a model";
  EXPECT_THAT(LoadError(dir / "garbage.onnx"), HasSubstr("garbage.onnx: not an ONNX model"));
}

TEST(OnnxDetector, OutputMatchingNoLayoutIsNamed) {
  hoidslam::testing::TempDir dir;
  tiny_onnx::WriteBytes(dir / "identity.onnx", tiny_onnx::IdentityModel({1, 3, 416, 416}));
  const std::string error = LoadError(dir / "identity.onnx");
  EXPECT_THAT(error, HasSubstr("identity.onnx: output shape 1×3×416×416 matches no known layout"));
  EXPECT_THAT(error, HasSubstr("1×3549×(5+C) for YOLOX"));
}

TEST(OnnxDetector, ModelThatIsNotAnImageModelIsNamed) {
  hoidslam::testing::TempDir dir;
  tiny_onnx::WriteBytes(dir / "table.onnx", tiny_onnx::IdentityModel({1, 7, 9}));
  EXPECT_THAT(LoadError(dir / "table.onnx"), HasSubstr("table.onnx: input 'images' has shape 1×7×9"));
}

TEST(OnnxDetectorOptions, CheckNamesTheParameter) {
  const OnnxDetectorOptions options = ForModel("m.onnx");
  EXPECT_NO_THROW(options.Check());
  const auto expect_named = [](const OnnxDetectorOptions& bad, const char* parameter) {
    try {
      bad.Check();
      ADD_FAILURE() << "expected an InputError naming " << parameter;
    } catch (const core::InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(parameter));
    }
  };
  expect_named(OnnxDetectorOptions{}, "Detector.model");
  for (const int size : {-32, 31, 400, 9000}) {
    OnnxDetectorOptions bad = options;
    bad.input_size = size;
    expect_named(bad, "Detector.inputSize");
  }
  for (const float conf : {0.0F, 1.0F, -0.5F}) {
    OnnxDetectorOptions bad = options;
    bad.confidence_threshold = conf;
    expect_named(bad, "Detector.confThreshold");
  }
  for (const float nms : {0.0F, 1.5F}) {
    OnnxDetectorOptions bad = options;
    bad.nms_threshold = nms;
    expect_named(bad, "Detector.nmsThreshold");
  }
}

}  // namespace
}  // namespace hoidslam::detect
