#pragma once
// Typed options shared across modules. Each struct documents its defaults and has a Check() that rejects
// invalid values with an InputError naming the settings-file parameter (e.g. "HOID.minInteractionArea").

#include <string>
#include <string_view>
#include <vector>

namespace hoidslam::core {

// Which detections make features drop (DESIGN.md, "The benchmark we can run here").
enum class FilterMode {
  kNone,     // drop nothing: the plain ORB-SLAM3-like baseline
  kPerson,   // drop features inside person boxes only
  kClasses,  // drop features inside every box of a potentially dynamic class (semantic prior)
  kHoid2d,   // persons + objects whose box overlaps a person box by >= minInteractionArea of its own area
  kHoid3d,   // as kHoid2d, and the object's depth must be within depthThreshold of the person's
};

std::string_view ToString(FilterMode mode);
// Parses "none", "person", "classes", "hoid2d", "hoid3d"; throws InputError naming `parameter` otherwise.
FilterMode ParseFilterMode(std::string_view text, const std::string& parameter = "HOID.mode");

// The HOID interaction filter (settings section HOID.*).
struct HoidOptions {
  FilterMode mode = FilterMode::kHoid2d;                    // HOID.mode
  double min_interaction_area = 0.4;                       // HOID.minInteractionArea, in (0, 1]: area(O∩P)/area(O)
  double depth_threshold = 0.2;                            // HOID.depthThreshold, metres, > 0 (hoid3d only)
  int sample_box_size = 20;                                // HOID.sampleBoxSize, pixels, >= 1 (hoid3d only)
  std::string person_class = "person";                     // HOID.personClass: always dynamic
  std::vector<std::string> dynamic_classes = {             // HOID.dynamicClasses: potentially dynamic objects
      "person", "chair", "cup", "book", "bottle", "keyboard", "laptop", "mouse", "tv"};

  bool IsPotentiallyDynamic(std::string_view label) const;
  void Check() const;
};

// ORB feature extraction (settings section ORBextractor.*, ORB-SLAM3 names and defaults).
struct OrbOptions {
  int n_features = 1000;      // ORBextractor.nFeatures, >= 1
  double scale_factor = 1.2;  // ORBextractor.scaleFactor, > 1
  int n_levels = 8;           // ORBextractor.nLevels, >= 1
  int ini_th_fast = 20;       // ORBextractor.iniThFAST, >= 1
  int min_th_fast = 7;        // ORBextractor.minThFAST, in [1, iniThFAST]

  void Check() const;
};

}  // namespace hoidslam::core
