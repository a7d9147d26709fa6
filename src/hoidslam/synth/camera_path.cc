#include "hoidslam/synth/camera_path.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/synth/option_checks.h"
#include "hoidslam/synth/plane_geometry.h"
#include "hoidslam/synth/random.h"

namespace hoidslam::synth {
namespace {

constexpr core::EnumNames<ProceduralMotion, 6> kMotionNames = {{
    {ProceduralMotion::kStatic, "static"},
    {ProceduralMotion::kXyz, "xyz"},
    {ProceduralMotion::kHalfsphere, "halfsphere"},
    {ProceduralMotion::kRpy, "rpy"},
    {ProceduralMotion::kCircle, "circle"},
    {ProceduralMotion::kWaypoints, "waypoints"},
}};

// Camera axes in the world: x right, y down, z = forward.
core::Pose PoseFromForward(const Eigen::Vector3d& position, const Eigen::Vector3d& forward,
                           const Eigen::Vector3d& right) {
  core::Pose T_wc = core::Pose::Identity();
  T_wc.linear().col(0) = right;
  T_wc.linear().col(1) = forward.cross(right);
  T_wc.linear().col(2) = forward;
  T_wc.translation() = position;
  return T_wc;
}

void RequireFile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw core::InputError::InFile(path, "file not found");
}

// Two frames whose RGB (or depth) stamps print alike: `frame` repeats the stamp of the `earlier` one.
struct StampClash {
  std::size_t frame = 0;
  std::size_t earlier = 0;
  std::string_view kind;    // "RGB" or "depth"
  std::string_view folder;  // where their images would go: "rgb" or "depth"
  std::string stamp;
};

// Frames are written to files named by their stamp text, so frames whose stamps print alike would write the same
// file (concurrently) and repeat it in the lists. RGB stamps of different frames are distinct numbers, but may
// round alike; depth stamps repeat whenever an associations file pairs two colour images with one depth image.
std::optional<StampClash> FindStampClash(const std::vector<CameraFrame>& frames) {
  std::unordered_map<std::string, std::size_t> rgb;
  std::unordered_map<std::string, std::size_t> depth;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    std::string rgb_stamp = StampText(frames[i].timestamp);
    if (const auto [at, added] = rgb.try_emplace(rgb_stamp, i); !added) {
      return StampClash{i, at->second, "RGB", "rgb", std::move(rgb_stamp)};
    }
    std::string depth_stamp = StampText(frames[i].depth_timestamp);
    if (const auto [at, added] = depth.try_emplace(depth_stamp, i); !added) {
      return StampClash{i, at->second, "depth", "depth", std::move(depth_stamp)};
    }
  }
  return std::nullopt;
}

// The first camera's view direction made level (in its own frame), or zero when it looks straight up or down.
Eigen::Vector3d LevelForward(const core::Pose& T_anchor) {
  const Eigen::Vector3d up = T_anchor.linear().transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d level = Eigen::Vector3d::UnitZ() - up.z() * up;
  return level.norm() > 1e-6 ? Eigen::Vector3d(level.normalized()) : Eigen::Vector3d::Zero();
}

// A smooth hand-held shake: along and about each camera axis, a sum of sines of seeded frequencies. The
// frequencies are not multiples of the turn rate, so a camera going round twice never repeats its poses; every
// sine starts at zero, so the first pose is the anchor; the weights add up to one, so the bounds hold.
class HandShake {
 public:
  explicit HandShake(std::uint64_t seed) {
    Random random(seed);
    for (auto& axis : axes_) {
      double total = 0.0;
      for (Sine& sine : axis) {
        // One random number per statement: the order of evaluation within one is the compiler's choice.
        sine.frequency = random.Uniform(0.05, 0.5);  // Hz: a slow sway, not a tremor
        sine.weight = random.Uniform(0.3, 1.0);
        if (random.Bernoulli(0.5)) sine.weight = -sine.weight;
        total += std::abs(sine.weight);
      }
      for (Sine& sine : axis) sine.weight /= total;
    }
  }

  // The shake at `elapsed` seconds, within `metres` along and `radians` about each camera axis.
  core::Pose At(double elapsed, double metres, double radians) const {
    Eigen::Matrix<double, 6, 1> value;
    for (std::size_t i = 0; i < axes_.size(); ++i) {
      double sum = 0.0;
      for (const Sine& sine : axes_[i]) {
        sum += sine.weight * std::sin(2.0 * std::numbers::pi * sine.frequency * elapsed);
      }
      value[static_cast<Eigen::Index>(i)] = sum;
    }
    core::Pose shake = core::Pose::Identity();
    shake.translation() = metres * value.head<3>();
    shake.linear() = (Eigen::AngleAxisd(radians * value[3], Eigen::Vector3d::UnitX()) *
                      Eigen::AngleAxisd(radians * value[4], Eigen::Vector3d::UnitY()) *
                      Eigen::AngleAxisd(radians * value[5], Eigen::Vector3d::UnitZ()))
                         .toRotationMatrix();
    return shake;
  }

 private:
  struct Sine {
    double frequency = 0.0;
    double weight = 0.0;
  };
  std::array<std::array<Sine, 3>, 6> axes_;  // x, y, z along, then about, the camera axes
};

// The motion relative to the first pose, in the first camera's frame, at `phase` radians of the cycle.
core::Pose RelativeMotion(const ProceduralPathOptions& o, double phase) {
  const double a = o.amplitude;
  const double angle = Radians(o.angle_amplitude_deg);
  core::Pose motion = core::Pose::Identity();
  switch (o.motion) {
    case ProceduralMotion::kStatic:
      break;
    case ProceduralMotion::kXyz:
      // A Lissajous figure through the start: sideways, up-down and forward-back at different rates.
      motion.translation() = Eigen::Vector3d(a * std::sin(phase), 0.5 * a * std::sin(2.0 * phase),
                                             0.6 * a * std::sin(0.5 * phase));
      break;
    case ProceduralMotion::kRpy:
      motion.linear() = (Eigen::AngleAxisd(angle * std::sin(phase), Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(0.6 * angle * std::sin(2.0 * phase), Eigen::Vector3d::UnitX()) *
                         Eigen::AngleAxisd(0.4 * angle * std::sin(0.5 * phase), Eigen::Vector3d::UnitZ()))
                            .toRotationMatrix();
      break;
    case ProceduralMotion::kHalfsphere: {
      // Orbit the pivot ahead: azimuth about the camera's down axis, elevation about its right axis.
      const Eigen::Vector3d pivot(0.0, 0.0, o.pivot_distance);
      const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(angle * std::sin(phase), Eigen::Vector3d::UnitY()) *
                                        Eigen::AngleAxisd(0.5 * angle * std::sin(2.0 * phase), Eigen::Vector3d::UnitX()))
                                           .toRotationMatrix();
      motion.linear() = rotation;
      motion.translation() = pivot - rotation * pivot;
      break;
    }
    case ProceduralMotion::kWaypoints:  // placed in the room by its waypoints, not relative to an anchor
      break;
    case ProceduralMotion::kCircle: {
      // Turn about the vertical through the centre, `radius` behind the first pose on the level.
      const Eigen::Vector3d up = o.T_anchor.linear().transpose() * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d centre = -o.radius * LevelForward(o.T_anchor);
      const Eigen::Matrix3d rotation = Eigen::AngleAxisd(phase, up).toRotationMatrix();
      motion.linear() = rotation;
      motion.translation() = centre - rotation * centre;
      break;
    }
  }
  return motion;
}

// The waypoint path's own checks (ProceduralPathOptions::Check).
void CheckWaypoints(const std::vector<CameraWaypoint>& waypoints, double fps, std::size_t frames) {
  if (waypoints.size() < 2) {
    throw core::InputError::ForParameter("camera.waypoints",
                                         fmt::format("needs at least two waypoints, got {}", waypoints.size()));
  }
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const CameraWaypoint& w = waypoints[i];
    const auto key = [i](const char* name) { return fmt::format("camera.waypoints[{}].{}", i, name); };
    if (i == 0 && w.time != 0.0) {
      throw core::InputError::ForParameter(key("time"), fmt::format("must be 0 (the path starts at its first "
                                                                    "waypoint), got {}", w.time));
    }
    if (i > 0 && !(w.time > waypoints[i - 1].time && std::isfinite(w.time))) {
      throw core::InputError::ForParameter(
          key("time"), fmt::format("must be after waypoints[{}].time ({} s), got {}", i - 1, waypoints[i - 1].time,
                                   w.time));
    }
    if (!w.position.allFinite()) throw core::InputError::ForParameter(key("position"), "must be finite");
    CheckInRange(w.yaw_deg, -360.0, 360.0, key("yaw_deg"));
    CheckInRange(w.pitch_deg, -89.0, 89.0, key("pitch_deg"));
    CheckInRange(w.roll_deg, -360.0, 360.0, key("roll_deg"));
  }
  const std::size_t most = WaypointFrameCount(waypoints, fps);
  if (frames > most) {
    throw core::InputError::ForParameter(
        "camera.frames", fmt::format("{} frames at {} fps run past the last waypoint at {} s ({} frames)", frames, fps,
                                     waypoints.back().time, most));
  }
}

}  // namespace

core::Pose CameraPoseFromYawPitch(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg) {
  const double yaw = Radians(yaw_deg);
  const double pitch = Radians(pitch_deg);
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  return PoseFromForward(position, forward, Eigen::Vector3d(std::sin(yaw), -std::cos(yaw), 0.0));
}

core::Pose CameraPoseFromYawPitchRoll(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg,
                                      double roll_deg) {
  core::Pose T_wc = CameraPoseFromYawPitch(position, yaw_deg, pitch_deg);
  T_wc.linear() = T_wc.linear() * Eigen::AngleAxisd(Radians(roll_deg), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T_wc;
}

core::Pose CameraPoseLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d direction = target - eye;
  if (!(direction.norm() > 1e-9)) throw core::InputError("camera look-at: the eye and the target coincide");
  const Eigen::Vector3d forward = direction.normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
  if (!(right.norm() > 1e-6)) throw core::InputError("camera look-at: the view is vertical, the horizon is undefined");
  return PoseFromForward(eye, forward, right.normalized());
}

WaypointCurve::WaypointCurve(const std::vector<CameraWaypoint>& waypoints) {
  for (const CameraWaypoint& waypoint : waypoints) {
    Values v = {waypoint.position.x(), waypoint.position.y(), waypoint.position.z(), waypoint.yaw_deg,
                waypoint.pitch_deg, waypoint.roll_deg};
    if (!values_.empty()) {
      // Yaw and roll turn the shorter way from the waypoint before.
      for (const std::size_t angle : {std::size_t{3}, std::size_t{5}}) {
        v[angle] = values_.back()[angle] + std::remainder(v[angle] - values_.back()[angle], 360.0);
      }
    }
    times_.push_back(waypoint.time);
    values_.push_back(v);
  }
  const std::size_t n = values_.size();
  slopes_.assign(n, Values{});  // zero at both ends: the camera starts and ends at rest
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double h0 = times_[k] - times_[k - 1];
    const double h1 = times_[k + 1] - times_[k];
    for (std::size_t c = 0; c < kChannels; ++c) {
      const double before = (values_[k][c] - values_[k - 1][c]) / h0;
      const double after = (values_[k + 1][c] - values_[k][c]) / h1;
      if (before * after <= 0.0) continue;  // turns back (or rests) here: flat, so nothing overshoots
      const double mean = (h1 * before + h0 * after) / (h0 + h1);
      const double limit = 3.0 * std::min(std::abs(before), std::abs(after));
      slopes_[k][c] = std::clamp(mean, -limit, limit);
    }
  }
}

core::Pose WaypointCurve::At(double time) const {
  Values v = values_.front();
  if (time >= times_.back()) {
    v = values_.back();
  } else if (time > times_.front()) {
    const std::size_t k =
        static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), time) - times_.begin()) - 1;
    const double h = times_[k + 1] - times_[k];
    const double s = (time - times_[k]) / h;
    // Cubic Hermite basis; at s = 0 it gives the waypoint's value exactly.
    const double s2 = s * s;
    const double s3 = s2 * s;
    const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    const double h10 = s3 - 2.0 * s2 + s;
    const double h01 = -2.0 * s3 + 3.0 * s2;
    const double h11 = s3 - s2;
    for (std::size_t c = 0; c < kChannels; ++c) {
      v[c] = h00 * values_[k][c] + h10 * h * slopes_[k][c] + h01 * values_[k + 1][c] + h11 * h * slopes_[k + 1][c];
    }
  }
  return CameraPoseFromYawPitchRoll({v[0], v[1], v[2]}, v[3], v[4], v[5]);
}

std::size_t WaypointFrameCount(const std::vector<CameraWaypoint>& waypoints, double fps) {
  if (waypoints.empty()) return 0;
  // The tolerance keeps a last waypoint that lies on a frame, but for rounding, in the path.
  const double span = waypoints.back().time - waypoints.front().time;
  return static_cast<std::size_t>(std::floor(span * fps + 1e-6)) + 1;
}

std::string_view ToString(ProceduralMotion motion) { return core::EnumName(kMotionNames, motion); }

ProceduralMotion ParseProceduralMotion(std::string_view text, const std::string& parameter) {
  return core::ParseEnumName(kMotionNames, text, parameter, "camera motion");
}

void ProceduralPathOptions::Check() const {
  const auto fail = [](const char* name, const std::string& what) {
    throw core::InputError::ForParameter(fmt::format("camera.{}", name), what);
  };
  if (!(fps > 0.0 && std::isfinite(fps))) fail("fps", fmt::format("must be > 0, got {}", fps));
  if (frames < 1) fail("frames", "must be >= 1");
  if (!(start_time >= 0.0 && std::isfinite(start_time))) fail("start_time", fmt::format("must be >= 0, got {}", start_time));
  if (!(amplitude >= 0.0 && std::isfinite(amplitude))) fail("amplitude", fmt::format("must be >= 0 metres, got {}", amplitude));
  if (!(angle_amplitude_deg >= 0.0 && angle_amplitude_deg <= 90.0)) {
    fail("angle_amplitude_deg", fmt::format("must be in [0, 90] degrees, got {}", angle_amplitude_deg));
  }
  if (!(pivot_distance > 0.0 && std::isfinite(pivot_distance))) {
    fail("pivot_distance", fmt::format("must be > 0 metres, got {}", pivot_distance));
  }
  if (!(period > 0.0 && std::isfinite(period))) fail("period", fmt::format("must be > 0 seconds, got {}", period));
  if (motion != ProceduralMotion::kCircle && motion != ProceduralMotion::kWaypoints) return;
  CheckInRange(wobble, 0.0, 0.5, "camera.wobble");
  CheckInRange(wobble_angle_deg, 0.0, 10.0, "camera.wobble_angle_deg");
  if (motion == ProceduralMotion::kWaypoints) {
    CheckWaypoints(waypoints, fps, frames);
    return;
  }
  if (!(radius > 0.0 && std::isfinite(radius))) fail("radius", fmt::format("must be > 0 metres, got {}", radius));
  if (LevelForward(T_anchor).isZero()) fail("pitch_deg", "the circle camera cannot look straight up or down");
}

core::Pose LerpPose(const core::Pose& a, const core::Pose& b, double s) {
  // The ends are returned as given, so that a pose sampled exactly at a knot (or an object at the end of a
  // motion) is bit-identical to the knot rather than a quaternion round trip away from it.
  if (s <= 0.0) return a;
  if (s >= 1.0) return b;
  core::Pose pose = core::Pose::Identity();
  pose.linear() = Eigen::Quaterniond(a.linear()).slerp(s, Eigen::Quaterniond(b.linear())).toRotationMatrix();
  pose.translation() = a.translation() + s * (b.translation() - a.translation());
  return pose;
}

core::Pose InterpolatePose(const core::Trajectory& trajectory, double timestamp) {
  const auto after = std::upper_bound(trajectory.begin(), trajectory.end(), timestamp,
                                      [](double t, const core::StampedPose& pose) { return t < pose.timestamp; });
  if (after == trajectory.begin()) return trajectory.front().T_wc;
  if (after == trajectory.end()) return trajectory.back().T_wc;
  const core::StampedPose& a = *(after - 1);
  const core::StampedPose& b = *after;
  return LerpPose(a.T_wc, b.T_wc, (timestamp - a.timestamp) / (b.timestamp - a.timestamp));
}

std::string StampText(double timestamp) { return fmt::format("{:.6f}", timestamp); }

CameraPath CameraPath::FromTum(const std::filesystem::path& groundtruth, const std::filesystem::path& associations,
                               const core::Pose& T_anchor, std::size_t max_frames) {
  RequireFile(groundtruth);
  RequireFile(associations);
  const core::Trajectory truth = io::ReadTumTrajectory(groundtruth);
  if (truth.empty()) throw core::InputError::InFile(groundtruth, "holds no pose");
  const std::vector<io::AssociationLine> lines = io::ReadAssociationList(associations);

  CameraPath path;
  std::vector<std::size_t> line_of_frame;  // for messages about a frame
  core::Pose T_anchor_tum = core::Pose::Identity();  // T_anchor * T_tum_wc(t0)^-1
  for (const io::AssociationLine& line : lines) {
    if (line.rgb_timestamp < truth.front().timestamp || line.rgb_timestamp > truth.back().timestamp) continue;
    if (max_frames > 0 && path.frames_.size() == max_frames) break;
    const core::Pose T_tum_wc = InterpolatePose(truth, line.rgb_timestamp);
    if (path.frames_.empty()) T_anchor_tum = T_anchor * T_tum_wc.inverse();
    path.frames_.push_back({line.rgb_timestamp, line.depth_timestamp, T_anchor_tum * T_tum_wc});
    line_of_frame.push_back(line.line);
  }
  if (path.frames_.empty()) {
    throw core::InputError::InFile(
        associations, fmt::format("no frame falls within the time span of {} ({:.6f} to {:.6f})", groundtruth.string(),
                                  truth.front().timestamp, truth.back().timestamp));
  }
  if (const auto clash = FindStampClash(path.frames_)) {
    throw core::InputError::AtLine(
        associations, line_of_frame[clash->frame],
        fmt::format("the {} timestamp {} is the same as on line {} at 6 decimals: both frames would be written to "
                    "{}/{}.png",
                    clash->kind, clash->stamp, line_of_frame[clash->earlier], clash->folder, clash->stamp));
  }
  return path;
}

CameraPath CameraPath::Procedural(const ProceduralPathOptions& options) {
  options.Check();
  const HandShake shake(options.wobble_seed);
  const bool waypoints = options.motion == ProceduralMotion::kWaypoints;
  const std::optional<WaypointCurve> curve =
      waypoints ? std::optional<WaypointCurve>(options.waypoints) : std::nullopt;
  CameraPath path;
  path.frames_.reserve(options.frames);
  for (std::size_t i = 0; i < options.frames; ++i) {
    const double elapsed = static_cast<double>(i) / options.fps;
    const double timestamp = options.start_time + elapsed;
    core::Pose T_wc = waypoints ? curve->At(elapsed)
                                : options.T_anchor *
                                      RelativeMotion(options, 2.0 * std::numbers::pi * elapsed / options.period);
    if (options.motion == ProceduralMotion::kCircle || waypoints) {
      T_wc = T_wc * shake.At(elapsed, options.wobble, Radians(options.wobble_angle_deg));
    }
    path.frames_.push_back({timestamp, timestamp, T_wc});
  }
  if (const auto clash = FindStampClash(path.frames_)) {
    throw core::InputError::ForParameter(
        "camera.fps", fmt::format("{} frames per second puts frames {} and {} at the same timestamp {} at 6 "
                                  "decimals (the precision of the file names)",
                                  options.fps, clash->earlier, clash->frame, clash->stamp));
  }
  return path;
}

core::Trajectory CameraPath::Trajectory() const {
  core::Trajectory trajectory;
  trajectory.reserve(frames_.size());
  for (const CameraFrame& frame : frames_) trajectory.push_back({frame.timestamp, frame.T_wc});
  return trajectory;
}

}  // namespace hoidslam::synth
