#include "hoidslam/detect/make_detector.h"

#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "hoidslam/detect/file_detector.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::detect {
namespace {

using ::testing::HasSubstr;

TEST(DetectorKind, ParsesEveryNameAndNamesTheParameterOnError) {
  for (const char* name : {"none", "onnx", "file"}) EXPECT_EQ(ToString(ParseDetectorKind(name)), name);
  try {
    ParseDetectorKind("yolo");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("Detector.kind"));
    EXPECT_THAT(e.what(), HasSubstr("yolo"));
  }
}

TEST(MakeDetector, NoneFindsNothing) {
  const auto detector = MakeDetector({});
  EXPECT_EQ(detector->Name(), "none");
  EXPECT_TRUE(detector->Detect(0.0, cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(0))).empty());
}

TEST(MakeDetector, FileKindNeedsAFileAndReplaysIt) {
  DetectorOptions options;
  options.kind = DetectorKind::kFile;
  try {
    MakeDetector(options);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("Detector.detectionsFile"));
  }
  hoidslam::testing::TempDir dir;
  std::ofstream(dir / "d.jsonl") << R"({"timestamp":2.0,"detections":[{"label":"cup","score":0.8,"box":[1,2,3,4]}]})"
                                 << '\n';
  options.detections_file = dir / "d.jsonl";
  const auto detector = MakeDetector(options);
  ASSERT_NE(dynamic_cast<FileDetector*>(detector.get()), nullptr);
  const auto detections = detector->Detect(2.0, cv::Mat());
  ASSERT_EQ(detections.size(), 1U);
  EXPECT_EQ(detections[0].label, "cup");
  EXPECT_EQ(detections[0].class_id, -1);
}

TEST(MakeDetector, OnnxKindChecksItsOptionsAndLoadsTheModel) {
  DetectorOptions options;
  options.kind = DetectorKind::kOnnx;
  EXPECT_THROW(MakeDetector(options), core::InputError);  // no model given
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  options.onnx.model = model;
  const auto detector = MakeDetector(options);
  EXPECT_NE(dynamic_cast<OnnxDetector*>(detector.get()), nullptr);
  EXPECT_EQ(detector->Name(), "yolox_nano.onnx");
}

}  // namespace
}  // namespace hoidslam::detect
