#include "hoidslam/slam/system.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/sliding_wall.h"
#include "support/temp_dir.h"

namespace hoidslam::slam {
namespace {

// The sliding wall (tests/support/sliding_wall.h): a camera sliding along -x in front of a textured wall at
// kPlaneDepth, the image content moving right by kShift pixels a frame.
constexpr double kPlaneDepth = testing::wall::kDepth;  // metres
using testing::wall::kShift;
using testing::wall::MakeFrame;
using testing::wall::MakeTexture;

SystemOptions Options() {
  SystemOptions options;
  options.deterministic = true;
  return options;
}

// The true T_cw of frame k (the first camera is the world frame).
Eigen::Vector3d TrueTranslation(int k) {
  return {kShift * k * kPlaneDepth / core::CameraIntrinsics{}.fx, 0.0, 0.0};
}

TEST(System, TracksACameraSlidingAlongATexturedWall) {
  const cv::Mat texture = MakeTexture(3);
  System system(Options());
  constexpr int kFrames = 8;
  for (int k = 0; k < kFrames; ++k) {
    const core::RgbdFrame frame = MakeFrame(texture, k);
    const ExtractedFeatures features = system.Extract(frame.rgb);
    const TrackResult result = system.Track(frame, features, {});
    ASSERT_EQ(result.state, TrackingState::kOk) << "frame " << k;
    ASSERT_TRUE(result.T_cw.has_value());
    EXPECT_EQ(result.keypoints, static_cast<int>(features.keypoints.size()));
    if (k == 0) {
      EXPECT_EQ(result.method, TrackingMethod::kInitialization);
      EXPECT_TRUE(result.keyframe);
      EXPECT_GE(result.inliers, 500);
    } else {
      EXPECT_NE(result.method, TrackingMethod::kInitialization);
      EXPECT_GE(result.inliers, 200) << "frame " << k;
    }
    EXPECT_LT((result.T_cw->translation() - TrueTranslation(k)).norm(), 0.003) << "frame " << k;
    EXPECT_LT(Eigen::AngleAxisd(result.T_cw->linear()).angle(), 0.2 * std::numbers::pi / 180.0) << "frame " << k;
  }
  system.Finish();

  const core::Trajectory trajectory = system.FrameTrajectory();
  ASSERT_EQ(trajectory.size(), static_cast<std::size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    EXPECT_DOUBLE_EQ(trajectory[static_cast<std::size_t>(k)].timestamp, 100.0 + k / 30.0);
    // Camera centres: T_wc translation = -T_cw translation here (no rotation).
    EXPECT_LT((trajectory[static_cast<std::size_t>(k)].T_wc.translation() + TrueTranslation(k)).norm(), 0.003);
  }
  EXPECT_GE(system.NumKeyFrames(), 1U);
  EXPECT_EQ(system.KeyFrameTrajectory().size(), system.NumKeyFrames());
  const std::vector<MapPointSample> points = system.MapPoints();
  ASSERT_GE(points.size(), 500U);
  for (const MapPointSample& p : points) {
    EXPECT_NEAR(p.position.z(), kPlaneDepth, 0.05);  // every point lies on the wall
    EXPECT_GE(p.observations, 1);
  }
}

TEST(System, DeterministicModeRepeatsItself) {
  const cv::Mat texture = MakeTexture(5);
  std::vector<core::Trajectory> runs;
  for (int run = 0; run < 2; ++run) {
    System system(Options());
    for (int k = 0; k < 5; ++k) {
      const core::RgbdFrame frame = MakeFrame(texture, k);
      system.Track(frame, system.Extract(frame.rgb), {});
    }
    system.Finish();
    runs.push_back(system.FrameTrajectory());
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (std::size_t i = 0; i < runs[0].size(); ++i) {
    EXPECT_TRUE(runs[0][i].T_wc.matrix() == runs[1][i].T_wc.matrix()) << i;
  }
}

// The safety net on the sliding wall: from frame 10 on a patch of the wall (a poster, say) is pushed towards the
// camera, 5 cm a frame, with nothing dropped by any filter. Its map points are erased once they misfit thrice;
// with the net off, or with nothing moving, none are. `depth_delay`: seconds the depth images are taken after
// the colour ones.
int MovingPointsErased(int moving_point_outliers, bool push_patch, double depth_delay = 0.0) {
  const cv::Mat texture = MakeTexture(11);
  SystemOptions options = Options();
  options.tracking.moving_point_outliers = moving_point_outliers;
  System system(options);
  const cv::Rect patch_in_texture(340, 200, 160, 160);
  int erased = 0;
  for (int k = 0; k < 24; ++k) {
    core::RgbdFrame frame = MakeFrame(texture, k);
    frame.depth_delay = depth_delay;
    if (push_patch && k >= 10) {
      const cv::Rect patch = (patch_in_texture - cv::Point(80 - kShift * k, 60)) & cv::Rect(0, 0, 640, 480);
      frame.depth(patch).setTo(kPlaneDepth - 0.05 * (k - 9));
    }
    const TrackResult result = system.Track(frame, system.Extract(frame.rgb), {});
    EXPECT_EQ(result.state, TrackingState::kOk) << "frame " << k;
    erased += result.moving_points;
  }
  system.Finish();
  return erased;
}

TEST(System, TheSafetyNetErasesMapPointsOnSomethingThatMovesAndNothingElse) {
  EXPECT_GE(MovingPointsErased(3, true), 20);
  EXPECT_EQ(MovingPointsErased(0, true), 0);
  EXPECT_LE(MovingPointsErased(3, false), 2);
}

TEST(System, TheSafetyNetAccusesNoPointThatMovedOverTheDepthImagesDelay) {
  // The wall slides kShift pixels a frame (1/30 s): over a depth image taken 1 ms after the colour it moves a
  // fifth of a pixel, and the net works as ever; over 20 ms, several pixels, so that a depth edge may land on the
  // wrong side of a keypoint, and no misfit counts.
  static_assert(kShift * 30 * 0.001 < 1.0 && kShift * 30 * 0.020 > 1.0);
  EXPECT_GE(MovingPointsErased(3, true, 0.001), 20);
  EXPECT_EQ(MovingPointsErased(3, true, 0.020), 0);
  EXPECT_EQ(MovingPointsErased(3, true, -0.020), 0) << "nor when the depth came first";
}

// The sliding wall with depth as noisy as a Kinect's at 2 m (6 mm, a fixed seed): the map's points, all truly on
// the wall, and how long the final adjustment took.
struct NoisyWallMap {
  double rms_depth_error = 0.0;  // of the map points, metres
  double final_adjustment_ms = 0.0;
};
NoisyWallMap MapTheNoisyWall(bool final_adjustment) {
  const cv::Mat texture = MakeTexture(13, {1600, 600});
  SystemOptions options = Options();
  options.final_adjustment.enabled = final_adjustment;
  System system(options);
  cv::RNG rng(7);
  for (int k = 0; k >= -90; --k) {  // 270 pixels along the wall, for several keyframes
    core::RgbdFrame frame = MakeFrame(texture, k);
    frame.timestamp = 100.0 - k / 30.0;
    cv::Mat noise(frame.depth.size(), CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, core::KinectDepthSigma(kPlaneDepth));
    frame.depth += noise;
    EXPECT_EQ(system.Track(frame, system.Extract(frame.rgb), {}).state, TrackingState::kOk) << "frame " << k;
  }
  system.Finish();
  NoisyWallMap map;
  const std::vector<MapPointSample> points = system.MapPoints();
  for (const MapPointSample& p : points) map.rms_depth_error += std::pow(p.position.z() - kPlaneDepth, 2);
  map.rms_depth_error = std::sqrt(map.rms_depth_error / static_cast<double>(points.size()));
  map.final_adjustment_ms = system.FinalAdjustmentMilliseconds();
  return map;
}

TEST(System, TheFinalAdjustmentAveragesTheDepthsOfTheKeyframesThatSeeAPoint) {
  const NoisyWallMap adjusted = MapTheNoisyWall(true);
  const NoisyWallMap as_tracked = MapTheNoisyWall(false);
  EXPECT_GT(adjusted.final_adjustment_ms, 0.0);
  EXPECT_EQ(as_tracked.final_adjustment_ms, 0.0);
  EXPECT_LT(adjusted.rms_depth_error, 0.5 * as_tracked.rms_depth_error) << "as tracked " << as_tracked.rms_depth_error;
}

TEST(System, KeepFlagsSelectKeypoints) {
  const cv::Mat texture = MakeTexture(3);
  System system(Options());
  const core::RgbdFrame frame = MakeFrame(texture, 0);
  const ExtractedFeatures features = system.Extract(frame.rgb);
  ASSERT_GT(features.keypoints.size(), 600U);
  // Nothing kept: nothing to start a map with.
  const std::vector<std::uint8_t> none(features.keypoints.size(), 0);
  TrackResult result = system.Track(frame, features, none);
  EXPECT_EQ(result.keypoints, 0);
  EXPECT_EQ(result.state, TrackingState::kNotInitialized);
  EXPECT_FALSE(result.T_cw.has_value());
  // Every other one kept.
  std::vector<std::uint8_t> half(features.keypoints.size(), 0);
  int kept = 0;
  for (std::size_t i = 0; i < half.size(); i += 2, ++kept) half[i] = 1;
  result = system.Track(MakeFrame(texture, 0), features, half);
  EXPECT_EQ(result.keypoints, kept);
  EXPECT_EQ(result.state, TrackingState::kOk);
  EXPECT_EQ(result.inliers, kept);  // all have depth
}

// Keep flags for `n` keypoints of the finest level, spread over it (the extractor gives them first, in the
// quadtree's order over the image).
std::vector<std::uint8_t> KeepSpread(const ExtractedFeatures& features, std::size_t n) {
  const auto finest = static_cast<std::size_t>(std::count_if(features.keypoints.begin(), features.keypoints.end(),
                                                             [](const cv::KeyPoint& kp) { return kp.octave == 0; }));
  std::vector<std::uint8_t> keep(features.keypoints.size(), 0);
  for (std::size_t k = 0; k < n && k < finest; ++k) keep[k * finest / n] = 1;
  return keep;
}

// Tracks frames [0, count) of the sliding wall with all their keypoints; each must be tracked.
void TrackWholeFrames(System& system, const cv::Mat& texture, int count) {
  for (int k = 0; k < count; ++k) {
    const core::RgbdFrame frame = MakeFrame(texture, k);
    ASSERT_EQ(system.Track(frame, system.Extract(frame.rgb), {}).state, TrackingState::kOk) << "frame " << k;
  }
}

// Tracks four whole frames of the sliding wall, then frame 4 with only `kept` of its keypoints (people fill the
// view); the result must be tracked where the camera truly is.
TrackResult TrackBareFrame(std::size_t kept) {
  const cv::Mat texture = MakeTexture(3);
  System system(Options());
  TrackWholeFrames(system, texture, 4);
  const core::RgbdFrame frame = MakeFrame(texture, 4);
  const ExtractedFeatures features = system.Extract(frame.rgb);
  const TrackResult result = system.Track(frame, features, KeepSpread(features, kept));
  EXPECT_EQ(result.state, TrackingState::kOk);
  if (result.T_cw) {
    EXPECT_LT((result.T_cw->translation() - TrueTranslation(4)).norm(), 0.005);
  }
  return result;
}

TEST(System, AFrameWithFewKeypointsIsTrackedOnItsSupport) {
  // 24 keypoints left, all with close depth: fewer than the 30 inliers a frame needs by count, yet their depth
  // supports the pose (24 × 1.5).
  const TrackResult result = TrackBareFrame(24);
  EXPECT_LT(result.inliers, 30);
}

TEST(System, AFrameTooBareForTheMotionModelIsFoundInTheMapAroundTheLastFrame) {
  // 18 keypoints left: fewer than the 20 matches the search from the last frame needs. The local map around it,
  // searched strictly where the motion model puts the camera, still holds them.
  const TrackResult result = TrackBareFrame(18);
  EXPECT_EQ(result.method, TrackingMethod::kMotionModel);
  EXPECT_LE(result.inliers, 18);
}

TEST(System, AShortLossIsBridgedByTheMotionModelAndSaysWhy) {
  const cv::Mat texture = MakeTexture(3);
  System system(Options());
  ASSERT_NO_FATAL_FAILURE(TrackWholeFrames(system, texture, 6));
  // Five frames with 8 keypoints left: too few to track, and said so.
  for (int k = 6; k < 11; ++k) {
    const core::RgbdFrame frame = MakeFrame(texture, k);
    const ExtractedFeatures features = system.Extract(frame.rgb);
    const TrackResult result = system.Track(frame, features, KeepSpread(features, 8));
    EXPECT_EQ(result.state, TrackingState::kLost) << "frame " << k;
    EXPECT_EQ(result.failure, TrackingFailure::kTooFewKeypoints) << "frame " << k;
    EXPECT_FALSE(result.T_cw);
  }
  // A frame of another wall: plenty of keypoints, nothing of the map among them.
  const core::RgbdFrame elsewhere = MakeFrame(MakeTexture(99), 11);
  const TrackResult unknown = system.Track(elsewhere, system.Extract(elsewhere.rgb), {});
  EXPECT_EQ(unknown.state, TrackingState::kLost);
  EXPECT_EQ(unknown.failure, TrackingFailure::kTooFewMatches);
  // The view clears: the camera kept sliding, and the motion model finds it where it was heading, without a
  // search of the whole map — provisionally until 0.2 s of frames have borne it out.
  for (int k = 12; k < 20; ++k) {
    const core::RgbdFrame frame = MakeFrame(texture, k);
    const TrackResult result = system.Track(frame, system.Extract(frame.rgb), {});
    ASSERT_EQ(result.state, k < 18 ? TrackingState::kProvisional : TrackingState::kOk) << "frame " << k;
    EXPECT_EQ(result.method, TrackingMethod::kMotionModel) << "frame " << k;
    EXPECT_EQ(result.failure, TrackingFailure::kNone);
    EXPECT_FALSE(result.keyframe && k < 18) << "frame " << k;
    EXPECT_LT((result.T_cw->translation() - TrueTranslation(k)).norm(), 0.005) << "frame " << k;
  }
}

// Tracks frame k of a sliding wall one frame's time after the frame tracked last: the camera carried from one view
// to another, each view lasting a frame.
struct NextFrame {
  TrackResult operator()(const cv::Mat& wall, int k) {
    core::RgbdFrame frame = MakeFrame(wall, k);
    frame.timestamp = timestamp += 1.0 / 30.0;
    return system.Track(frame, system.Extract(frame.rgb), {});
  }
  System& system;
  double timestamp;  // of the frame tracked last
};

TEST(System, ACameraCarriedBackToAPlaceItMappedIsRelocalisedThere) {
  const cv::Mat texture = MakeTexture(3);
  SystemOptions options = Options();
  options.tracking.new_map_after = 0.0;  // no new map on the other wall: the camera stays lost until relocalised
  System system(options);
  ASSERT_NO_FATAL_FAILURE(TrackWholeFrames(system, texture, 20));
  // Two seconds before another wall: lost, too long for the motion model to say where the camera went.
  const cv::Mat elsewhere = MakeTexture(99);
  NextFrame next{system, MakeFrame(texture, 19).timestamp};
  for (int k = 0; k < 60; ++k) ASSERT_EQ(next(elsewhere, k % 20).state, TrackingState::kLost) << "frame " << k;
  // Back where frame 5 was: the keyframes that look like it are found by their words, and the pose is found again,
  // provisionally: nothing enters the map from it.
  const TrackResult result = next(texture, 5);
  ASSERT_EQ(result.state, TrackingState::kProvisional);
  EXPECT_EQ(result.method, TrackingMethod::kRelocalization);
  EXPECT_FALSE(result.keyframe);
  EXPECT_LT((result.T_cw->translation() - TrueTranslation(5)).norm(), 0.005);
  // The camera slides on from there, and the frames that follow confirm the pose: after 0.2 s tracking is ok again.
  TrackResult after;
  for (int k = 6; k <= 10; ++k) {
    after = next(texture, k);
    ASSERT_EQ(after.state, TrackingState::kProvisional) << "frame " << k;
    EXPECT_FALSE(after.keyframe) << "frame " << k;
    EXPECT_LT((after.T_cw->translation() - TrueTranslation(k)).norm(), 0.005) << "frame " << k;
  }
  after = next(texture, 11);
  EXPECT_EQ(after.state, TrackingState::kOk);
  EXPECT_TRUE(after.withdrawn.empty());
  system.Finish();
  EXPECT_EQ(system.FrameTrajectory().size(), 20U + 7U);
}

// A relocalisation the next frames do not bear out is withdrawn: its frames are lost after all, and the
// trajectory leaves them out.
TEST(System, ARelocalisationTheNextFramesRefuteIsWithdrawn) {
  const cv::Mat texture = MakeTexture(3);
  SystemOptions options = Options();
  options.tracking.new_map_after = 0.0;
  System system(options);
  ASSERT_NO_FATAL_FAILURE(TrackWholeFrames(system, texture, 20));
  const cv::Mat elsewhere = MakeTexture(99);
  NextFrame next{system, MakeFrame(texture, 19).timestamp};
  for (int k = 0; k < 60; ++k) ASSERT_EQ(next(elsewhere, k % 20).state, TrackingState::kLost) << "frame " << k;
  // Found again at frame 10's view, tracked for two frames sliding on, then the view jumps back to frame 0's, ten
  // frames' worth in a thirtieth of a second: no camera moves so, and the pose found is withdrawn with the frames
  // after it.
  ASSERT_EQ(next(texture, 10).state, TrackingState::kProvisional);
  ASSERT_EQ(next(texture, 11).state, TrackingState::kProvisional);
  ASSERT_EQ(next(texture, 12).state, TrackingState::kProvisional);
  const TrackResult refuting = next(texture, 0);
  EXPECT_EQ(refuting.state, TrackingState::kLost);
  EXPECT_EQ(refuting.failure, TrackingFailure::kRelocalizationRefuted);
  EXPECT_EQ(refuting.withdrawn.size(), 3U);
  system.Finish();
  EXPECT_EQ(system.FrameTrajectory().size(), 20U);
}

TEST(System, ACameraCarriedBackFromNewGroundIsRelocalisedInTheFirstMap) {
  const cv::Mat texture = MakeTexture(3);
  System system(Options());
  ASSERT_NO_FATAL_FAILURE(TrackWholeFrames(system, texture, 20));
  // Two seconds before another wall: lost for a second, then a map of its own is started there.
  const cv::Mat elsewhere = MakeTexture(99);
  NextFrame next{system, MakeFrame(texture, 19).timestamp};
  TrackResult result;
  for (int k = 0; k < 60; ++k) result = next(elsewhere, k % 20);
  ASSERT_EQ(result.state, TrackingState::kOk);
  EXPECT_EQ(result.map, 1U);
  // Back where frame 5 was: lost in the new map, and a second later found again in the first one.
  const double back = next.timestamp;
  while (next.timestamp < back + 1.5 && (result = next(texture, 5)).state != TrackingState::kProvisional) {
  }
  ASSERT_EQ(result.state, TrackingState::kProvisional);
  EXPECT_EQ(result.method, TrackingMethod::kRelocalization);
  EXPECT_EQ(result.map, 0U);
  EXPECT_GT(next.timestamp - back, 1.0);
  EXPECT_LT((result.T_cw->translation() - TrueTranslation(5)).norm(), 0.005);
  // Standing there, the pose is confirmed after 0.2 s.
  int found_again = 1;
  while ((result = next(texture, 5)).state == TrackingState::kProvisional) ++found_again;
  ASSERT_EQ(result.state, TrackingState::kOk);
  ++found_again;
  EXPECT_EQ(result.map, 0U);
  system.Finish();
  // Both maps have frames: the first its 20 and those found again, the other wall's its own.
  const std::vector<MapSummary> maps = system.Maps();
  ASSERT_EQ(maps.size(), 2U);
  EXPECT_EQ(maps[0].frames, 20U + found_again);
  EXPECT_EQ(system.FrameTrajectory(0).size(), 20U + found_again);
}

TEST(System, ARelocalisationTheMotionModelRulesOutAfterAShortLossIsRefused) {
  const cv::Mat texture = MakeTexture(3);
  SystemOptions options = Options();
  // A camera that hardly accelerates: however long a loss under a second, it stays within 2 cm of where it was
  // heading.
  options.tracking.motion.acceleration = 0.02;               // m/s²: 2 cm a second
  options.tracking.motion.angular_acceleration_deg = 2.0;    // °/s²
  System system(options);
  ASSERT_NO_FATAL_FAILURE(TrackWholeFrames(system, texture, 20));
  // Three frames of another wall, then the view of frame 0, 0.21 m back where the camera was sliding on: the motion
  // model rules it out, so no pose is taken, however well the map fits it.
  const cv::Mat elsewhere = MakeTexture(99);
  NextFrame next{system, MakeFrame(texture, 19).timestamp};
  for (int k = 0; k < 3; ++k) ASSERT_EQ(next(elsewhere, k).state, TrackingState::kLost);
  const TrackResult refused = next(texture, 0);
  EXPECT_EQ(refused.state, TrackingState::kLost);
  EXPECT_EQ(refused.failure, TrackingFailure::kPoseRejected);
  // Once a second has passed, the camera may be anywhere: the same view is relocalised, and not before.
  const double last_tracked = MakeFrame(texture, 19).timestamp;
  TrackResult result;
  while (next.timestamp < last_tracked + 1.5 && (result = next(texture, 0)).state == TrackingState::kLost) {
  }
  ASSERT_EQ(result.state, TrackingState::kProvisional);
  EXPECT_GT(next.timestamp - last_tracked, 1.0);
  EXPECT_EQ(result.method, TrackingMethod::kRelocalization);
  EXPECT_LT((result.T_cw->translation() - TrueTranslation(0)).norm(), 0.005);
}

// Loop closing on the wall: the camera looks at it from kPlaneDepth and moves parallel to it; a frame is the view
// whose top-left corner is at `offset` pixels of the texture.
core::RgbdFrame ViewAt(const cv::Mat& texture, cv::Point offset, int k) {
  core::RgbdFrame frame;
  frame.timestamp = 100.0 + k / 30.0;
  frame.rgb = texture(cv::Rect(offset, cv::Size(640, 480))).clone();
  frame.depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(kPlaneDepth));
  return frame;
}

// The camera centre of the view at `offset`, the first view (at `start`) the world's origin.
Eigen::Vector3d TrueCentre(cv::Point offset, cv::Point start) {
  const core::CameraIntrinsics camera;
  return {(offset.x - start.x) * kPlaneDepth / camera.fx, (offset.y - start.y) * kPlaneDepth / camera.fy, 0.0};
}

// Offsets along the path: from `from` to `to` in steps of `step` pixels, `to` included.
void AddLeg(std::vector<cv::Point>& path, cv::Point from, cv::Point to, int step) {
  const cv::Point d = to - from;
  const int steps = std::max(std::abs(d.x), std::abs(d.y)) / step;
  for (int s = 1; s <= steps; ++s) path.push_back(from + d * s / steps);
}

// Round a rectangle of 700 × 500 pixels (2.6 × 1.9 m at 2 m), 14 pixels a frame, and on along its first side: the
// views at its corners share nothing, so the map comes back to its start along keyframes that never saw it, and
// only a loop can join the two ends.
struct RoundTheWall {
  std::vector<cv::Point> path;
  core::Trajectory trajectory;
  std::vector<LoopClosure> loops;
};

RoundTheWall GoRoundTheWall(bool loop_closing) {
  const cv::Mat texture = MakeTexture(7, {1340, 980});
  RoundTheWall round;
  std::vector<cv::Point>& path = round.path;
  path = {{0, 0}};
  AddLeg(path, {0, 0}, {700, 0}, 14);
  AddLeg(path, {700, 0}, {700, 500}, 14);
  AddLeg(path, {700, 500}, {0, 500}, 14);
  AddLeg(path, {0, 500}, {0, 0}, 14);
  AddLeg(path, {0, 0}, {700, 0}, 14);
  SystemOptions options = Options();
  options.loop_closing.enabled = loop_closing;
  options.loop_closing.min_keyframes = 4;  // a plane needs few keyframes
  System system(options);
  for (std::size_t k = 0; k < path.size(); ++k) {
    const core::RgbdFrame frame = ViewAt(texture, path[k], static_cast<int>(k));
    EXPECT_EQ(system.Track(frame, system.Extract(frame.rgb), {}).state, TrackingState::kOk) << "frame " << k;
  }
  system.Finish();
  round.trajectory = system.FrameTrajectory();
  round.loops = system.LoopClosures();
  return round;
}

// The largest distance of a tracked camera centre from the truth, over frames [first, end).
double MaxError(const RoundTheWall& round, std::size_t first, std::size_t end) {
  double worst = 0.0;
  for (std::size_t k = first; k < end; ++k) {
    worst = std::max(worst, (round.trajectory[k].T_wc.translation() - TrueCentre(round.path[k], round.path[0])).norm());
  }
  return worst;
}

TEST(System, ACameraGoingRoundTheWallClosesTheLoopWhereItStarted) {
  const RoundTheWall open = GoRoundTheWall(false);
  const RoundTheWall closed = GoRoundTheWall(true);
  EXPECT_TRUE(open.loops.empty());
  ASSERT_FALSE(closed.loops.empty());
  const LoopClosure& loop = closed.loops.front();
  const std::size_t frame = loop.frame_id, base = loop.loop_frame_id;
  EXPECT_GT(frame, 170U);  // on the way back over the first side ...
  EXPECT_LE(base, 50U);    // ... to a keyframe of the first side
  // The verification's relative pose is the true one.
  const Eigen::Vector3d true_offset = TrueCentre(closed.path[frame], closed.path[0]) -
                                      TrueCentre(closed.path[base], closed.path[0]);
  EXPECT_LT((loop.T_loop_current.translation() - true_offset).norm(), 0.01);
  EXPECT_LT(core::RotationAngleDegrees(loop.T_loop_current.linear()), 0.5);
  // Closed, the path's second pass over the first side is where the first pass was; open, it kept the drift.
  ASSERT_EQ(closed.trajectory.size(), closed.path.size());
  ASSERT_EQ(open.trajectory.size(), open.path.size());
  const std::size_t end = closed.path.size();
  const double open_error = MaxError(open, frame, end), closed_error = MaxError(closed, frame, end);
  EXPECT_LT(closed_error, 0.5 * open_error) << "open " << open_error;
  EXPECT_LT(closed_error, 0.015);
}

TEST(System, AWallThatRepeatsItselfIsNotTakenForALoop) {
  // The same 700-pixel tile of texture three times over: after 700 pixels the camera sees again what it saw at
  // the start, 2.6 m further on. Every view fits; the correction a loop would make is more than drift.
  const cv::Mat tile = MakeTexture(11, {700, 480});
  cv::Mat texture;
  cv::hconcat(std::vector<cv::Mat>{tile, tile, tile}, texture);
  std::vector<cv::Point> path = {{0, 0}};
  AddLeg(path, {0, 0}, {1400, 0}, 14);
  System system(Options());
  for (std::size_t k = 0; k < path.size(); ++k) {
    const core::RgbdFrame frame = ViewAt(texture, path[k], static_cast<int>(k));
    ASSERT_EQ(system.Track(frame, system.Extract(frame.rgb), {}).state, TrackingState::kOk) << "frame " << k;
  }
  system.Finish();
  EXPECT_TRUE(system.LoopClosures().empty());
  const core::Trajectory trajectory = system.FrameTrajectory();
  ASSERT_EQ(trajectory.size(), path.size());
  EXPECT_LT((trajectory.back().T_wc.translation() - TrueCentre(path.back(), path[0])).norm(), 0.05);
}

// Two places alike: the wall repeats itself, and both copies are mapped. Lost long (no motion to go by), the camera
// shows a view both copies fit: neither is taken.
TEST(System, ARelocalisationBetweenTwoPlacesAlikeIsNotMade) {
  const cv::Mat tile = MakeTexture(11, {700, 480});
  cv::Mat texture;
  cv::hconcat(std::vector<cv::Mat>{tile, tile, tile}, texture);
  std::vector<cv::Point> path = {{0, 0}};
  AddLeg(path, {0, 0}, {1400, 0}, 14);
  SystemOptions options = Options();
  options.tracking.new_map_after = 0.0;  // no new map on the other wall
  System system(options);
  int k = 0;
  for (; k < static_cast<int>(path.size()); ++k) {
    const core::RgbdFrame frame = ViewAt(texture, path[static_cast<std::size_t>(k)], k);
    ASSERT_EQ(system.Track(frame, system.Extract(frame.rgb), {}).state, TrackingState::kOk) << "frame " << k;
  }
  // Two seconds of another wall, then the view at 350 px, which the wall shows again at 1050.
  const cv::Mat elsewhere = MakeTexture(99, {1340, 980});
  for (const int end = k + 60; k < end; ++k) {
    ASSERT_EQ(system.Track(ViewAt(elsewhere, {0, 0}, k), system.Extract(ViewAt(elsewhere, {0, 0}, k).rgb), {}).state,
              TrackingState::kLost);
  }
  const core::RgbdFrame twin = ViewAt(texture, {350, 0}, k);
  const TrackResult result = system.Track(twin, system.Extract(twin.rgb), {});
  EXPECT_EQ(result.state, TrackingState::kLost);
  EXPECT_EQ(result.method, TrackingMethod::kRelocalization);
  EXPECT_EQ(result.rejection, PoseRejection::kAmbiguous);
}

TEST(System, RejectsBadInput) {
  SystemOptions bad = Options();
  bad.bf = 0.0;
  EXPECT_THROW(System{bad}, core::InputError);

  const cv::Mat texture = MakeTexture(3);
  System system(Options());
  core::RgbdFrame frame = MakeFrame(texture, 0);
  const ExtractedFeatures features = system.Extract(frame.rgb);
  const std::vector<std::uint8_t> short_keep(features.keypoints.size() - 1, 1);
  EXPECT_THROW(system.Track(frame, features, short_keep), std::invalid_argument);
  core::RgbdFrame small = frame;
  small.depth = cv::Mat(240, 320, CV_32FC1, cv::Scalar(1.0));
  EXPECT_THROW(system.Track(small, features, {}), std::invalid_argument);
  EXPECT_THROW(system.Extract(cv::Mat(480, 640, CV_32FC1)), std::invalid_argument);
}

// A map of the sliding wall, saved; then loaded by a second system that tracks frames of the same wall from
// another start, going the other way.
class MapReuse : public ::testing::Test {
 protected:
  void SetUp() override {
    System mapping(Options());
    ASSERT_NO_FATAL_FAILURE(TrackWholeFrames(mapping, texture_, 20));
    mapping.Finish();
    mapping.SaveMap(map_file_);
    keyframes_ = mapping.NumKeyFrames();
  }

  SystemOptions LoadOptions(bool localization) const {
    SystemOptions options = Options();
    options.load_map = map_file_;
    options.localization = localization;
    return options;
  }

  std::vector<std::uint8_t> MapBytes(const System& system) const {
    system.SaveMap(dir_ / "again.hmap");
    std::ifstream file(dir_ / "again.hmap", std::ios::binary);
    return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  }

  // Twice as wide as the frames need, so the camera can slide on past where the map ends (negative k).
  const cv::Mat texture_ = MakeTexture(3, {1600, 600});
  testing::TempDir dir_;
  std::filesystem::path map_file_ = dir_ / "wall.hmap";
  std::size_t keyframes_ = 0;
};

TEST_F(MapReuse, LocalizationTracksFromTheFirstFrameAndLeavesTheMapAsItWas) {
  System system(LoadOptions(true));
  const std::vector<std::uint8_t> loaded = MapBytes(system);
  for (int k = 15; k >= 3; --k) {
    core::RgbdFrame frame = MakeFrame(texture_, k);
    frame.timestamp = 200.0 + (15 - k) / 30.0;
    const TrackResult result = system.Track(frame, system.Extract(frame.rgb), {});
    // Found in the map at once, and confirmed by the frames that follow (0.2 s, three frames at least).
    ASSERT_EQ(result.state, k > 15 - 6 ? TrackingState::kProvisional : TrackingState::kOk) << "frame " << k;
    EXPECT_EQ(result.method == TrackingMethod::kRelocalization, k == 15) << "frame " << k;
    EXPECT_FALSE(result.keyframe);
    EXPECT_LT((result.T_cw->translation() - TrueTranslation(k)).norm(), 0.005) << "frame " << k;
  }
  system.Finish();
  EXPECT_EQ(system.NumKeyFrames(), keyframes_);
  EXPECT_EQ(MapBytes(system), loaded);
}

TEST_F(MapReuse, ALoadedMapIsContinuedWithoutLocalization) {
  System system(LoadOptions(false));
  // From frame 10 back past the first, on to wall the map has not seen.
  for (int k = 10; k >= -150; --k) {
    core::RgbdFrame frame = MakeFrame(texture_, k);
    frame.timestamp = 200.0 + (10 - k) / 30.0;
    const TrackResult result = system.Track(frame, system.Extract(frame.rgb), {});
    ASSERT_EQ(result.state, k > 10 - 6 ? TrackingState::kProvisional : TrackingState::kOk) << "frame " << k;
    // Nothing enters the map from a provisional pose.
    if (result.state == TrackingState::kProvisional) {
      EXPECT_FALSE(result.keyframe) << "frame " << k;
    }
    // On new wall the map drifts as any map does: up to 9 mm after 150 frames.
    EXPECT_LT((result.T_cw->translation() - TrueTranslation(k)).norm(), 0.012) << "frame " << k;
  }
  system.Finish();
  EXPECT_GT(system.NumKeyFrames(), keyframes_);
}

TEST_F(MapReuse, LocalizationNeedsAMapAndAMapItsCamera) {
  SystemOptions no_map = Options();
  no_map.localization = true;
  EXPECT_THROW(System{no_map}, core::InputError);
  SystemOptions other_camera = LoadOptions(true);
  other_camera.camera.fx = 500.0;
  try {
    System system(other_camera);
    ADD_FAILURE() << "a map of another camera was loaded";
  } catch (const core::InputError& error) {
    EXPECT_NE(std::string(error.what()).find(map_file_.string() + ": the map was made with another camera"),
              std::string::npos)
        << error.what();
  }
}

// The Atlas on the wall: the camera maps the first side of the rectangle, the lens is covered for 1.5 s while it
// moves to the far corner (ground no keyframe saw), and it goes on round the rectangle, back over the first side.
// Frames under the cover are black, without depth. `covered` holds which frames those are.
struct LostInNewGround {
  std::vector<cv::Point> path;
  std::vector<bool> covered;
  std::vector<TrackResult> results;
  std::vector<MapSummary> maps;
  std::vector<LoopClosure> merges;
  core::Trajectory main_trajectory;
  core::Trajectory other_trajectory;  // of the second map, when it stayed apart
};

LostInNewGround LoseTheCameraInNewGround(bool merge_maps) {
  const cv::Mat texture = MakeTexture(7, {1340, 980});
  LostInNewGround run;
  run.path = {{0, 0}};
  AddLeg(run.path, {0, 0}, {700, 0}, 14);
  run.covered.assign(run.path.size(), false);
  constexpr int kCoveredFrames = 45;
  for (int k = 0; k < kCoveredFrames; ++k) {
    run.path.push_back({700, 500});
    run.covered.push_back(true);
  }
  const std::size_t uncovered = run.path.size();
  run.path.push_back({700, 500});
  AddLeg(run.path, {700, 500}, {0, 500}, 14);
  AddLeg(run.path, {0, 500}, {0, 0}, 14);
  AddLeg(run.path, {0, 0}, {700, 0}, 14);
  run.covered.resize(run.path.size(), false);
  EXPECT_EQ(run.covered[uncovered], false);

  SystemOptions options = Options();
  options.loop_closing.min_keyframes = 4;  // a plane needs few keyframes
  options.loop_closing.merge_maps = merge_maps;
  System system(options);
  for (std::size_t k = 0; k < run.path.size(); ++k) {
    core::RgbdFrame frame = ViewAt(texture, run.path[k], static_cast<int>(k));
    if (run.covered[k]) {
      frame.rgb.setTo(cv::Scalar::all(0));
      frame.depth.setTo(0.0F);
    }
    run.results.push_back(system.Track(frame, system.Extract(frame.rgb), {}));
  }
  system.Finish();
  run.maps = system.Maps();
  run.merges = system.MapMerges();
  run.main_trajectory = system.FrameTrajectory();
  for (const MapSummary& map : run.maps) {
    if (map.id != system.MainMap()) run.other_trajectory = system.FrameTrajectory(map.id);
  }
  return run;
}

// The first frame after the cover: tracking lost for 1.5 s found nothing of it in the map, and started a map there.
std::size_t UncoveredFrame(const LostInNewGround& run) {
  return static_cast<std::size_t>(std::find(run.covered.begin() + 1, run.covered.end(), true) - run.covered.begin()) +
         45;
}

TEST(System, ACameraLostInNewGroundStartsAMapAndMergesItWhereItSeesTheFirst) {
  const LostInNewGround run = LoseTheCameraInNewGround(true);
  const std::size_t uncovered = UncoveredFrame(run);
  for (std::size_t k = 0; k < run.path.size(); ++k) {
    EXPECT_EQ(run.results[k].T_cw.has_value(), !run.covered[k]) << "frame " << k;
  }
  EXPECT_EQ(run.results[uncovered].method, TrackingMethod::kInitialization);
  EXPECT_EQ(run.results[uncovered].map, 1U);
  EXPECT_EQ(run.results[uncovered - 46].map, 0U);

  // Merged once the camera came back over the first side: one map holds every tracked frame.
  ASSERT_EQ(run.merges.size(), 1U);
  const LoopClosure& merge = run.merges.front();
  EXPECT_EQ(merge.merged_map, std::optional<MapId>(1));
  EXPECT_EQ(merge.map, 0U);
  EXPECT_LT(merge.loop_frame_id, uncovered);
  EXPECT_GT(merge.frame_id, uncovered);
  const Eigen::Vector3d true_offset = TrueCentre(run.path[merge.frame_id], run.path[0]) -
                                      TrueCentre(run.path[merge.loop_frame_id], run.path[0]);
  EXPECT_LT((merge.T_loop_current.translation() - true_offset).norm(), 0.01);
  EXPECT_LT(core::RotationAngleDegrees(merge.T_loop_current.linear()), 0.5);
  ASSERT_EQ(run.maps.size(), 1U);
  EXPECT_EQ(run.maps.front().id, 0U);
  const std::size_t tracked = static_cast<std::size_t>(std::count(run.covered.begin(), run.covered.end(), false));
  EXPECT_EQ(run.maps.front().frames, tracked);
  // Every frame, the second map's too, is where it truly was in the first map's world frame (the second map drifted
  // a little on its way round before the merge).
  ASSERT_EQ(run.main_trajectory.size(), tracked);
  std::size_t i = 0;
  for (std::size_t k = 0; k < run.path.size(); ++k) {
    if (run.covered[k]) continue;
    const double error = (run.main_trajectory[i++].T_wc.translation() - TrueCentre(run.path[k], run.path[0])).norm();
    EXPECT_LT(error, 0.03) << "frame " << k;
  }
}

TEST(System, AMapStartedInNewGroundStaysApartWhenMapsAreNotMerged) {
  const LostInNewGround run = LoseTheCameraInNewGround(false);
  const std::size_t uncovered = UncoveredFrame(run);
  EXPECT_TRUE(run.merges.empty());
  ASSERT_EQ(run.maps.size(), 2U);
  // The second map, from the uncovering on, is the longer: the main one.
  EXPECT_EQ(run.maps[1].id, 1U);
  EXPECT_EQ(run.maps[1].frames, run.path.size() - uncovered);
  EXPECT_EQ(run.maps[0].frames, uncovered - 45);
  ASSERT_EQ(run.main_trajectory.size(), run.path.size() - uncovered);
  ASSERT_EQ(run.other_trajectory.size(), uncovered - 45);
  // Its world frame is its first camera's.
  EXPECT_LT(run.main_trajectory.front().T_wc.translation().norm(), 1e-9);
  const Eigen::Vector3d walked = TrueCentre(run.path[uncovered + 20], run.path[uncovered]);
  EXPECT_LT((run.main_trajectory[20].T_wc.translation() - walked).norm(), 0.01);
}

}  // namespace
}  // namespace hoidslam::slam
