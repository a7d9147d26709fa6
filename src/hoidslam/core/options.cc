#include "hoidslam/core/options.h"

#include <algorithm>
#include <array>
#include <utility>

#include <fmt/format.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/option_checks.h"

namespace hoidslam::core {
namespace {

constexpr EnumNames<FilterMode, 6> kModeNames = {{
    {FilterMode::kNone, "none"},
    {FilterMode::kPerson, "person"},
    {FilterMode::kClasses, "classes"},
    {FilterMode::kHoid2d, "hoid2d"},
    {FilterMode::kHoid3d, "hoid3d"},
    {FilterMode::kHoidPlus, "hoidplus"},
}};

// hoidplus's parts by the names --filter hoidplus:PARTS uses, in the order they are printed.
constexpr std::array<std::pair<std::string_view, bool HoidPlusOptions::*>, 3> kHoidPlusParts = {{
    {"depth", &HoidPlusOptions::depth},
    {"memory", &HoidPlusOptions::memory},
    {"net", &HoidPlusOptions::safety_net},
}};

}  // namespace

std::string_view ToString(FilterMode mode) { return EnumName(kModeNames, mode); }

FilterMode ParseFilterMode(std::string_view text, const std::string& parameter) {
  return ParseEnumName(kModeNames, text, parameter, "mode");
}

bool HoidOptions::IsPotentiallyDynamic(std::string_view label) const {
  return label == person_class ||
         std::find(dynamic_classes.begin(), dynamic_classes.end(), label) != dynamic_classes.end();
}

void HoidOptions::Check() const {
  if (!(min_interaction_area > 0.0 && min_interaction_area <= 1.0)) {
    throw InputError::ForParameter("HOID.minInteractionArea",
                                   fmt::format("must be in (0, 1], got {}", min_interaction_area));
  }
  if (!(depth_threshold > 0.0)) {
    throw InputError::ForParameter("HOID.depthThreshold", fmt::format("must be > 0 metres, got {}", depth_threshold));
  }
  if (sample_box_size < 1) {
    throw InputError::ForParameter("HOID.sampleBoxSize", fmt::format("must be >= 1 pixel, got {}", sample_box_size));
  }
  if (person_class.empty()) throw InputError::ForParameter("HOID.personClass", "must not be empty");
  for (const std::string& name : dynamic_classes) {
    if (name.empty()) throw InputError::ForParameter("HOID.dynamicClasses", "contains an empty class name");
  }
  plus.Check();
}

void HoidPlusOptions::SetParts(std::string_view parts, const std::string& parameter) {
  for (const auto& [name, on] : kHoidPlusParts) this->*on = false;
  std::string_view rest = parts;
  while (true) {
    const std::size_t end = rest.find('+');
    const std::string_view part = rest.substr(0, end);
    const auto named = std::find_if(kHoidPlusParts.begin(), kHoidPlusParts.end(),
                                    [&](const auto& entry) { return entry.first == part; });
    if (named == kHoidPlusParts.end()) {
      throw InputError::ForParameter(
          parameter, fmt::format("unknown hoidplus part '{}' in '{}': use depth, memory and net, joined by +", part, parts));
    }
    this->*(named->second) = true;
    if (end == std::string_view::npos) break;
    rest = rest.substr(end + 1);
  }
}

std::string HoidPlusOptions::Parts() const {
  std::string parts;
  for (const auto& [name, on] : kHoidPlusParts) {
    if (!(this->*on)) continue;
    if (!parts.empty()) parts += '+';
    parts += name;
  }
  return parts;
}

void HoidPlusOptions::Check() const {
  const auto positive = [](double value, const char* name) {
    if (!(value > 0.0)) throw InputError::ForParameter(name, fmt::format("must be > 0, got {}", value));
  };
  const auto not_negative = [](double value, const char* name) {
    if (!(value >= 0.0)) throw InputError::ForParameter(name, fmt::format("must be >= 0, got {}", value));
  };
  const auto share = [](double value, const char* name) {
    if (!(value > 0.0 && value <= 1.0)) throw InputError::ForParameter(name, fmt::format("must be in (0, 1], got {}", value));
  };
  positive(depth_bin, "HOIDplus.depthBin");
  share(valley, "HOIDplus.valley");
  share(foreground_share, "HOIDplus.foregroundShare");
  not_negative(depth_extent, "HOIDplus.depthExtent");
  not_negative(edge_margin, "HOIDplus.edgeMargin");
  not_negative(box_margin, "HOIDplus.boxMargin");
  share(association_iou, "HOIDplus.associationIoU");
  share(relabel_iou, "HOIDplus.relabelIoU");
  not_negative(max_missed_seconds, "HOIDplus.maxMissedSeconds");
  not_negative(still_seconds, "HOIDplus.stillSeconds");
  positive(still_distance, "HOIDplus.stillDistance");
  positive(moving_point_outliers, "HOIDplus.movingPointOutliers");
}

void OrbOptions::Check() const {
  if (n_features < 1) {
    throw InputError::ForParameter("ORBextractor.nFeatures", fmt::format("must be >= 1, got {}", n_features));
  }
  if (!(scale_factor > 1.0)) {
    throw InputError::ForParameter("ORBextractor.scaleFactor", fmt::format("must be > 1, got {}", scale_factor));
  }
  if (n_levels < 1) {
    throw InputError::ForParameter("ORBextractor.nLevels", fmt::format("must be >= 1, got {}", n_levels));
  }
  if (ini_th_fast < 1) {
    throw InputError::ForParameter("ORBextractor.iniThFAST", fmt::format("must be >= 1, got {}", ini_th_fast));
  }
  if (min_th_fast < 1 || min_th_fast > ini_th_fast) {
    throw InputError::ForParameter("ORBextractor.minThFAST",
                                   fmt::format("must be in [1, iniThFAST={}], got {}", ini_th_fast, min_th_fast));
  }
  CheckInRange(dim_mean, 0.0, 255.0, "ORBextractor.dimMean");
  if (!(max_gain >= 1.0)) {
    throw InputError::ForParameter("ORBextractor.maxGain", fmt::format("must be >= 1, got {}", max_gain));
  }
}

}  // namespace hoidslam::core
