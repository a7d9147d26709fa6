#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/hoidslam.h"
#include "hoidslam/hoidslam_opencv.h"
#include "hoidslam/api/convert.h"
#include "hoidslam/detect/file_detector.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/synth/test_scenarios.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Options with `filter`, changed by `change`.
template <typename Change>
Options WithFilter(const std::string& filter, Change change) {
  Options options;
  options.filter = filter;
  change(options);
  return options;
}
Options WithFilter(const std::string& filter) {
  return WithFilter(filter, [](Options&) {});
}
const auto kDeterministic = [](Options& o) { o.deterministic = true; };

// A frame of the camera's size with nothing in it.
struct BlankFrame {
  cv::Mat rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(90, 120, 150));
  cv::Mat depth = cv::Mat(480, 640, CV_16UC1, cv::Scalar(10000));
};

// The message of the InputError `call` throws.
template <typename Call>
std::string ErrorOf(Call call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(System, GivesTheTrajectoryOfHoidslamRunByteForByte) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path root = synth::fixtures::RenderShortWalk(dir / "walk", tum_dir, 30);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(root);

  pipeline::RunOptions run_options = pipeline::RunOptions::FromSettings(io::Settings{});
  pipeline::SetFilterMode("hoid2d", run_options.exclusion);
  run_options.system.deterministic = true;
  fs::create_directories(dir / "run");
  detect::FileDetector run_detector(root / "detections.jsonl");
  pipeline::RunSequence(sequence, run_detector, run_options, dir / "run");

  // The frames as a camera program has them: 16-bit depth as the sensor gives it, boxes from its own detector.
  System slam(WithFilter("hoid2d", kDeterministic));
  detect::FileDetector detector(root / "detections.jsonl");
  std::size_t tracked = 0, dropped = 0;
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const core::RgbdFrame frame = sequence.LoadFrame(i);
    const cv::Mat depth = cv::imread(frame.depth_path, cv::IMREAD_UNCHANGED);
    const FrameResult r = Track(slam, frame.rgb, depth, frame.timestamp, api::ToApiDetections(detector.Detect(frame.timestamp, frame.rgb)));
    EXPECT_EQ(r.index, i);
    tracked += r.T_wc ? 1 : 0;
    for (std::size_t k = 0; k < r.keypoints.size(); ++k) {
      if (r.keypoints.kept[k] != 0) continue;
      ++dropped;
      ASSERT_GE(r.keypoints.box[k], 0);
      EXPECT_TRUE(r.boxes[static_cast<std::size_t>(r.keypoints.box[k])].dynamic);
      EXPECT_THAT(std::string(r.DropReason(k)), ::testing::AnyOf("person", "interaction"));
    }
  }
  EXPECT_EQ(tracked, 30U);
  EXPECT_GT(dropped, 0U);  // people are in view
  EXPECT_EQ(slam.Trajectory().size(), 30U);
  slam.Save(dir / "api");
  for (const char* file : {"trajectory.txt", "keyframes.txt", "map.ply"}) {
    EXPECT_EQ(testing::ReadText(dir / "api" / file), testing::ReadText(dir / "run" / file)) << file;
  }
}

TEST(System, TakesRgbGreyAndFloatDepthAndPaddedRows) {
  const BlankFrame blank;
  System slam(WithFilter("none", kDeterministic));
  EXPECT_EQ(slam.width(), 640);
  EXPECT_EQ(slam.height(), 480);
  EXPECT_EQ(slam.filter(), "none");
  cv::Mat rgb, grey, metres;
  cv::cvtColor(blank.rgb, rgb, cv::COLOR_BGR2RGB);
  cv::cvtColor(blank.rgb, grey, cv::COLOR_BGR2GRAY);
  blank.depth.convertTo(metres, CV_32F, 1.0 / slam.depth_factor());
  // A row padded to 4000 bytes, as some camera SDKs lay images out.
  cv::Mat padded_storage(480, 4000, CV_8UC1);
  cv::Mat padded(480, 640, CV_8UC3, padded_storage.data, 4000);
  blank.rgb.copyTo(padded);
  EXPECT_EQ(Track(slam, rgb, metres, 1.0, {}, PixelFormat::kRgb).state,
            TrackingState::kNotInitialized);  // a blank frame has no keypoints
  EXPECT_NO_THROW(Track(slam, grey, blank.depth, 2.0));
  EXPECT_NO_THROW(Track(slam, padded, blank.depth, 3.0));
  EXPECT_THAT(ErrorOf([&] { Track(slam, metres, blank.depth, 4.0); }), HasSubstr("parameter rgb: must be CV_8UC3"));
}

TEST(System, NamesTheArgumentThatIsWrong) {
  const BlankFrame blank;
  System slam(WithFilter("hoid2d"));
  const ImageView depth = ToDepthView(blank.depth);
  const cv::Mat small(240, 320, CV_16UC1, cv::Scalar(0));
  EXPECT_THAT(ErrorOf([&] { Track(slam, blank.rgb, small, 1.0); }),
              HasSubstr("parameter depth: is 320x240 but the camera's images are 640x480"));
  ImageView short_rows = ToImageView(blank.rgb);
  short_rows.stride = 100;
  EXPECT_THAT(ErrorOf([&] { slam.Track(short_rows, depth, 1.0, {}); }),
              HasSubstr("parameter rgb: stride 100 bytes is shorter than a row of 1920 bytes"));
  EXPECT_THAT(ErrorOf([&] { slam.Track({}, depth, 1.0, {}); }), HasSubstr("parameter rgb: no image data"));
  EXPECT_THAT(ErrorOf([&] { slam.Track(depth, depth, 1.0, {}); }),
              HasSubstr("parameter rgb: must be a colour image (format bgr, rgb or gray), got a depth format"));
  EXPECT_THAT(ErrorOf([&] { slam.Track(ToImageView(blank.rgb), ToImageView(blank.rgb), 1.0, {}); }),
              HasSubstr("parameter depth: must be a depth image"));
  const std::vector<Detection> bad = {{"person", 1.0F, {0, 0, 10, 10}}, {"cup", 2.0F, {0, 0, 10, 10}}};
  EXPECT_THAT(ErrorOf([&] { slam.Track(ToImageView(blank.rgb), depth, 1.0, bad); }),
              HasSubstr("parameter detections[1]: score must be in [0, 1], got 2"));
  EXPECT_THAT(ErrorOf([&] { slam.Track(ToImageView(blank.rgb), depth, 1.0, {}, 2.5); }),
              HasSubstr("parameter depth_delay: must be under a second either way, got 2.5"));
  slam.Track(ToImageView(blank.rgb), depth, 1.0, {});
  EXPECT_THAT(ErrorOf([&] { slam.Track(ToImageView(blank.rgb), depth, 1.0, {}); }),
              HasSubstr("parameter timestamp: frames must come in time order"));
}

TEST(System, RejectsOptionsThatCannotWork) {
  EXPECT_THAT(ErrorOf([] { System(WithFilter("hoid5d")); }), HasSubstr("parameter filter"));
  EXPECT_THAT(ErrorOf([] { System(WithFilter("hoid2d", [](Options& o) { o.detector = DetectorKind::kNone; })); }),
              HasSubstr("parameter detector: filter hoid2d needs detections"));
  EXPECT_THAT(ErrorOf([] { System(WithFilter("", [](Options& o) { o.detector = DetectorKind::kOnnx; })); }),
              HasSubstr("parameter model: the ONNX detector needs a model file"));
  EXPECT_THAT(ErrorOf([] { System(WithFilter("", [](Options& o) { o.realtime = o.deterministic = true; })); }), HasSubstr("cannot go with"));
  EXPECT_THAT(ErrorOf([] { System(WithFilter("", [](Options& o) { o.settings = "/nonexistent/TUM9.yaml"; })); }), HasSubstr("/nonexistent/TUM9.yaml"));
}

}  // namespace
}  // namespace hoidslam
