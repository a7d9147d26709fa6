#include "hoidslam/pipeline/run.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/detect/file_detector.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/pipeline/playback.h"
#include "hoidslam/pipeline/session.h"
#include "hoidslam/synth/test_scenarios.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::pipeline {
namespace {

namespace fs = std::filesystem;

fs::path RenderWalking(const testing::TempDir& dir, const fs::path& tum_dir, std::size_t frames) {
  return synth::fixtures::RenderShortWalk(dir / "walking_xyz", tum_dir, frames);
}

std::vector<nlohmann::json> ReadLog(const fs::path& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

RunOptions Hoid2d() {
  RunOptions options = RunOptions::FromSettings(io::Settings{});
  options.exclusion.hoid.mode = core::FilterMode::kHoid2d;
  options.system.deterministic = true;
  return options;
}

// Replays a detections file but fails on chosen frames, as a flaky network or a file with holes would.
class FlakyDetector final : public detect::Detector {
 public:
  FlakyDetector(const fs::path& file, std::vector<std::size_t> failing) : inner_(file), failing_(std::move(failing)) {}
  std::vector<core::Detection> Detect(double timestamp, const cv::Mat& bgr) override {
    const bool fail = std::find(failing_.begin(), failing_.end(), calls_++) != failing_.end();
    if (fail) throw core::InputError("no detections for this frame");
    return inner_.Detect(timestamp, bgr);
  }
  std::string Name() const override { return "flaky"; }

 private:
  detect::FileDetector inner_;
  std::vector<std::size_t> failing_;
  std::size_t calls_ = 0;
};

TEST(RunSequence, TracksEveryFrameAndWritesCompleteOutputs) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path sequence_root = RenderWalking(dir, tum_dir, 40);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(sequence_root);
  fs::create_directories(dir / "out");
  FlakyDetector detector(sequence_root / "detections.jsonl", {5, 6});
  const RunSummary summary = RunSequence(sequence, detector, Hoid2d(), dir / "out");

  EXPECT_EQ(summary.frames, 40U);
  EXPECT_EQ(summary.tracked, 40U);
  EXPECT_EQ(summary.lost + summary.before_initialization, 0U);
  EXPECT_EQ(summary.detector_failures, 2U);
  EXPECT_GT(summary.keypoints_dropped, 0U);  // people are in view
  EXPECT_GT(summary.keyframes, 1U);
  EXPECT_GT(summary.map_points, 500U);
  ASSERT_EQ(summary.times.size(), 40U);

  EXPECT_EQ(io::ReadTumTrajectory(dir / "out" / "trajectory.txt").size(), 40U);
  EXPECT_EQ(io::ReadTumTrajectory(dir / "out" / "keyframes.txt").size(), summary.keyframes);
  EXPECT_TRUE(fs::exists(dir / "out" / "map.ply"));
  const std::vector<nlohmann::json> log = ReadLog(dir / "out" / "frames.jsonl");
  ASSERT_EQ(log.size(), 40U);
  EXPECT_EQ(log[0]["method"], "initialization");
  EXPECT_EQ(log[10]["state"], "ok");
  EXPECT_GE(log[10]["features"]["inliers"].get<int>(), 30);
  EXPECT_TRUE(log[5].contains("detector_error"));
  EXPECT_FALSE(log[7].contains("detector_error"));
  bool person_logged = false;
  for (const auto& entry : log) {
    for (const auto& d : entry["dynamic"]) person_logged |= d["label"] == "person" && d["reason"] == "person";
  }
  EXPECT_TRUE(person_logged);

  // Scored against the synthetic sequence's moving masks, frame by frame and in total.
  ASSERT_TRUE(summary.exclusion.has_value());
  EXPECT_GT(summary.exclusion->moving_dropped, 0U);
  EXPECT_LT(summary.exclusion->Leaked(), 0.2);  // ground-truth boxes cover the people
  EXPECT_LT(summary.exclusion->Wasted(), 0.2);
  EXPECT_TRUE(summary.still_people_scored);  // the sequence has people masks
  EXPECT_LE(summary.exclusion->static_dropped_without_depth + summary.exclusion->static_dropped_on_still_people,
            summary.exclusion->static_dropped);
  std::size_t logged_dropped = 0;
  std::size_t logged_on_still_people = 0;
  for (const auto& entry : log) {
    logged_dropped += entry["exclusion"]["moving_dropped"].get<std::size_t>() +
                      entry["exclusion"]["static_dropped"].get<std::size_t>();
    logged_on_still_people += entry["exclusion"]["static_dropped_on_still_people"].get<std::size_t>();
  }
  EXPECT_EQ(logged_dropped, summary.keypoints_dropped);
  EXPECT_EQ(logged_on_still_people, summary.exclusion->static_dropped_on_still_people);

  // Six annotated frames in the middles of six equal parts of the run.
  std::vector<std::string> snapshots;
  for (const auto& file : fs::directory_iterator(dir / "out" / "snapshots")) {
    snapshots.push_back(file.path().filename().string());
  }
  std::sort(snapshots.begin(), snapshots.end());
  EXPECT_EQ(snapshots, (std::vector<std::string>{"000003.jpg", "000010.jpg", "000016.jpg", "000023.jpg",
                                                 "000030.jpg", "000036.jpg"}));
  EXPECT_EQ(cv::imread((dir / "out" / "snapshots" / "000030.jpg").string()).size(), cv::Size(640, 480));
}

TEST(RunSequence, TheKeypointBudgetGoesToWhatTheFilterKeeps) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path sequence_root = RenderWalking(dir, tum_dir, 40);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(sequence_root);
  std::map<KeypointBudget, std::vector<nlohmann::json>> logs;
  std::map<KeypointBudget, RunSummary> summaries;
  for (const KeypointBudget budget : {KeypointBudget::kStatic, KeypointBudget::kImage}) {
    const fs::path out = dir / std::string(ToString(budget));
    fs::create_directories(out);
    detect::FileDetector detector(sequence_root / "detections.jsonl");
    RunOptions options = Hoid2d();
    options.keypoint_budget = budget;
    summaries[budget] = RunSequence(sequence, detector, options, out);
    logs[budget] = ReadLog(out / "frames.jsonl");
  }
  EXPECT_EQ(summaries[KeypointBudget::kStatic].tracked, 40U);
  // The first extraction and the filter's verdict on it are the same; what tracking gets differs.
  EXPECT_EQ(summaries[KeypointBudget::kStatic].keypoints_dropped, summaries[KeypointBudget::kImage].keypoints_dropped);
  int crowded = 0;
  for (std::size_t i = 0; i < 40; ++i) {
    const nlohmann::json& mine = logs[KeypointBudget::kStatic][i]["features"];
    const nlohmann::json& image = logs[KeypointBudget::kImage][i]["features"];
    EXPECT_EQ(image["kept"], image["extracted"].get<int>() - image["dropped"].get<int>()) << "frame " << i;
    if (mine["dropped"].get<int>() < 200) continue;
    ++crowded;
    EXPECT_GE(mine["kept"].get<int>(), 900) << "frame " << i;
  }
  EXPECT_GT(crowded, 5) << "people cover part of the view in some frames";
  // What tracking gets is not more on moving things than before: the second extraction avoids the dynamic boxes
  // (it adds keypoints on what moves outside them, a thing carried without a person's box, only in proportion;
  // looking inside the boxes would add hundreds).
  const auto share_on_moving = [&](KeypointBudget budget) {
    const ExclusionCounts& counts = *summaries[budget].exclusion;
    return static_cast<double>(counts.moving_kept) / static_cast<double>(counts.moving_kept + counts.static_kept);
  };
  EXPECT_LE(share_on_moving(KeypointBudget::kStatic), 1.5 * share_on_moving(KeypointBudget::kImage));
  EXPECT_GT(summaries[KeypointBudget::kStatic].keypoints_tracked, summaries[KeypointBudget::kImage].keypoints_tracked);
}

TEST(RunSequence, StopsWhenAskedAndKeepsWhatWasDone) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path sequence_root = RenderWalking(dir, tum_dir, 20);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(sequence_root);
  fs::create_directories(dir / "out");
  detect::FileDetector detector(sequence_root / "detections.jsonl");
  int polls = 0;
  const RunSummary summary = RunSequence(sequence, detector, Hoid2d(), dir / "out",
                                         {.stop_requested = [&polls] { return ++polls > 12; }});
  EXPECT_TRUE(summary.interrupted);
  EXPECT_EQ(summary.frames, 12U);
  EXPECT_EQ(ReadLog(dir / "out" / "frames.jsonl").size(), 12U);
  EXPECT_EQ(io::ReadTumTrajectory(dir / "out" / "trajectory.txt").size(), summary.tracked);
}

// What a viewer follows: the session from its start to its end, every frame tracked, and a paused playback that
// lets exactly the frames stepped through go. The session is let go of before it goes when the run throws too.
TEST(RunSequence, HooksFollowTheSessionAndAPausedPlaybackLetsOnlyTheStepsGo) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path sequence_root = RenderWalking(dir, tum_dir, 12);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(sequence_root);
  fs::create_directories(dir / "out");
  detect::FileDetector detector(sequence_root / "detections.jsonl");
  Playback playback;
  playback.Pause();
  std::atomic<int> started{0}, tracked{0}, finished{0};
  RunHooks hooks{.playback = &playback,
                 .started = [&](const Session&) { ++started; },
                 .frame_tracked = [&](std::size_t, const core::RgbdFrame&, const FrameOutcome&) { ++tracked; },
                 .finished = [&](const Session& session) { finished += session.finished() ? 1 : 100; }};
  std::thread stepper([&] {
    for (int step = 1; step <= 3; ++step) {
      playback.Step();
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
      while (tracked.load() < step && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_EQ(tracked.load(), 3);  // paused after the steps
    playback.Play();
  });
  const RunSummary summary = RunSequence(sequence, detector, Hoid2d(), dir / "out", hooks);
  stepper.join();
  EXPECT_EQ(summary.frames, 12U);
  EXPECT_EQ(started.load(), 1);
  EXPECT_EQ(tracked.load(), 12);
  EXPECT_EQ(finished.load(), 1);  // once, after Finish

  // A frame of another size stops the run with an error naming it; the session is let go of first.
  cv::imwrite(sequence.entry(5).rgb_path.string(), cv::Mat(240, 320, CV_8UC3, cv::Scalar(0, 0, 0)));
  finished = 0;
  RunHooks watching{.finished = [&](const Session&) { ++finished; }};
  fs::create_directories(dir / "out2");
  EXPECT_THROW(RunSequence(io::RgbdSequence::OpenTum(sequence_root), detector, Hoid2d(), dir / "out2", watching),
               core::InputError);
  EXPECT_EQ(finished.load(), 1);
}

TEST(RunSequence, BlackFramesAreLostNotGuessed) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path sequence_root = RenderWalking(dir, tum_dir, 30);
  // Frames 10..14 go black (a covered lens) with no depth: nothing to track there.
  const io::RgbdSequence original = io::RgbdSequence::OpenTum(sequence_root);
  for (std::size_t i = 10; i < 15; ++i) {
    cv::imwrite(original.entry(i).rgb_path.string(), cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0)));
    cv::imwrite(original.entry(i).depth_path.string(), cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)));
  }
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(sequence_root);
  fs::create_directories(dir / "out");
  detect::FileDetector detector(sequence_root / "detections.jsonl");
  const RunSummary summary = RunSequence(sequence, detector, Hoid2d(), dir / "out");
  EXPECT_EQ(summary.frames, 30U);
  EXPECT_GE(summary.lost, 5U);
  EXPECT_EQ(summary.tracked + summary.lost, 30U);
  // The black frames have no pose in the trajectory.
  const core::Trajectory trajectory = io::ReadTumTrajectory(dir / "out" / "trajectory.txt");
  for (const core::StampedPose& pose : trajectory) {
    for (std::size_t i = 10; i < 15; ++i) EXPECT_NE(pose.timestamp, original.entry(i).rgb_timestamp);
  }
}

// The detector in its own thread, at a live camera's pace: frames 133 ms apart, the detector taking 60 ms, so each
// frame is judged by the detections of the frame before it, carried to it.
TEST(RunSequenceRealTime, JudgesEachFrameByTheNewestDetectionsCarriedToIt) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path sequence_root = RenderWalking(dir, tum_dir, 40);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(sequence_root);
  fs::create_directories(dir / "out");
  FlakyDetector detector(sequence_root / "detections.jsonl", {3});
  RunOptions options = Hoid2d();
  options.system.deterministic = false;
  options.realtime.enabled = true;
  options.realtime.pace = true;
  options.realtime.detector_latency_ms = 60.0;
  const RunSummary summary = RunSequence(sequence, detector, options, dir / "out");

  EXPECT_EQ(summary.frames + summary.dropped, 40U);
  EXPECT_EQ(summary.tracked, summary.frames);
  ASSERT_EQ(summary.detection_age_frames.size(), summary.frames);
  EXPECT_EQ(summary.detection_age_frames[0], 0U);  // the first frame waits for its own
  const std::vector<nlohmann::json> log = ReadLog(dir / "out" / "frames.jsonl");
  ASSERT_EQ(log.size(), summary.frames);
  std::size_t late = 0;
  for (const nlohmann::json& entry : log) {
    const nlohmann::json& detections = entry.at("detections");
    const auto frame = entry["frame"].get<std::size_t>();
    const auto of = detections["frame"].get<std::size_t>();
    ASSERT_LE(of, frame);
    EXPECT_EQ(detections["age_frames"].get<std::size_t>(), frame - of);
    EXPECT_GE(detections["detector_ms"].get<double>(), 60.0);
    if (of < frame) ++late;
  }
  EXPECT_LE(summary.detector_failures, 1U);  // frame 3's failure is seen only if the detector took frame 3
  EXPECT_EQ(io::ReadTumTrajectory(dir / "out" / "trajectory.txt").size(), summary.tracked);
  // When tracking a frame takes well under the detector's 60 ms (in a Release build, not under the slow
  // ThreadSanitizer build, which drops most frames), the frames after the first get the detections of the one
  // before, carried by their keypoints, and they still cover the people. On a busy machine a frame whose feature
  // extraction outlasts the detector may find its own detections ready: a few such frames are allowed.
  if (summary.dropped == 0) {
    EXPECT_GE(late, 35U);
    EXPECT_GT(summary.boxes_carried_by_keypoints, 0U);
    ASSERT_TRUE(summary.exclusion.has_value());
    EXPECT_LT(summary.exclusion->Leaked(), 0.2);
  }
}

TEST(RunSequenceRealTime, APacedRunDropsTheFramesThatArriveWhileItIsBusy) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  testing::TempDir dir;
  const fs::path sequence_root = RenderWalking(dir, tum_dir, 16);  // 16 frames, 0.13 s apart
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(sequence_root);
  fs::create_directories(dir / "out");
  detect::FileDetector detector(sequence_root / "detections.jsonl");
  RunOptions options = Hoid2d();
  options.system.deterministic = false;
  options.realtime.enabled = true;
  options.realtime.pace = true;
  options.realtime.detector_latency_ms = 500.0;  // the first frame waits for it: three frames come meanwhile
  const RunSummary summary = RunSequence(sequence, detector, options, dir / "out");

  EXPECT_GE(summary.dropped, 2U);
  EXPECT_EQ(summary.frames + summary.dropped, 16U);
  const std::vector<nlohmann::json> log = ReadLog(dir / "out" / "frames.jsonl");
  ASSERT_EQ(log.size(), summary.frames);
  // Each frame follows the one before it and the frames dropped between them.
  std::size_t logged_dropped = 0;
  for (std::size_t i = 0; i < log.size(); ++i) {
    const auto dropped_before = log[i].value("dropped_before", std::size_t{0});
    const std::size_t expected = i == 0 ? 0 : log[i - 1]["frame"].get<std::size_t>() + 1 + dropped_before;
    EXPECT_EQ(log[i]["frame"].get<std::size_t>(), expected) << i;
    logged_dropped += dropped_before;
  }
  EXPECT_EQ(logged_dropped, summary.dropped);
  EXPECT_EQ(io::ReadTumTrajectory(dir / "out" / "trajectory.txt").size(), summary.tracked);
}

TEST(RunOptions, TheRealTimeModeCannotBeDeterministic) {
  RunOptions options = Hoid2d();
  options.realtime.enabled = true;
  try {
    options.Check();
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--realtime"), std::string::npos);
  }
  options.system.deterministic = false;
  options.realtime.detector_latency_ms = -1;
  EXPECT_THROW(options.Check(), core::InputError);
  options.realtime.detector_latency_ms = 0;
  options.realtime.preload_megabytes = 0;
  try {
    options.Check();
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--preload-mb"), std::string::npos);
  }
}

}  // namespace
}  // namespace hoidslam::pipeline
