#pragma once
// Numbers as the page gets them: rounded to what it can show, so that the JSON stays short (a map of 20,000
// points is sent whole to each new page).

#include <cmath>

#include <nlohmann/json.hpp>

#include "hoidslam/core/pose.h"

namespace hoidslam::viewer {

// `value` rounded to 1 / `per_unit` (10: a tenth).
inline double Rounded(double value, double per_unit) { return std::round(value * per_unit) / per_unit; }

// A pose as the page takes it: the 4×4 matrix, row-major, rotation to 1e-6 and translation to 0.1 mm.
nlohmann::json PoseJson(const core::Pose& pose);

}  // namespace hoidslam::viewer
