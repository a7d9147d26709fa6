#include "hoidslam/synth/camera_path.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/io/text_lines.h"
#include "hoidslam/io/trajectory_file.h"

namespace hoidslam::synth {
namespace {

constexpr core::EnumNames<ProceduralMotion, 4> kMotionNames = {{
    {ProceduralMotion::kStatic, "static"},
    {ProceduralMotion::kXyz, "xyz"},
    {ProceduralMotion::kHalfsphere, "halfsphere"},
    {ProceduralMotion::kRpy, "rpy"},
}};

double Radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

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

struct AssociatedTimes {
  double rgb = 0.0;
  double depth = 0.0;
};

std::vector<AssociatedTimes> ReadAssociations(const std::filesystem::path& path) {
  std::vector<AssociatedTimes> times;
  io::ForEachDataLine(path, [&](std::size_t line, const std::vector<std::string_view>& fields) {
    if (fields.size() < 4) {
      throw core::InputError::AtLine(path, line, "expected `t_rgb rgb/<file> t_depth depth/<file>`");
    }
    const AssociatedTimes entry{io::ParseDouble(fields[0], path, line), io::ParseDouble(fields[2], path, line)};
    if (!times.empty() && entry.rgb <= times.back().rgb) {
      throw core::InputError::AtLine(path, line, "RGB timestamps must increase from line to line");
    }
    times.push_back(entry);
  });
  return times;
}

void RequireFile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw core::InputError::InFile(path, "file not found");
}

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
  }
  return motion;
}

}  // namespace

core::Pose CameraPoseFromYawPitch(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg) {
  const double yaw = Radians(yaw_deg);
  const double pitch = Radians(pitch_deg);
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  return PoseFromForward(position, forward, Eigen::Vector3d(std::sin(yaw), -std::cos(yaw), 0.0));
}

core::Pose CameraPoseLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d direction = target - eye;
  if (!(direction.norm() > 1e-9)) throw core::InputError("camera look-at: the eye and the target coincide");
  const Eigen::Vector3d forward = direction.normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
  if (!(right.norm() > 1e-6)) throw core::InputError("camera look-at: the view is vertical, the horizon is undefined");
  return PoseFromForward(eye, forward, right.normalized());
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
}

core::Pose InterpolatePose(const core::Trajectory& trajectory, double timestamp) {
  const auto after = std::upper_bound(trajectory.begin(), trajectory.end(), timestamp,
                                      [](double t, const core::StampedPose& pose) { return t < pose.timestamp; });
  if (after == trajectory.begin()) return trajectory.front().T_wc;
  if (after == trajectory.end()) return trajectory.back().T_wc;
  const core::StampedPose& a = *(after - 1);
  const core::StampedPose& b = *after;
  const double s = (timestamp - a.timestamp) / (b.timestamp - a.timestamp);
  if (s == 0.0) return a.T_wc;
  const Eigen::Quaterniond qa(a.T_wc.linear());
  const Eigen::Quaterniond qb(b.T_wc.linear());
  core::Pose pose = core::Pose::Identity();
  pose.linear() = qa.slerp(s, qb).toRotationMatrix();
  pose.translation() = (1.0 - s) * a.T_wc.translation() + s * b.T_wc.translation();
  return pose;
}

CameraPath CameraPath::FromTum(const std::filesystem::path& groundtruth, const std::filesystem::path& associations,
                               const core::Pose& T_anchor, std::size_t max_frames) {
  RequireFile(groundtruth);
  RequireFile(associations);
  const core::Trajectory truth = io::ReadTumTrajectory(groundtruth);
  if (truth.empty()) throw core::InputError::InFile(groundtruth, "holds no pose");
  const std::vector<AssociatedTimes> times = ReadAssociations(associations);

  CameraPath path;
  core::Pose T_anchor_tum = core::Pose::Identity();  // T_anchor * T_tum_wc(t0)^-1
  for (const AssociatedTimes& time : times) {
    if (time.rgb < truth.front().timestamp || time.rgb > truth.back().timestamp) continue;
    if (max_frames > 0 && path.frames_.size() == max_frames) break;
    const core::Pose T_tum_wc = InterpolatePose(truth, time.rgb);
    if (path.frames_.empty()) T_anchor_tum = T_anchor * T_tum_wc.inverse();
    path.frames_.push_back({time.rgb, time.depth, T_anchor_tum * T_tum_wc});
  }
  if (path.frames_.empty()) {
    throw core::InputError::InFile(
        associations, fmt::format("no frame falls within the time span of {} ({:.6f} to {:.6f})", groundtruth.string(),
                                  truth.front().timestamp, truth.back().timestamp));
  }
  return path;
}

CameraPath CameraPath::Procedural(const ProceduralPathOptions& options) {
  options.Check();
  CameraPath path;
  path.frames_.reserve(options.frames);
  for (std::size_t i = 0; i < options.frames; ++i) {
    const double elapsed = static_cast<double>(i) / options.fps;
    const double timestamp = options.start_time + elapsed;
    const core::Pose T_wc = options.T_anchor * RelativeMotion(options, 2.0 * std::numbers::pi * elapsed / options.period);
    path.frames_.push_back({timestamp, timestamp, T_wc});
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
