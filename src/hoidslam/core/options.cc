#include "hoidslam/core/options.h"

#include <algorithm>

#include <fmt/format.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"

namespace hoidslam::core {
namespace {

constexpr EnumNames<FilterMode, 5> kModeNames = {{
    {FilterMode::kNone, "none"},
    {FilterMode::kPerson, "person"},
    {FilterMode::kClasses, "classes"},
    {FilterMode::kHoid2d, "hoid2d"},
    {FilterMode::kHoid3d, "hoid3d"},
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
}

}  // namespace hoidslam::core
