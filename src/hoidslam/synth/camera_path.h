#pragma once
// Camera paths for synthetic sequences: either a real TUM fr3 camera path with its real frame timing,
// re-anchored into the synthetic room, or a procedural path at a fixed frame rate that needs no data files.
//
// Re-anchoring: T_synth_wc(t) = T_anchor * T_tum_wc(t0)^-1 * T_tum_wc(t), where t0 is the first frame kept,
// so the first camera pose is T_anchor and every motion relative to it is the real one.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/core/pose.h"

namespace hoidslam::synth {

// A camera pose in the room (world z up): optical centre `position`, looking along the direction with
// heading `yaw_deg` (0 = world +x, 90 = world +y) and elevation `pitch_deg` (negative = looking down), with
// the image x axis horizontal and the image y axis pointing down.
core::Pose CameraPoseFromYawPitch(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg);
// A camera pose at `eye` looking at `target` with a level horizon. Throws InputError when they coincide or
// the view is vertical.
core::Pose CameraPoseLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

// One frame of a path: when it is taken and where the camera is.
struct CameraFrame {
  double timestamp = 0.0;        // RGB image time, seconds
  double depth_timestamp = 0.0;  // depth image time, seconds (real sequences: a few microseconds after RGB)
  core::Pose T_wc = core::Pose::Identity();
};

// Shapes of procedural motion, named after the TUM fr3 sequences they imitate, and a loop through the room.
enum class ProceduralMotion {
  kStatic,      // "static": the camera stands still
  kXyz,         // "xyz": translation along the three axes, orientation fixed
  kHalfsphere,  // "halfsphere": an arc on a sphere around a point in front of the camera, looking at it
  kRpy,         // "rpy": rotation about the three axes, position fixed
  kCircle,      // "circle": round a vertical axis `radius` behind the first pose, facing outwards, one turn
                // (counter-clockwise seen from above) per `period`, with a seeded hand-held shake
};
std::string_view ToString(ProceduralMotion motion);
// Parses "static", "xyz", "halfsphere", "rpy", "circle"; throws InputError naming `parameter` otherwise.
ProceduralMotion ParseProceduralMotion(std::string_view text, const std::string& parameter);

struct ProceduralPathOptions {
  ProceduralMotion motion = ProceduralMotion::kXyz;
  double fps = 30.0;               // frames per second, > 0
  std::size_t frames = 900;        // number of frames, >= 1
  double start_time = 0.0;         // timestamp of the first frame, seconds, >= 0
  double amplitude = 0.25;         // metres, >= 0: xyz excursion
  double angle_amplitude_deg = 15; // degrees, in [0, 90]: rpy rotation and halfsphere sweep
  double pivot_distance = 2.0;     // metres, > 0: halfsphere orbits the point this far ahead of the first pose
  double period = 12.0;            // seconds, > 0: time of one full cycle (circle: one turn)
  double radius = 0.5;             // metres, > 0: circle radius
  // The circle's hand-held shake, so that a second turn sees the room from nearly, not exactly, the same poses:
  // smooth, zero at the first frame, within these bounds along and about each camera axis.
  double wobble = 0.03;            // metres, in [0, 0.5]
  double wobble_angle_deg = 2.0;   // degrees, in [0, 10]
  std::uint64_t wobble_seed = 1;
  core::Pose T_anchor = core::Pose::Identity();  // the pose at the first frame

  // Throws InputError naming the parameter ("camera.fps", ...).
  void Check() const;
};

class CameraPath {
 public:
  // A real camera path: frame times from an associations file (io::ReadAssociationList: sorted by RGB time,
  // a repeated RGB time keeps its last line), poses from a TUM ground-truth trajectory (io::ReadTumTrajectory),
  // interpolated at each RGB time (linear position, slerp rotation, across any gap in the ground truth).
  // Frames before the first or after the last ground-truth pose are dropped. `max_frames` > 0 keeps only the
  // first max_frames. Throws InputError naming the file (and line) when a file is missing or malformed, when no
  // frame falls within the ground truth, and when two frames' RGB or depth times are alike in StampText.
  static CameraPath FromTum(const std::filesystem::path& groundtruth, const std::filesystem::path& associations,
                            const core::Pose& T_anchor, std::size_t max_frames = 0);

  // A procedural path (options.Check() is applied). Depth timestamps equal RGB timestamps. Throws InputError
  // naming camera.fps when frames come so fast that their times are alike in StampText.
  static CameraPath Procedural(const ProceduralPathOptions& options);

  // In time order. No two frames share an RGB or a depth StampText, so every frame's images get files of
  // their own.
  const std::vector<CameraFrame>& frames() const { return frames_; }
  std::size_t size() const { return frames_.size(); }
  // The camera poses as a ground-truth trajectory (RGB timestamps).
  core::Trajectory Trajectory() const;

 private:
  std::vector<CameraFrame> frames_;
};

// The pose a fraction `s` of the way from `a` to `b`: linear in position, slerp in rotation; exactly `a` for
// s <= 0 and exactly `b` for s >= 1.
core::Pose LerpPose(const core::Pose& a, const core::Pose& b, double s);

// The pose of `trajectory` (sorted by time, non-empty) at `timestamp` within its time span: LerpPose between
// the two bracketing poses; exact at the poses themselves.
core::Pose InterpolatePose(const core::Trajectory& trajectory, double timestamp);

// A timestamp as written to the TUM lists and in the image file names of a sequence: `%.6f`.
std::string StampText(double timestamp);

}  // namespace hoidslam::synth
