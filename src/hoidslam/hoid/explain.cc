#include "hoidslam/hoid/explain.h"

#include <cmath>

#include <fmt/format.h>

namespace hoidslam::hoid {

std::string DescribeDecision(std::span<const core::Detection> detections, std::span<const Decision> decisions,
                             std::size_t index) {
  const core::Detection& detection = detections[index];
  const Decision& decision = decisions[index];
  std::string line = fmt::format("{} {:.2f} {}: {}", detection.label, detection.score,
                                 decision.dynamic ? "dynamic" : "static", ToString(decision.reason));
  if (decision.person_index >= 0) {
    line += fmt::format(" with person#{} ({:.0f}%)", decision.person_index, 100.0F * decision.interaction_ratio);
  }
  if (!std::isnan(decision.depth) && !std::isnan(decision.person_depth)) {
    line += fmt::format(", depth {:.2f} vs {:.2f} m", decision.depth, decision.person_depth);
  } else if (!std::isnan(decision.depth)) {
    line += fmt::format(", depth {:.2f} m", decision.depth);
  }
  return line;
}

std::string CaptionDecision(const core::Detection& detection, const Decision& decision) {
  std::string caption = fmt::format("{} {:.2f}", detection.label, detection.score);
  switch (decision.reason) {
    case Reason::kInteraction:
    case Reason::kDepthConfirmed:
    case Reason::kDepthUnavailable:
      return caption + fmt::format(" held {:.0f}%", 100.0F * decision.interaction_ratio);
    case Reason::kDepthRejected:
      return caption + fmt::format(" behind {:.2f}m", decision.depth_difference);
    case Reason::kCarried:
      return caption + " carried";
    case Reason::kRecentlyHandled:
      return caption + " handled";
    case Reason::kSeenStill:
      return caption + " still";
    case Reason::kTooLargeToHandle:
      return caption + fmt::format(" {:.1f}m: too large", decision.extent);
    case Reason::kNoInteraction:
      return decision.person_index >= 0 ? caption + fmt::format(" {:.0f}%", 100.0F * decision.interaction_ratio)
                                        : caption;
    default:
      return caption;
  }
}

}  // namespace hoidslam::hoid
