#include "hoidslam/io/detections_file.h"

#include <string>

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::io {
namespace {

using ::hoidslam::testing::WriteText;


std::string ErrorOf(const std::filesystem::path& path) {
  try {
    DetectionsFile::Read(path);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "no error";
}

core::Detection MakeDetection(const std::string& label, int class_id, float score, cv::Rect2f box) {
  core::Detection d;
  d.label = label;
  d.class_id = class_id;
  d.score = score;
  d.box = box;
  return d;
}

TEST(DetectionsFile, WriterAndReaderRoundTrip) {
  testing::TempDir dir;
  const auto path = dir / "detections.jsonl";
  {
    DetectionsFileWriter writer(path, {"rgbd_dataset_freiburg3_walking_xyz", "yolox_nano.onnx", 640, 480});
    writer.Write({1341846313.592026, {MakeDetection("person", 0, 0.91F, {10.5F, 20.25F, 100, 200}),
                                      MakeDetection("tv", 62, 0.5F, {300, 40, 80, 60})}});
    writer.Write({1341846313.628, {}});
    writer.Commit();
  }
  const DetectionsFile file = DetectionsFile::Read(path);
  ASSERT_TRUE(file.header().has_value());
  EXPECT_EQ(file.header()->sequence, "rgbd_dataset_freiburg3_walking_xyz");
  EXPECT_EQ(file.header()->detector, "yolox_nano.onnx");
  EXPECT_EQ(file.header()->image_width, 640);
  ASSERT_EQ(file.frames().size(), 2U);
  const FrameDetections* first = file.Find(1341846313.592026);
  ASSERT_NE(first, nullptr);
  ASSERT_EQ(first->detections.size(), 2U);
  EXPECT_EQ(first->detections[0].label, "person");
  EXPECT_EQ(first->detections[0].class_id, 0);
  EXPECT_FLOAT_EQ(first->detections[0].score, 0.91F);
  EXPECT_EQ(first->detections[0].box, cv::Rect2f(10.5F, 20.25F, 100, 200));
  EXPECT_EQ(first->detections[1].label, "tv");
  const FrameDetections* empty = file.Find(1341846313.628);
  ASSERT_NE(empty, nullptr);
  EXPECT_TRUE(empty->detections.empty());
  EXPECT_EQ(file.Find(1341846313.61), nullptr);
}

TEST(DetectionsFile, HandWrittenFileWithoutHeaderOrClassIds) {
  testing::TempDir dir;
  WriteText(dir / "d.jsonl",
            "{\"timestamp\": 2.0, \"detections\": []}\n"
            "\n"
            "{\"timestamp\": 1.0, \"detections\": [{\"label\": \"cup\", \"score\": 1, \"box\": [1, 2, 3, 4]}]}\n");
  const DetectionsFile file = DetectionsFile::Read(dir / "d.jsonl");
  EXPECT_FALSE(file.header().has_value());
  ASSERT_EQ(file.frames().size(), 2U);
  EXPECT_DOUBLE_EQ(file.frames()[0].timestamp, 1.0);  // sorted
  EXPECT_EQ(file.frames()[0].detections[0].class_id, -1);
}

TEST(DetectionsFile, ErrorsNameFileLineAndKey) {
  testing::TempDir dir;
  const auto path = dir / "d.jsonl";
  const std::string prefix = path.string() + ":2: ";
  const std::string good = "{\"timestamp\": 1.0, \"detections\": []}\n";

  WriteText(path, good + "{\"timestamp\": 2.0, \"detections\": [\n");
  EXPECT_EQ(ErrorOf(path).rfind(prefix + "not valid JSON", 0), 0U) << ErrorOf(path);
  WriteText(path, good + "{\"detections\": []}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "missing key 'timestamp'");
  WriteText(path, good + "{\"timestamp\": \"2.0\", \"detections\": []}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "'timestamp' must be a number, got \"2.0\"");
  WriteText(path, good + "{\"timestamp\": 2, \"detections\": [{\"label\": \"cup\", \"score\": 1.5, \"box\": [0,0,1,1]}]}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "'detections[0].score' must be in [0, 1], got 1.5");
  WriteText(path, good + "{\"timestamp\": 2, \"detections\": [{\"label\": \"cup\", \"score\": 1, \"box\": [0,0,1]}]}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "'detections[0].box' must be [x, y, width, height]");
  WriteText(path, good + "{\"timestamp\": 2, \"detections\": [{\"label\": \"cup\", \"score\": 1, \"box\": [0,0,-1,1]}]}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "'detections[0].box' has a negative width or height");
  WriteText(path, good + "{\"timestamp\": 2, \"detections\": [{\"score\": 1, \"box\": [0,0,1,1]}]}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "missing key 'detections[0].label'");
  WriteText(path, good + "{\"format\": \"hoidslam-detections\", \"version\": 1}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "the header line must be the first line");
  WriteText(path, good + "{\"timestamp\": 1e400, \"detections\": []}\n");
  EXPECT_EQ(ErrorOf(path).rfind(prefix + "not valid JSON ([json.exception.out_of_range.406] number overflow", 0), 0U)
      << ErrorOf(path);
  WriteText(path,
            good + "{\"timestamp\": 2, \"detections\": [{\"label\": \"cup\", \"score\": 1, \"box\": [1e300,0,1,1]}]}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "'detections[0].box[0]' is out of range");
  WriteText(path, good + "{\"timestamp\": 2, \"detections\": [{\"label\": \"cup\", \"class_id\": 4294967296, "
                         "\"score\": 1, \"box\": [0,0,1,1]}]}\n");
  EXPECT_EQ(ErrorOf(path), prefix + "'detections[0].class_id' must be an integer in [-1, 2147483647], got 4294967296");
  WriteText(path, "{\"format\": \"hoidslam-detections\", \"version\": 4294967297}\n");
  EXPECT_EQ(ErrorOf(path), path.string() + ":1: unsupported version 4294967297 (this hoidslam reads version 1)");
  WriteText(path, "{\"format\": \"hoidslam-detections\", \"version\": 1, \"image_size\": [-640, 480]}\n");
  EXPECT_EQ(ErrorOf(path), path.string() + ":1: 'image_size[0]' must be an integer in [0, 2147483647], got -640");
  WriteText(path, good + good);
  EXPECT_EQ(ErrorOf(path), path.string() + ": timestamp 1.000000 appears on more than one line");
  EXPECT_EQ(ErrorOf(dir / "absent.jsonl"), (dir / "absent.jsonl").string() + ": no such file");
}

TEST(DetectionsFile, CheckCoversRejectsAnotherSequence) {
  testing::TempDir dir;
  const auto path = dir / "d.jsonl";
  {
    DetectionsFileWriter writer(path, {"walking_xyz", "test", 0, 0});
    writer.Write({1.0, {}});
    writer.Write({2.0, {}});
    writer.Commit();
  }
  const DetectionsFile file = DetectionsFile::Read(path);
  EXPECT_NO_THROW(file.CheckCovers({1.0, 2.00001}, "walking_xyz"));
  try {
    file.CheckCovers({1.0, 2.0}, "walking_static");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("was written for sequence 'walking_xyz', not 'walking_static'"),
              std::string::npos);
  }
  try {
    file.CheckCovers({1.0, 2.0, 3.0, 4.0}, "walking_xyz");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no line for 2 of the 4 frames of 'walking_xyz' (first: timestamp 3.000000)"),
              std::string::npos)
        << e.what();
  }
}

TEST(DetectionsFileWriter, UncommittedWriterLeavesNoFile) {
  testing::TempDir dir;
  {
    DetectionsFileWriter writer(dir / "d.jsonl", {});
    writer.Write({1.0, {}});
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "d.jsonl"));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace hoidslam::io
