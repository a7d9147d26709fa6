#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/hoidslam.h"
#include "hoidslam/hoidslam_opencv.h"
#include "hoidslam/api/convert.h"
#include "hoidslam/detect/file_detector.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/report/html_report.h"
#include "hoidslam/synth/test_scenarios.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

// After Eigen: the server library brings <resolv.h>, whose macro _res would rename a parameter of Eigen's.
#include <httplib.h>

namespace hoidslam {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
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

// The frames of a short synthetic walk rendered into dir/walk: `count` frames, every 4th of walking_xyz.
std::vector<core::RgbdFrame> RenderedWalk(const testing::TempDir& dir, const fs::path& tum_dir, std::size_t count) {
  const io::RgbdSequence sequence =
      io::RgbdSequence::OpenTum(synth::fixtures::RenderShortWalk(dir / "walk", tum_dir, count));
  std::vector<core::RgbdFrame> frames;
  for (std::size_t i = 0; i < sequence.size(); ++i) frames.push_back(sequence.LoadFrame(i));
  return frames;
}

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

// A camera thread and a replay thread, a viewer reading the map: Track from four threads and reads from a fifth
// (run under ThreadSanitizer in CI). Each call is either tracked whole or refused for coming after a newer frame;
// the frames tracked keep their time order, and the trajectory read at the end is theirs.
TEST(System, TracksFromFourThreadsWhileAFifthReadsTheMap) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const std::vector<core::RgbdFrame> frames = RenderedWalk(dir, tum_dir, 40);

  System slam(WithFilter("none"));
  std::atomic<std::size_t> next{0};
  std::atomic<int> tracking_threads{4};
  std::mutex results_mutex;
  std::vector<FrameResult> results;
  std::vector<std::string> other_errors;
  std::atomic<std::size_t> refused{0};
  const auto track = [&] {
    for (std::size_t i; (i = next++) < frames.size();) {
      try {
        FrameResult r = Track(slam, frames[i].rgb, frames[i].depth, frames[i].timestamp);
        const std::lock_guard lock(results_mutex);
        results.push_back(std::move(r));
      } catch (const InputError& e) {
        if (std::string(e.what()).find("frames must come in time order") != std::string::npos) {
          ++refused;
        } else {
          const std::lock_guard lock(results_mutex);
          other_errors.emplace_back(e.what());
        }
      }
    }
    --tracking_threads;
  };
  std::size_t reads = 0;
  bool keyframes_in_order = true, points_finite = true;
  const auto read = [&] {
    while (tracking_threads > 0) {
      const std::vector<StampedPose> keyframes = slam.KeyFrames();
      keyframes_in_order &= std::is_sorted(keyframes.begin(), keyframes.end(),
                                           [](const auto& a, const auto& b) { return a.timestamp < b.timestamp; });
      for (const MapPoint& p : slam.MapPoints()) {
        points_finite &= std::all_of(p.position.begin(), p.position.end(), [](double x) { return std::isfinite(x); });
      }
      slam.Trajectory();
      ++reads;
    }
  };
  {
    std::vector<std::jthread> threads;
    for (int t = 0; t < 4; ++t) threads.emplace_back(track);
    threads.emplace_back(read);
  }
  EXPECT_THAT(other_errors, ::testing::IsEmpty());
  EXPECT_EQ(results.size() + refused, frames.size());
  EXPECT_GT(reads, 0U);
  EXPECT_TRUE(keyframes_in_order);
  EXPECT_TRUE(points_finite);
  // Frames are numbered in the order they were tracked, and that order is their time order.
  std::sort(results.begin(), results.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
  std::size_t tracked = 0;
  for (std::size_t k = 0; k < results.size(); ++k) {
    EXPECT_EQ(results[k].index, k);
    if (k > 0) {
      EXPECT_GT(results[k].timestamp, results[k - 1].timestamp);
    }
    tracked += results[k].T_wc ? 1 : 0;
  }
  EXPECT_GT(tracked, 0U);
  slam.Finish();
  EXPECT_EQ(slam.Trajectory().size(), tracked);
}

// A program's own camera: intrinsics and depth scale from its SDK, millimetre depth as RealSense, OpenNI and Azure
// Kinect give it. Tracked as the same frames in TUM's units are; the same millimetres with the default 5000 units a
// metre are refused on the first frame, naming depth and the fix.
TEST(System, ACameraGivenByValuesTakesMillimetreDepthAndTheWrongUnitIsRefused) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const std::vector<core::RgbdFrame> frames = RenderedWalk(dir, tum_dir, 20);
  const core::CameraIntrinsics tum3;  // the synthetic camera's intrinsics
  Options options = WithFilter("none", kDeterministic);
  options.camera = Camera{tum3.fx, tum3.fy, tum3.cx, tum3.cy, {}, 640, 480, 0.001, 0.075};
  System camera(options);
  System defaults(WithFilter("none"));
  std::size_t tracked = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const core::RgbdFrame& frame = frames[i];
    cv::Mat millimetres;
    frame.depth.convertTo(millimetres, CV_16UC1, 1000.0);
    tracked += Track(camera, frame.rgb, millimetres, frame.timestamp).T_wc ? 1 : 0;
    if (i == 0) {
      EXPECT_THAT(ErrorOf([&] { Track(defaults, frame.rgb, millimetres, frame.timestamp); }),
                  AllOf(HasSubstr("parameter depth: the depth looks too near for a room: read with 5000 units a "
                                  "metre"),
                        HasSubstr("1000 units a metre would put it where a room is")));
    }
  }
  EXPECT_EQ(tracked, frames.size());
  EXPECT_EQ(camera.depth_factor(), 1000.0);

  options.camera->cx = 700.0;
  EXPECT_THAT(ErrorOf([&] { System{options}; }), HasSubstr("parameter camera.cx: must be in [0, width=640], got 700"));
  options.camera->cx = 320.0;
  options.camera->depth_scale = 0.0;
  EXPECT_THAT(ErrorOf([&] { System{options}; }), HasSubstr("parameter camera.depth_scale: must be > 0"));
}

// The live viewer from a program: a page gets the frames it tracks and, once finished, the map it writes.
TEST(System, ShowsTheSessionInTheViewerWhenAskedAndOnlyThen) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const std::vector<core::RgbdFrame> frames = RenderedWalk(dir, tum_dir, 20);
  EXPECT_EQ(System(WithFilter("none")).ViewerUrl(), "");
  System system(WithFilter("hoid2d", [](Options& o) { o.view.emplace().port = 0; }));
  const std::string url = system.ViewerUrl();
  ASSERT_THAT(url, ::testing::StartsWith("http://127.0.0.1:"));
  for (const core::RgbdFrame& frame : frames) Track(system, frame.rgb, frame.depth, frame.timestamp);
  system.Finish();
  nlohmann::json map, frame, status;
  std::string buffer;
  httplib::Client client(url.substr(0, url.size() - 1));
  client.Get("/events", [&](const char* data, std::size_t length) {
    buffer.append(data, length);
    for (std::size_t end; (end = buffer.find("\n\n")) != std::string::npos; buffer.erase(0, end + 2)) {
      const std::string message = buffer.substr(0, end);
      const std::size_t data_at = message.find("\ndata: ");
      if (data_at == std::string::npos) continue;
      const nlohmann::json json = nlohmann::json::parse(message.substr(data_at + 7));
      if (message.starts_with("event: map")) map = json;
      if (message.starts_with("event: frame")) frame = json;
      if (message.starts_with("event: status")) status = json;
    }
    return status.is_null();
  });
  ASSERT_FALSE(map.is_null());
  EXPECT_EQ(map["maps"][0]["points"], system.MapPoints().size());
  EXPECT_EQ(frame["index"], frames.size() - 1);
  EXPECT_EQ(status["state"], "finished");
}

// What the command does, from a program: every file of a run folder (read back as `hoidslam report` reads it), a
// map file that a second session localises in, and a reset that starts again from nothing.
TEST(System, SavesARunFolderAndAMapAndResets) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const std::vector<core::RgbdFrame> frames = RenderedWalk(dir, tum_dir, 20);
  System slam(WithFilter("none", kDeterministic));
  for (const core::RgbdFrame& frame : frames) Track(slam, frame.rgb, frame.depth, frame.timestamp);
  slam.Save(dir / "out");
  const report::RunReport report = report::LoadRunReport(dir / "out", {});
  EXPECT_EQ(report.frames, frames.size());
  EXPECT_EQ(report.tracked, frames.size());
  EXPECT_EQ(report.frame_log.size(), frames.size());
  EXPECT_TRUE(fs::exists(dir / "out" / "report.html"));
  const nlohmann::json summary = nlohmann::json::parse(testing::ReadText(dir / "out" / "summary.json"));
  EXPECT_EQ(summary["provenance"]["settings"]["chosen"], "default");
  EXPECT_EQ(summary["provenance"]["version"], Version());
  EXPECT_TRUE(summary["provenance"]["command_line"].is_null());

  slam.SaveMap(dir / "walk.hmap");
  Options localize = WithFilter("none", kDeterministic);
  localize.load_map = dir / "walk.hmap";
  localize.localization = true;
  System again(localize);
  std::size_t tracked = 0;
  for (const core::RgbdFrame& frame : frames) tracked += Track(again, frame.rgb, frame.depth, frame.timestamp).T_wc ? 1 : 0;
  EXPECT_GE(tracked, frames.size() - 1);  // the first frame is relocalised, provisionally
  EXPECT_EQ(again.KeyFrames().size(), slam.KeyFrames().size());  // localisation adds no keyframe

  again.Reset();
  EXPECT_EQ(Track(again, frames[0].rgb, frames[0].depth, frames[0].timestamp).index, 0U);  // an earlier time is fine
  localize.load_map.clear();
  EXPECT_THAT(ErrorOf([&] { System{localize}; }), HasSubstr("parameter localization: needs a map"));
  EXPECT_THAT(ErrorOf([&] { slam.SaveMap(dir / "no" / "such" / "folder.hmap"); }), HasSubstr("folder.hmap"));
}

TEST(System, SavesTheDenseMapWithTheOptionsGiven) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const std::vector<core::RgbdFrame> frames = RenderedWalk(dir, tum_dir, 10);
  Options options = WithFilter("none", kDeterministic);
  options.dense = Dense{.voxel_size = 0.02, .keep_seen_through = true};
  System slam(options);
  for (const core::RgbdFrame& frame : frames) Track(slam, frame.rgb, frame.depth, frame.timestamp);
  slam.Save(dir / "out");
  EXPECT_TRUE(fs::exists(dir / "out" / "mesh.ply"));
  const nlohmann::json dense = nlohmann::json::parse(testing::ReadText(dir / "out" / "summary.json"))["dense"];
  EXPECT_EQ(dense["options"]["voxel_size"], 0.02);
  EXPECT_EQ(dense["options"]["truncation"], 0.08);
  EXPECT_EQ(dense["options"]["keep_seen_through"], true);
  EXPECT_EQ(dense["mesh"]["seen_through_vertices"], 0);
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
