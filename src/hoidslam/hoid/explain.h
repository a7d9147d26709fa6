#pragma once
// Human-readable accounts of HOID decisions, for logs, tables and annotated pictures (not for the hot path).

#include <span>
#include <string>

#include "hoidslam/core/detection.h"
#include "hoidslam/hoid/filter.h"

namespace hoidslam::hoid {

// One line on detection `index`, e.g. "cup 0.81 dynamic: interaction with person#0 (62%), depth 1.42 vs 1.38 m".
std::string DescribeDecision(std::span<const core::Detection> detections, std::span<const Decision> decisions,
                             std::size_t index);

// A short caption for drawing over the box, e.g. "cup 0.81 held 62%", "tv 0.77 behind 1.05m", "person 0.93".
std::string CaptionDecision(const core::Detection& detection, const Decision& decision);

}  // namespace hoidslam::hoid
