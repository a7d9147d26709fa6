#pragma once
// Camera paths for synthetic sequences: either a real TUM fr3 camera path with its real frame timing,
// re-anchored into the synthetic room, or a procedural path at a fixed frame rate that needs no data files (a
// shape placed by its first pose, or a smooth path through timed waypoints in the room).
//
// Re-anchoring: T_synth_wc(t) = T_anchor * T_tum_wc(t0)^-1 * T_tum_wc(t), where t0 is the first frame kept,
// so the first camera pose is T_anchor and every motion relative to it is the real one.

#include <array>
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
// CameraPoseFromYawPitch turned by `roll_deg` about the optical axis; positive turns the image's right side down
// (clockwise, seen from behind the camera).
core::Pose CameraPoseFromYawPitchRoll(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg,
                                      double roll_deg);
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
  kWaypoints,   // "waypoints": a smooth path through timed poses in the room (WaypointCurve), with the same shake
};
std::string_view ToString(ProceduralMotion motion);
// Parses "static", "xyz", "halfsphere", "rpy", "circle", "waypoints"; throws InputError naming `parameter` otherwise.
ProceduralMotion ParseProceduralMotion(std::string_view text, const std::string& parameter);

// One timed pose of a waypoint path, in the room frame.
struct CameraWaypoint {
  double time = 0.0;                                   // seconds from the first frame
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // optical centre, metres
  double yaw_deg = 90.0;                               // heading (CameraPoseFromYawPitch), in [-360, 360]
  double pitch_deg = 0.0;                              // elevation, negative = down, in [-89, 89]
  double roll_deg = 0.0;  // about the optical axis (CameraPoseFromYawPitchRoll), in [-360, 360]
};

// A camera moving smoothly through timed waypoints: each of x, y, z, yaw, pitch and roll is a cubic Hermite curve
// of time through the waypoints' values. Its slope at a waypoint is the time-weighted mean of the slopes of the two
// straight pieces that meet there (Catmull-Rom for uneven steps), zero where the value turns back and at most three
// times the smaller of those slopes (so between two waypoints each value stays between theirs: no overshoot past a
// wall or a desk the waypoints keep clear of), and zero at the first and last waypoint (the camera starts and ends
// at rest). So the path goes exactly through every waypoint and its velocity is continuous (C1). Yaw and roll turn
// the shorter way from one waypoint to the next: a turn of more than 180 degrees needs waypoints in between.
class WaypointCurve {
 public:
  // `waypoints`: at least one, times strictly increasing (ProceduralPathOptions::Check says so by key).
  explicit WaypointCurve(const std::vector<CameraWaypoint>& waypoints);

  // The pose at `time` (the waypoints' clock); before the first or after the last waypoint, the pose there. At a
  // waypoint's time, exactly its pose (CameraPoseFromYawPitchRoll of its values; of yaw or roll unwrapped by
  // whole turns when they wrap round).
  core::Pose At(double time) const;

 private:
  static constexpr std::size_t kChannels = 6;  // x, y, z (metres), yaw, pitch, roll (degrees, unwrapped)
  using Values = std::array<double, kChannels>;
  std::vector<double> times_;
  std::vector<Values> values_;
  std::vector<Values> slopes_;  // per second
};

// The frames of a waypoint path at `fps`: one every 1 / fps seconds from the first waypoint's time to the last's
// (the last included when it falls on a frame).
std::size_t WaypointFrameCount(const std::vector<CameraWaypoint>& waypoints, double fps);

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
  // The circle's and the waypoint path's hand-held shake, so that a second turn (or a return) sees the room from
  // nearly, not exactly, the same poses: smooth, zero at the first frame, within these bounds along and about each
  // camera axis.
  double wobble = 0.03;            // metres, in [0, 0.5]
  double wobble_angle_deg = 2.0;   // degrees, in [0, 10]
  std::uint64_t wobble_seed = 1;
  core::Pose T_anchor = core::Pose::Identity();  // the pose at the first frame (waypoints: not used, the path
                                                 // starts at its first waypoint)
  // The waypoint path: at least two, the first at time 0, times strictly increasing; `frames` at most
  // WaypointFrameCount(waypoints, fps).
  std::vector<CameraWaypoint> waypoints;

  // Throws InputError naming the parameter ("camera.fps", "camera.waypoints[3].time", ...).
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
