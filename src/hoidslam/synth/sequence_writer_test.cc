#include "hoidslam/synth/sequence_writer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <stdexcept>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/error.h"
#include "hoidslam/io/detections_file.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/synth/renderer.h"
#include "hoidslam/synth/static_geometry.h"
#include "hoidslam/synth/test_scenarios.h"
#include "hoidslam/synth/world.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::synth {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::map<std::string, std::string> ReadAllFiles(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    files[fs::relative(entry.path(), root).string()] = {std::istreambuf_iterator<char>(in), {}};
  }
  return files;
}

SynthOptions Options(const fs::path& out, int threads = 2) {
  SynthOptions options;
  options.out = out;
  options.threads = threads;
  return options;
}

// A frame of a written sequence re-rendered without noise, with what the world says about it.
struct CleanFrame {
  SceneSnapshot snapshot;
  RenderOutput rendered;
};

std::vector<CleanFrame> RenderClean(const Scenario& scenario, const core::Trajectory& groundtruth) {
  const TextureSet textures(scenario.textures);
  const World world(scenario, textures);
  const Renderer renderer(core::CameraIntrinsics{}, textures);
  std::vector<CleanFrame> frames;
  for (const core::StampedPose& pose : groundtruth) {
    CleanFrame frame;
    frame.snapshot = world.Snapshot(pose.timestamp - groundtruth.front().timestamp);
    frame.rendered = renderer.Render(frame.snapshot, pose.T_wc);
    frames.push_back(std::move(frame));
  }
  return frames;
}

TEST(SequenceWriter, WritesATumSequenceTheReadersAccept) {
  testing::TempDir temp;
  const Scenario scenario = fixtures::SmallScenario(fixtures::kWalkThenStop, 6, "xyz");
  const SynthResult result = WriteSequence(scenario, Options(temp / "seq"));
  EXPECT_EQ(result.frames, 6U);
  EXPECT_FALSE(fs::exists(temp / "seq.partial-"));

  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / "seq");
  ASSERT_EQ(sequence.size(), 6U);
  EXPECT_EQ(sequence.name(), "seq");
  const core::RgbdFrame frame = sequence.LoadFrame(3);
  EXPECT_EQ(frame.rgb.size(), cv::Size(640, 480));
  EXPECT_EQ(cv::imread((temp / "seq" / "mask" / fs::path(sequence.entry(3).rgb_path).filename()).string(),
                       cv::IMREAD_UNCHANGED)
                .type(),
            CV_8U);

  const io::DetectionsFile detections = io::DetectionsFile::Read(temp / "seq" / "detections.jsonl");
  EXPECT_NO_THROW(detections.CheckCovers(sequence.Timestamps(), sequence.name()));
  ASSERT_TRUE(detections.header().has_value());
  EXPECT_EQ(detections.header()->detector, "synthetic ground truth");
  EXPECT_EQ(detections.header()->sequence, "seq");
  const io::FrameDetections* first = detections.Find(sequence.Timestamps().front());
  ASSERT_NE(first, nullptr);
  EXPECT_THAT(first->detections, ::testing::Contains(::testing::Field(&core::Detection::label, "person")));
  EXPECT_THAT(first->detections, ::testing::Contains(::testing::Field(&core::Detection::label, "tv")));

  const core::Trajectory groundtruth = io::ReadTumTrajectory(temp / "seq" / "groundtruth.txt");
  const CameraPath path = ScenarioCameraPath(scenario, {});
  ASSERT_EQ(groundtruth.size(), 6U);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(groundtruth[i].timestamp, path.frames()[i].timestamp, 1e-6);
    EXPECT_TRUE(groundtruth[i].T_wc.isApprox(path.frames()[i].T_wc, 1e-6));
  }
  EXPECT_EQ(sequence.groundtruth().size(), 6U);
  // The event log is JSON Lines; the walker's entry is its first line.
  std::ifstream events(temp / "seq" / "events.jsonl");
  std::string line;
  ASSERT_TRUE(std::getline(events, line));
  const nlohmann::json enter = nlohmann::json::parse(line);
  EXPECT_EQ(enter.at("person"), "walker");
  EXPECT_EQ(enter.at("action"), "enter");
  EXPECT_NEAR(enter.at("time").get<double>(), path.frames()[0].timestamp, 1e-6);
  // The scenario copy renders the same thing again.
  const Scenario copy = LoadScenario((temp / "seq" / "scenario.json").string());
  EXPECT_EQ(copy.people.size(), 1U);
  EXPECT_EQ(copy.seed, scenario.seed);
  EXPECT_EQ(copy.max_frames, scenario.max_frames);
}

TEST(SequenceWriter, WritesTheStaticGeometryAndTheSpaceTheWalkerFilled) {
  testing::TempDir temp;
  const Scenario scenario = fixtures::SmallScenario(fixtures::kWalkThenStop, 6, "xyz");
  WriteSequence(scenario, Options(temp / "seq"));
  const io::TriangleMesh mesh = io::ReadPlyMesh(temp / "seq" / "static_geometry.ply");
  const io::VoxelCentres volume = io::ReadVoxelCentresPly(temp / "seq" / "moving_volume.ply");
  EXPECT_THAT(ReadAllFiles(temp / "seq").at("static_geometry.ply"),
              HasSubstr("\ncomment hoidslam static geometry of seq\n"));

  // Nobody touches anything: the mesh is every box but the walker's, the volume the walker's cells at each frame.
  const World world(scenario, fixtures::DefaultTextures());
  const core::Trajectory groundtruth = io::ReadTumTrajectory(temp / "seq" / "groundtruth.txt");
  io::TriangleMesh expected_mesh;
  for (const SceneInstance& instance : world.Snapshot(0.0).instances) {
    if (instance.label == "person") continue;
    for (const Box& box : instance.parts) AppendBoxMesh(box, expected_mesh);
  }
  VoxelCells expected_cells(kMovingVolumeVoxelSize);
  for (const core::StampedPose& pose : groundtruth) {
    for (const SceneInstance& instance : world.Snapshot(pose.timestamp - groundtruth.front().timestamp).instances) {
      if (instance.label != "person") continue;
      for (const Box& box : instance.parts) expected_cells.AddBox(box);
    }
  }
  EXPECT_EQ(mesh.vertices, expected_mesh.vertices);
  EXPECT_EQ(mesh.triangles, expected_mesh.triangles);
  EXPECT_EQ(volume.voxel_size, kMovingVolumeVoxelSize);
  EXPECT_GT(volume.centres.size(), 10000U);
  EXPECT_EQ(volume.centres, expected_cells.Centres().centres);
}

TEST(SequenceWriter, OneSeedGivesByteIdenticalFilesWhateverTheThreads) {
  testing::TempDir temp;
  Scenario scenario = fixtures::SmallScenario(fixtures::kWalkThenStop, 10, "xyz");
  scenario.detector_noise.box_jitter = 0.05;
  scenario.detector_noise.false_positive_rate = 0.5;
  // Same folder name (the detections header names it), different parents. Five threads share 10 frames
  // unevenly, so frames finish out of order.
  WriteSequence(scenario, Options(temp / "a" / "seq", 5));
  WriteSequence(scenario, Options(temp / "b" / "seq", 1));
  const auto a = ReadAllFiles(temp / "a" / "seq");
  const auto b = ReadAllFiles(temp / "b" / "seq");
  ASSERT_EQ(a.size(), 4U * 10U + 10U);  // rgb, depth, mask, people per frame; 3 lists, gt, 2 detections, events,
                                        // scenario, static geometry, moving volume
  for (const auto& [name, bytes] : a) {
    ASSERT_TRUE(b.contains(name)) << name;
    EXPECT_TRUE(bytes == b.at(name)) << name << " differs";
  }
  // Another seed changes the noise, not the lists.
  scenario.seed += 1;
  WriteSequence(scenario, Options(temp / "c" / "seq", 2));
  const auto c = ReadAllFiles(temp / "c" / "seq");
  EXPECT_EQ(c.at("rgb.txt"), a.at("rgb.txt"));
  int images_compared = 0;
  for (const auto& [name, bytes] : a) {
    if (!name.starts_with("rgb/") && !name.starts_with("depth/")) continue;
    ASSERT_TRUE(c.contains(name)) << name;
    EXPECT_NE(c.at(name), bytes) << name;
    ++images_compared;
  }
  EXPECT_EQ(images_compared, 20);
  EXPECT_NE(c.at("detections.jsonl"), a.at("detections.jsonl"));
}

TEST(SequenceWriter, BoxesEncloseTheVisiblePixelsOfTheirInstance) {
  const Scenario scenario = fixtures::SmallScenario(fixtures::kWalkThenStop, 3, "xyz");
  const CameraPath path = ScenarioCameraPath(scenario, {});
  const std::vector<CleanFrame> frames = RenderClean(scenario, path.Trajectory());
  for (const CleanFrame& frame : frames) {
    const cv::Mat& ids = frame.rendered.instance;
    const std::vector<core::Detection> boxes = GroundTruthBoxes(ids, frame.snapshot, 50);
    ASSERT_GE(boxes.size(), 5U);
    std::map<std::string, int> by_label;
    for (const SceneInstance& instance : frame.snapshot.instances) {
      if (instance.label.empty()) continue;
      const cv::Mat pixels = ids == instance.id;
      const int count = cv::countNonZero(pixels);
      const auto box = std::find_if(boxes.begin(), boxes.end(), [&](const core::Detection& d) {
        return d.label == instance.label && cv::countNonZero(pixels(cv::Rect(d.box))) == count;
      });
      if (count < 50) continue;
      ASSERT_NE(box, boxes.end()) << instance.label << " " << instance.id << " has no enclosing box";
      // Tight: every edge row and column of the box holds a pixel of the instance.
      const cv::Rect r(box->box);
      EXPECT_GT(cv::countNonZero(pixels.row(r.y).colRange(r.x, r.x + r.width)), 0);
      EXPECT_GT(cv::countNonZero(pixels.row(r.y + r.height - 1).colRange(r.x, r.x + r.width)), 0);
      EXPECT_GT(cv::countNonZero(pixels.col(r.x).rowRange(r.y, r.y + r.height)), 0);
      EXPECT_GT(cv::countNonZero(pixels.col(r.x + r.width - 1).rowRange(r.y, r.y + r.height)), 0);
      ++by_label[instance.label];
    }
    EXPECT_EQ(by_label["person"], 1);
  }
}

TEST(SequenceWriter, MasksMarkWhatMovesAndPeopleMasksMarkThePersonStillOrNot) {
  testing::TempDir temp;
  // The walker crosses the view for about a second and then stands still in it (10 Hz, 20 frames).
  const Scenario scenario = fixtures::SmallScenario(fixtures::kWalkThenStop, 20);
  WriteSequence(scenario, Options(temp / "seq"));
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / "seq");
  const std::vector<CleanFrame> frames = RenderClean(scenario, sequence.groundtruth());
  const World world(scenario, TextureSet(scenario.textures));
  int moving_frames = 0;
  int still_frames = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat mask =
        cv::imread((temp / "seq" / "mask" / sequence.entry(i).rgb_path.filename()).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat people =
        cv::imread((temp / "seq" / "people" / sequence.entry(i).rgb_path.filename()).string(), cv::IMREAD_UNCHANGED);
    bool visible_moving = false;
    for (const SceneInstance& instance : frames[i].snapshot.instances) {
      if (instance.moving && cv::countNonZero(frames[i].rendered.instance == instance.id) > 0) visible_moving = true;
    }
    const bool world_moving =
        !world.MovingAt(sequence.entry(i).rgb_timestamp - sequence.entry(0).rgb_timestamp).empty();
    EXPECT_EQ(cv::countNonZero(mask) > 0, visible_moving) << "frame " << i;
    EXPECT_EQ(visible_moving, world_moving) << "frame " << i;  // the walker is in view throughout
    // The mask is exactly the moving instance's pixels.
    const int walker = *world.InstanceId("walker");
    if (visible_moving) {
      EXPECT_EQ(cv::countNonZero(mask != (frames[i].rendered.instance == walker)), 0);
    }
    // The people mask is the walker's pixels whether they move or stand still.
    EXPECT_GT(cv::countNonZero(people), 0) << "frame " << i;
    EXPECT_EQ(cv::countNonZero(people != (frames[i].rendered.instance == walker)), 0) << "frame " << i;
    (world_moving ? moving_frames : still_frames) += 1;
  }
  EXPECT_GE(moving_frames, 5);
  EXPECT_GE(still_frames, 5);
}

TEST(SequenceWriter, MasksAreEmptyWithoutPeople) {
  testing::TempDir temp;
  WriteSequence(fixtures::SmallScenario("[]", 8, "xyz"), Options(temp / "seq"));
  for (const char* folder : {"mask", "people"}) {
    for (const auto& entry : fs::directory_iterator(temp / "seq" / folder)) {
      EXPECT_EQ(cv::countNonZero(cv::imread(entry.path().string(), cv::IMREAD_UNCHANGED)), 0) << entry.path();
    }
  }
  EXPECT_EQ(ReadAllFiles(temp / "seq").at("events.jsonl"), "");
  EXPECT_TRUE(io::ReadVoxelCentresPly(temp / "seq" / "moving_volume.ply").centres.empty());
}

TEST(SequenceWriter, PosesReprojectStaticPointsAndDepthAgreesWithTheGeometry) {
  testing::TempDir temp;
  const Scenario scenario = fixtures::SmallScenario("[]", 3, "halfsphere");
  WriteSequence(scenario, Options(temp / "seq"));
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / "seq");
  const std::vector<CleanFrame> frames = RenderClean(scenario, sequence.groundtruth());
  const core::CameraIntrinsics camera;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const core::Pose& T_wc = sequence.groundtruth()[i].T_wc;
    const cv::Mat& clean = frames[i].rendered.depth;
    const cv::Mat noisy = sequence.LoadFrame(i).depth;
    int floor_pixels = 0;
    int compared = 0;
    int within = 0;
    for (int v = 0; v < clean.rows; v += 4) {
      for (int u = 0; u < clean.cols; u += 4) {
        const float z = clean.at<float>(v, u);
        if (z <= 0.0F) continue;
        // The floor (instance 1) is the plane z = 0: the written pose puts the drawn point back on it.
        if (frames[i].rendered.instance.at<int>(v, u) == 1) {
          const Eigen::Vector3d p_w = T_wc * camera.Unproject(u, v, z);
          EXPECT_NEAR(p_w.z(), 0.0, 1e-3);
          ++floor_pixels;
        }
        const float measured = noisy.at<float>(v, u);
        if (measured <= 0.0F) continue;
        ++compared;
        within += std::abs(measured - z) <= 4.0 * core::KinectDepthSigma(z) + 2.0 / 5000.0 ? 1 : 0;
      }
    }
    EXPECT_GT(floor_pixels, 100);
    // Static points projected with the written pose land on the pixels where the renderer drew them: the
    // centres of the monitor screens and keyboards of the front desks.
    const World world(scenario, TextureSet(scenario.textures));
    for (const auto& [name, point] :
         {std::pair{"tv_1", Eigen::Vector3d(0.034, 0.0, 0.375)}, std::pair{"tv_2", Eigen::Vector3d(0.034, 0.0, 0.375)},
          std::pair{"keyboard_1", Eigen::Vector3d(0.0, 0.0, 0.024)},
          std::pair{"keyboard_2", Eigen::Vector3d(0.0, 0.0, 0.024)}}) {
      const Eigen::Vector3d p_c = T_wc.inverse() * (*world.ObjectPose(name, 0.0) * point);
      const Eigen::Vector2d px = camera.Project(p_c);
      const int u = static_cast<int>(std::lround(px.x()));
      const int v = static_cast<int>(std::lround(px.y()));
      ASSERT_TRUE(u >= 0 && v >= 0 && u < 640 && v < 480) << name;
      EXPECT_EQ(frames[i].rendered.instance.at<int>(v, u), *world.InstanceId(name)) << name << " frame " << i;
      EXPECT_NEAR(frames[i].rendered.depth.at<float>(v, u), p_c.z(), 0.01) << name << " frame " << i;
    }
    ASSERT_GT(compared, 5000);
    EXPECT_GT(static_cast<double>(within) / compared, 0.99) << "frame " << i;
  }
}

// The names in `folder`, sorted.
std::vector<std::string> Listing(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Asks to stop once `frames` frames have started (polled before each frame, from every thread).
std::function<bool()> StopAfter(int frames) {
  auto started = std::make_shared<std::atomic<int>>(0);
  return [started, frames] { return started->fetch_add(1) >= frames; };
}

// Changes the working directory for the life of the object.
class WorkingDirectory {
 public:
  explicit WorkingDirectory(const fs::path& folder) : saved_(fs::current_path()) { fs::current_path(folder); }
  ~WorkingDirectory() { fs::current_path(saved_); }
  WorkingDirectory(const WorkingDirectory&) = delete;
  WorkingDirectory& operator=(const WorkingDirectory&) = delete;

 private:
  fs::path saved_;
};

TEST(SequenceWriter, AStoppedRunThrowsInterruptedAndLeavesTheParentAsItWas) {
  testing::TempDir temp;
  std::ofstream(temp / "other.txt") << "mine";
  SynthOptions options = Options(temp / "seq");
  options.stop_requested = StopAfter(4);
  EXPECT_THROW(WriteSequence(fixtures::SmallScenario("[]", 12), options), core::Interrupted);
  EXPECT_EQ(Listing(temp.path()), std::vector<std::string>{"other.txt"});
}

TEST(SequenceWriter, AFailureWhileRenderingLeavesNothing) {
  testing::TempDir temp;
  // A failure in the middle of the frames, from a worker thread: the stop callback is the one thing a caller
  // runs there.
  SynthOptions options = Options(temp / "seq");
  const std::function<bool()> stop_after = StopAfter(5);
  options.stop_requested = [stop_after]() -> bool {
    if (stop_after()) throw std::runtime_error("no space left on device (injected)");
    return false;
  };
  try {
    WriteSequence(fixtures::SmallScenario("[]", 12), options);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("(injected)"));
  }
  EXPECT_TRUE(fs::is_empty(temp.path()));
}

TEST(SequenceWriter, OutIsTheFolderNamedHoweverItIsSpelt) {
  testing::TempDir temp;
  fs::create_directories(temp / "work");
  WriteSequence(fixtures::SmallScenario("[]", 2), Options(temp / "work" / "seq/"));
  EXPECT_EQ(Listing(temp / "work"), std::vector<std::string>{"seq"});
  EXPECT_EQ(io::DetectionsFile::Read(temp / "work" / "seq" / "detections.jsonl").header()->sequence, "seq");
  EXPECT_EQ(io::RgbdSequence::OpenTum(temp / "work" / "seq").size(), 2U);
  const auto written = ReadAllFiles(temp / "work" / "seq");
  // Run from inside the scratch folder, so that a failure of the check could only remove the scratch folder.
  const WorkingDirectory inside(temp / "work");
  for (const std::string out : {".", "./", "seq/..", ".."}) {
    SCOPED_TRACE(out);
    SynthOptions options = Options(out);
    options.force = true;
    try {
      WriteSequence(fixtures::SmallScenario("[]", 2), options);
      FAIL() << "no error";
    } catch (const core::InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("parameter --out"));
      EXPECT_THAT(e.what(), HasSubstr("working directory"));
    }
    EXPECT_EQ(Listing(temp / "work"), std::vector<std::string>{"seq"});
    EXPECT_TRUE(ReadAllFiles(temp / "work" / "seq") == written);
  }
  // Not --force: the root is never replaced whatever the check says, but the check comes first.
  try {
    WriteSequence(fixtures::SmallScenario("[]", 2), Options("/"));
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("working directory"));
  }
}

TEST(SequenceWriter, ForceReplacesTheOldSequenceOnlyWithACompleteOne) {
  testing::TempDir temp;
  Scenario scenario = fixtures::SmallScenario("[]", 6);
  WriteSequence(scenario, Options(temp / "seq"));
  const auto old_files = ReadAllFiles(temp / "seq");
  scenario.seed += 1;
  SynthOptions forced = Options(temp / "seq");
  forced.force = true;
  forced.stop_requested = StopAfter(3);
  EXPECT_THROW(WriteSequence(scenario, forced), core::Interrupted);
  EXPECT_EQ(Listing(temp.path()), std::vector<std::string>{"seq"});
  EXPECT_TRUE(ReadAllFiles(temp / "seq") == old_files);

  forced.stop_requested = nullptr;
  WriteSequence(scenario, forced);
  EXPECT_EQ(Listing(temp.path()), std::vector<std::string>{"seq"});  // no partial or old folder left
  const auto new_files = ReadAllFiles(temp / "seq");
  ASSERT_EQ(new_files.size(), old_files.size());
  EXPECT_NE(new_files.at("scenario.json"), old_files.at("scenario.json"));  // the new seed
}

TEST(SequenceWriter, RefusesToOverwriteUnlessForced) {
  testing::TempDir temp;
  fs::create_directories(temp / "seq");
  std::ofstream(temp / "seq" / "keep.txt") << "mine";
  const Scenario scenario = fixtures::SmallScenario("[]", 2);
  try {
    WriteSequence(scenario, Options(temp / "seq"));
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--force"));
  }
  EXPECT_TRUE(fs::exists(temp / "seq" / "keep.txt"));
  SynthOptions forced = Options(temp / "seq");
  forced.force = true;
  WriteSequence(scenario, forced);
  EXPECT_FALSE(fs::exists(temp / "seq" / "keep.txt"));
  EXPECT_TRUE(fs::exists(temp / "seq" / "rgb.txt"));
}

TEST(SequenceWriter, AFailedRunLeavesNothingBehind) {
  testing::TempDir temp;
  Scenario scenario = fixtures::SmallScenario("[]", 2);
  scenario.camera.tum = "fr3_no_such_sequence";
  SynthOptions options = Options(temp / "seq");
  options.tum_dir = temp / "tum";
  try {
    WriteSequence(scenario, options);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("fr3_no_such_sequence.txt"));
  }
  EXPECT_TRUE(fs::is_empty(temp.path()));
}

std::vector<nlohmann::json> ReadJsonLines(const fs::path& file) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

// The event log's line of `action` ("cover_lens", "uncover_lens", "dark", "undark"); fails the test when there is none.
nlohmann::json LensEvent(const fs::path& sequence, const std::string& action) {
  for (const nlohmann::json& line : ReadJsonLines(sequence / "events.jsonl")) {
    if (line.at("action") == action) return line;
  }
  ADD_FAILURE() << "no " << action << " in " << sequence;
  return nlohmann::json::object();
}

// What a frame of a written sequence shows: its mean grey level and share of pixels with depth.
struct FrameLook {
  double mean_level = 0.0;
  double level_deviation = 0.0;
  double depth_share = 0.0;
};

FrameLook Look(const io::RgbdSequence& sequence, std::size_t i) {
  const core::RgbdFrame frame = sequence.LoadFrame(i);
  cv::Mat grey;
  cv::cvtColor(frame.rgb, grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean;
  cv::Scalar deviation;
  cv::meanStdDev(grey, mean, deviation);
  return {mean[0], deviation[0], static_cast<double>(cv::countNonZero(frame.depth)) / frame.depth.total()};
}

TEST(SequenceWriter, ACoveredLensGivesDarkFramesWithoutDepthWhileTheGroundTruthGoesOn) {
  testing::TempDir temp;
  const Scenario scenario = ParseScenario(R"({"name": "covered", "seed": 7,
    "camera": {"procedural": "xyz", "fps": 10, "frames": 8, "position": [4.0, 1.2, 1.45], "look_at": [4.0, 4.5, 0.85]},
    "covered": [{"from": 0.25, "for": 0.3}],
    "people": )" + std::string(fixtures::kWalkThenStop) + "}",
                                          "covered.json");
  WriteSequence(scenario, Options(temp / "seq"));
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / "seq");
  ASSERT_EQ(sequence.size(), 8U);
  const io::DetectionsFile detections = io::DetectionsFile::Read(temp / "seq" / "detections.jsonl");
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    SCOPED_TRACE(i);
    const FrameLook look = Look(sequence, i);
    const std::string image = fs::path(sequence.entry(i).rgb_path).filename().string();
    const cv::Mat moving = cv::imread((temp / "seq" / "mask" / image).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat people = cv::imread((temp / "seq" / "people" / image).string(), cv::IMREAD_UNCHANGED);
    const io::FrameDetections* boxes = detections.Find(sequence.Timestamps()[i]);
    ASSERT_NE(boxes, nullptr);
    if (i >= 3 && i < 6) {  // 0.3 to 0.5 s: covered
      EXPECT_LT(look.mean_level, 10.0);
      EXPECT_GT(look.level_deviation, 0.2);  // sensor noise
      EXPECT_EQ(look.depth_share, 0.0);
      EXPECT_EQ(cv::countNonZero(moving), 0);
      EXPECT_EQ(cv::countNonZero(people), 0);
      EXPECT_TRUE(boxes->detections.empty());
    } else {
      EXPECT_GT(look.mean_level, 50.0);
      EXPECT_GT(look.depth_share, 0.5);
      EXPECT_GT(cv::countNonZero(people), 0);
      EXPECT_FALSE(boxes->detections.empty());
    }
  }
  // The ground truth goes on under the cover: the camera's own pose at every frame.
  const core::Trajectory groundtruth = io::ReadTumTrajectory(temp / "seq" / "groundtruth.txt");
  const CameraPath path = ScenarioCameraPath(scenario, {});
  ASSERT_EQ(groundtruth.size(), path.size());
  for (std::size_t i = 0; i < path.size(); ++i) EXPECT_TRUE(groundtruth[i].T_wc.isApprox(path.frames()[i].T_wc, 1e-6));
  EXPECT_GT((groundtruth[6].T_wc.translation() - groundtruth[2].T_wc.translation()).norm(), 0.01);
  // The event log says when the lens is covered and uncovered, and at which frames.
  const double start = sequence.Timestamps().front();
  const nlohmann::json cover = LensEvent(temp / "seq", "cover_lens");
  EXPECT_NEAR(cover.value("time", 0.0), start + 0.25, 1e-6);
  EXPECT_EQ(cover.value("frame", -1), 3);
  const nlohmann::json uncover = LensEvent(temp / "seq", "uncover_lens");
  EXPECT_NEAR(uncover.value("time", 0.0), start + 0.55, 1e-6);
  EXPECT_EQ(uncover.value("frame", -1), 6);
  EXPECT_FALSE(uncover.contains("person"));
}

// The bytes of a file.
std::string FileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(SequenceWriter, DarkFramesAreDimmedBeforeTheNoiseWithDepthMasksAndBoxesAsEver) {
  testing::TempDir temp;
  const auto scenario = [](const std::string& dark) {
    return ParseScenario(R"({"name": "dark", "seed": 7, "camera": {"procedural": "xyz", "fps": 10, "frames": 8,
                                 "position": [4.0, 1.2, 1.45], "look_at": [4.0, 4.5, 0.85]},)" +
                             dark + R"( "people": )" + std::string(fixtures::kWalkThenStop) + "}",
                         "dark.json");
  };
  WriteSequence(scenario(R"("dark": [{"from": 0.25, "for": 0.3, "level": 0.2}],)"), Options(temp / "dark"));
  WriteSequence(scenario(""), Options(temp / "lit"));
  const io::RgbdSequence dark = io::RgbdSequence::OpenTum(temp / "dark");
  const io::RgbdSequence lit = io::RgbdSequence::OpenTum(temp / "lit");
  ASSERT_EQ(dark.size(), 8U);
  for (std::size_t i = 0; i < dark.size(); ++i) {
    SCOPED_TRACE(i);
    const core::RgbdFrame a = dark.LoadFrame(i);
    const core::RgbdFrame b = lit.LoadFrame(i);
    const std::string image = fs::path(dark.entry(i).rgb_path).filename().string();
    for (const char* folder : {"depth", "mask", "people"}) {
      EXPECT_EQ(FileBytes(temp / "dark" / folder / image), FileBytes(temp / "lit" / folder / image)) << folder;
    }
    if (i < 3 || i >= 6) {  // lit: the same image
      EXPECT_EQ(FileBytes(temp / "dark" / "rgb" / image), FileBytes(temp / "lit" / "rgb" / image));
      continue;
    }
    // 0.3 to 0.5 s: a fifth of the light, and the same sensor noise as ever. The noise n of both images is the same,
    // so dark - 0.2 lit = 0.8 n: about 0.9 grey levels after the blur (0.2 n, were the noise dimmed too).
    cv::Mat difference;
    cv::Mat(a.rgb).convertTo(difference, CV_32F);
    cv::Mat lit_rgb;
    b.rgb.convertTo(lit_rgb, CV_32F, 0.2);
    difference -= lit_rgb;
    cv::Scalar mean;
    cv::Scalar deviation;
    cv::meanStdDev(difference.reshape(1), mean, deviation);
    EXPECT_NEAR(mean[0], 0.0, 0.3);
    EXPECT_GT(deviation[0], 0.6);
    EXPECT_LT(deviation[0], 1.5);
  }
  // The same boxes (the header names the folder).
  const std::vector<nlohmann::json> dark_boxes = ReadJsonLines(temp / "dark" / "detections.jsonl");
  const std::vector<nlohmann::json> lit_boxes = ReadJsonLines(temp / "lit" / "detections.jsonl");
  ASSERT_EQ(dark_boxes.size(), lit_boxes.size());
  for (std::size_t i = 1; i < dark_boxes.size(); ++i) EXPECT_EQ(dark_boxes[i], lit_boxes[i]);
  // The event log says when the lights dim and come back, and at which frames.
  const double start = dark.Timestamps().front();
  const nlohmann::json dim = LensEvent(temp / "dark", "dark");
  EXPECT_NEAR(dim.value("time", 0.0), start + 0.25, 1e-6);
  EXPECT_EQ(dim.value("frame", -1), 3);
  EXPECT_DOUBLE_EQ(dim.value("level", 0.0), 0.2);
  const nlohmann::json undark = LensEvent(temp / "dark", "undark");
  EXPECT_NEAR(undark.value("time", 0.0), start + 0.55, 1e-6);
  EXPECT_EQ(undark.value("frame", -1), 6);
  EXPECT_FALSE(undark.contains("person"));
}

TEST(SequenceWriter, ShippedLoopKidnapAndRevisitScenariosRenderTheOfficeInTheirFirstFrames) {
  testing::TempDir temp;
  for (const std::string name : {"loop", "loop_static", "kidnap", "kidnap_static", "kidnap_unmapped",
                                 "kidnap_unmapped_static", "revisit_a", "revisit_b"}) {
    SCOPED_TRACE(name);
    Scenario scenario = LoadScenario(name);
    scenario.max_frames = 2;
    WriteSequence(scenario, Options(temp / name));
    const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / name);
    ASSERT_EQ(sequence.size(), 2U);
    const FrameLook look = Look(sequence, 0);
    EXPECT_GT(look.mean_level, 50.0);
    EXPECT_GT(look.depth_share, 0.8);
    io::DetectionsFile::Read(temp / name / "detections.jsonl").CheckCovers(sequence.Timestamps(), name);
  }
}

TEST(SequenceWriter, ShippedKidnapNamesTheUncoveringFrame) {
  testing::TempDir temp;
  SynthOptions options = Options(temp / "kidnap");
  options.frame_step = 60;  // a frame every 2 s: the lens is covered at 20 s, uncovered at 22 s
  WriteSequence(LoadScenario("kidnap"), options);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / "kidnap");
  const nlohmann::json uncover = LensEvent(temp / "kidnap", "uncover_lens");
  const int frame = uncover.value("frame", -1);
  ASSERT_EQ(frame, 11);
  EXPECT_NEAR(sequence.Timestamps()[11] - sequence.Timestamps()[0], 22.0, 1e-6);
  EXPECT_EQ(Look(sequence, 10).depth_share, 0.0);
  EXPECT_GT(Look(sequence, 11).depth_share, 0.8);
}

// A map made on one pass is evaluated on the other, so both write their ground truth in the room frame: a point
// that revisit_a's ground truth and depth put in the room is where revisit_b's ground truth and depth see it.
TEST(SequenceWriter, RevisitPassesShareTheRoomFrame) {
  testing::TempDir temp;
  // The passes have other people at other places; without them, the views differ only by the camera poses.
  Scenario first = LoadScenario("revisit_a");
  first.people.clear();
  first.max_frames = 151;
  SynthOptions first_options = Options(temp / "a");
  first_options.frame_step = 150;  // frames 0 and 150: 5 s in, where revisit_b starts looking
  WriteSequence(first, first_options);
  Scenario second = LoadScenario("revisit_b");
  second.people.clear();
  second.max_frames = 1;
  WriteSequence(second, Options(temp / "b"));

  const io::RgbdSequence a = io::RgbdSequence::OpenTum(temp / "a");
  const io::RgbdSequence b = io::RgbdSequence::OpenTum(temp / "b");
  ASSERT_EQ(a.size(), 2U);
  const core::Pose T_wa = a.groundtruth()[1].T_wc;
  const core::Pose T_bw = b.groundtruth()[0].T_wc.inverse();
  const cv::Mat depth_a = a.LoadFrame(1).depth;
  const cv::Mat depth_b = b.LoadFrame(0).depth;
  const core::CameraIntrinsics k;
  constexpr float kNear = 2.5F;  // metres: nearer, the depth noise is below 1 cm
  std::vector<double> differences;
  for (int v = 0; v < depth_a.rows; v += 4) {
    for (int u = 0; u < depth_a.cols; u += 4) {
      const float z = depth_a.at<float>(v, u);
      if (z <= 0.0F || z > kNear) continue;
      const Eigen::Vector3d in_b = T_bw * (T_wa * k.Unproject(u, v, z));
      const Eigen::Vector2d pixel = k.Project(in_b);
      const int ub = static_cast<int>(std::lround(pixel.x()));
      const int vb = static_cast<int>(std::lround(pixel.y()));
      if (in_b.z() <= 0.0 || ub < 0 || vb < 0 || ub >= depth_b.cols || vb >= depth_b.rows) continue;
      if (depth_b.at<float>(vb, ub) <= 0.0F) continue;
      differences.push_back(std::abs(depth_b.at<float>(vb, ub) - in_b.z()));
    }
  }
  ASSERT_GT(differences.size(), 1000U);
  std::nth_element(differences.begin(), differences.begin() + differences.size() / 2, differences.end());
  EXPECT_LT(differences[differences.size() / 2], 0.01);  // depth noise, rounding to whole pixels, occlusions
}

TEST(SequenceWriter, ShippedTumScenarioFollowsTheRealCameraPath) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(groundtruth, "data/tum/groundtruth/fr3_walking_xyz.txt");
  testing::TempDir temp;
  Scenario scenario = LoadScenario("walking_xyz");
  scenario.max_frames = 3;
  SynthOptions options = Options(temp / "walking_xyz");
  options.tum_dir = groundtruth.parent_path().parent_path();
  WriteSequence(scenario, options);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(temp / "walking_xyz");
  ASSERT_EQ(sequence.size(), 3U);
  // Real fr3 timing, and the first pose is the scenario's anchor.
  EXPECT_NEAR(sequence.entry(0).rgb_timestamp, 1341846313.654184, 1e-6);
  EXPECT_TRUE(sequence.groundtruth().front().T_wc.isApprox(scenario.camera.T_anchor, 1e-6));
  io::DetectionsFile::Read(temp / "walking_xyz" / "detections.jsonl").CheckCovers(sequence.Timestamps(), "walking_xyz");
}

}  // namespace
}  // namespace hoidslam::synth
