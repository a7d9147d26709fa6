#pragma once
// The small angle and floor-plane helpers the office, its people and the camera paths share.

#include <cmath>
#include <numbers>

#include <Eigen/Core>

namespace hoidslam::synth {

inline constexpr double kPi = std::numbers::pi;

inline double Radians(double degrees) { return degrees * kPi / 180.0; }
inline double Degrees(double radians) { return radians * 180.0 / kPi; }

// The unit vector on the floor a yaw (radians, from +x towards +y) points along.
inline Eigen::Vector2d Direction(double yaw) { return {std::cos(yaw), std::sin(yaw)}; }

// The ease-in, ease-out ramp 3s² - 2s³ on [0, 1]: motion that starts and stops without a jerk.
inline double Smoothstep(double s) { return s * s * (3.0 - 2.0 * s); }

}  // namespace hoidslam::synth
