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
  kHoidPlus, // the HOID rule plus depth-refined exclusion, memory across frames and a geometric safety net
};

std::string_view ToString(FilterMode mode);
// Parses "none", "person", "classes", "hoid2d", "hoid3d", "hoidplus"; throws InputError naming `parameter` otherwise.
FilterMode ParseFilterMode(std::string_view text, const std::string& parameter = "HOID.mode");

// A filter mode written "hoidplus:PARTS" (as --filter and bench --modes take it) runs only the parts named.
inline constexpr std::string_view kHoidPlusPartsPrefix = "hoidplus:";

// What mode hoidplus adds to the HOID rule (settings section HOIDplus.*; docs/hoidplus.md). Each part can be
// switched off on its own, for ablations.
struct HoidPlusOptions {
  // Part 1, depth-refined exclusion: inside a dynamic box only the keypoints at or in front of the box's
  // foreground depth cluster are dropped; the background behind it is kept.
  bool depth = true;                  // HOIDplus.depthRefinement
  // The foreground is the dominant mode of a histogram of the box's depths, out to where its density falls off.
  double depth_bin = 0.03;            // HOIDplus.depthBin, > 0: bin width as a share of the depth (sensor noise
                                      // grows with depth)
  double valley = 0.2;                // HOIDplus.valley, in (0, 1]: density, as a share of the peak's, that ends
                                      // a depth mode
  double foreground_share = 0.15;     // HOIDplus.foregroundShare, in (0, 1]: weight the nearest mode needs to be
                                      // the foreground (nearer, lighter modes are clutter or sensor noise)
  double depth_extent = 0.5;          // HOIDplus.depthExtent, metres, >= 0: how far behind the foreground's
                                      // median depth the thing still reaches (a walker's back foot, an arm);
                                      // keypoints are kept only beyond both this and the mode's far end
  int edge_margin = 3;                // HOIDplus.edgeMargin, pixels, >= 0: foreground grown by this much, so
                                      // corners on a moving silhouette's edge drop too
  double box_margin = 0.05;           // HOIDplus.boxMargin, >= 0: dynamic boxes grown by this share of their
                                      // size on each side (the depth test keeps the background they take in)
  // An object whose box, at its foreground depth, is larger than anything of its class a person handles (a desk a
  // detector calls a laptop, a wall called a tv: LargestHandled) is not handled, and its box not dropped.
  bool size_check = true;             // HOIDplus.sizeCheck
  // Part 2, memory across frames.
  bool memory = true;                 // HOIDplus.memory
  double association_iou = 0.3;       // HOIDplus.associationIoU, (0, 1]: same-class box overlap to continue a track
  double relabel_iou = 0.6;           // HOIDplus.relabelIoU, (0, 1]: overlap at which a box of another class
                                      // continues a track (detectors confuse classes)
  double max_missed_seconds = 0.5;    // HOIDplus.maxMissedSeconds, >= 0: a confirmed track missed this long is
                                      // still excluded, its box carried by its keypoints' motion
  double still_seconds = 1.0;         // HOIDplus.stillSeconds, >= 0: a handled object must be seen still this
                                      // long before it counts as static again
  double still_distance = 0.1;        // HOIDplus.stillDistance, metres, > 0: how far a still object may seem to move
  // Part 3, the geometric safety net: a map point that is an outlier of the pose optimisation this many times in
  // a row is taken to be moving and removed from the map.
  bool safety_net = true;             // HOIDplus.safetyNet
  int moving_point_outliers = 3;      // HOIDplus.movingPointOutliers, >= 1

  // Turns on only the parts named in `parts`, "+"-separated from depth, memory and net (as in
  // `--filter hoidplus:depth+memory`). Throws InputError naming `parameter` for an unknown or empty part.
  void SetParts(std::string_view parts, const std::string& parameter);
  // The parts switched on, as SetParts takes them ("depth+memory+net"; "" when none).
  std::string Parts() const;
  void Check() const;
};

// The HOID interaction filter (settings section HOID.*).
struct HoidOptions {
  FilterMode mode = FilterMode::kHoidPlus;                  // HOID.mode
  double min_interaction_area = 0.4;                       // HOID.minInteractionArea, in (0, 1]: area(O∩P)/area(O)
  double depth_threshold = 0.2;                            // HOID.depthThreshold, metres, > 0 (hoid3d only)
  int sample_box_size = 20;                                // HOID.sampleBoxSize, pixels, >= 1 (hoid3d only)
  std::string person_class = "person";                     // HOID.personClass: always dynamic
  std::vector<std::string> dynamic_classes = {             // HOID.dynamicClasses: potentially dynamic objects
      "person", "chair", "cup", "book", "bottle", "keyboard", "laptop", "mouse", "tv"};
  HoidPlusOptions plus;                                    // mode hoidplus only

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
  // A dim image (lights down, exposure at its limit) is brightened before extraction, so that the FAST thresholds,
  // which are absolute grey levels, still find its corners: an image whose mean grey is below dim_mean is scaled
  // towards that mean, by at most max_gain. A gain changes no BRIEF test, so its keypoints match the map's.
  double dim_mean = 48.0;  // ORBextractor.dimMean, in [0, 255] (0: never brighten)
  double max_gain = 4.0;   // ORBextractor.maxGain, >= 1

  void Check() const;
};

}  // namespace hoidslam::core
