#pragma once
// The SLAM system behind one small facade: ORB extraction, tracking, local mapping and loop closing (each in its
// own thread, or in step with tracking in the deterministic mode). A caller extracts a frame's features, decides which
// keypoints to keep (the exclusion filter), and tracks the frame with the kept ones; at the end it reads the
// trajectory and the map.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/core/camera.h"
#include "hoidslam/core/frame.h"
#include "hoidslam/core/options.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/features/orb_extractor.h"
#include "hoidslam/slam/local_mapper.h"
#include "hoidslam/slam/loop_closer.h"
#include "hoidslam/slam/data/map.h"
#include "hoidslam/slam/data/sensor.h"
#include "hoidslam/slam/tracker.h"

namespace hoidslam::slam {

// The vocabulary shipped with hoidslam (data/vocabulary of core::ShippedDir).
std::filesystem::path ShippedVocabulary();

struct SystemOptions {
  core::CameraIntrinsics camera;
  double bf = 40.0;           // Camera.bf: virtual baseline (metres) times fx (pixels)
  double close_depth = 2.99;  // metres: ThDepth * bf / fx
  core::OrbOptions orb;
  TrackerOptions tracking;
  LocalMapperOptions mapping;
  LoopClosingOptions loop_closing;
  FinalAdjustmentOptions final_adjustment;  // of every map, by Finish (never with `localization`)
  // Local mapping in step with tracking (no thread) and single-threaded bundle adjustment: the same input gives
  // a byte-identical trajectory on every run.
  bool deterministic = false;
  // The bag-of-words vocabulary place recognition describes keyframes and lost frames with (docs/vocabulary.md):
  // by default the one shipped in data/vocabulary.
  std::filesystem::path vocabulary = ShippedVocabulary();
  // A map file (map_file.h) to start from instead of an empty map: tracking relocalises the first frame in it, and
  // new keyframes continue it. Empty: a new map.
  std::filesystem::path load_map;
  // With load_map: track against the loaded map without changing it (no keyframes, no local mapping, no loops).
  bool localization = false;

  void Check() const;
};

struct ExtractedFeatures {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

// One map of the Atlas (map.h) as the outputs show it: the frames tracked in it (after the merges) and its keyframes.
struct MapSummary {
  MapId id = 0;
  std::size_t frames = 0;
  std::size_t keyframes = 0;
};

// The main map of these: the one with the most tracked frames (of a tie, the first); 0 when there is none.
MapId MainMapOf(const std::vector<MapSummary>& maps);

// A map point as the outputs show it.
struct MapPointSample {
  Eigen::Vector3d position;
  cv::Vec3b color;  // BGR
  int observations = 0;
};

// Every map of the Atlas as a viewer draws it while the run goes: values by id, never pointers into the map.
struct AtlasView {
  struct Point {
    MapPointId id = 0;
    MapId map = 0;
    Eigen::Vector3f position;  // world, metres
    cv::Vec3b color;           // BGR
  };
  struct KeyFrameView {
    KeyFrameId id = 0;
    MapId map = 0;
    core::Pose T_wc;
  };
  std::vector<Point> points;           // by increasing id
  std::vector<KeyFrameView> keyframes;  // by increasing id
  // Keyframe pairs (lower id first) that share at least `kCovisibilityEdgeWeight` points, and the pairs a loop
  // closing or a merge joined.
  std::vector<std::pair<KeyFrameId, KeyFrameId>> covisibility;
  std::vector<std::pair<KeyFrameId, KeyFrameId>> loops;
  static constexpr int kCovisibilityEdgeWeight = 100;
};

class System {
 public:
  // Throws core::InputError when the options fail Check(), or naming the map file when options.load_map cannot be
  // loaded (see LoadMap).
  explicit System(const SystemOptions& options);
  ~System();  // stops local mapping and loop closing
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // ORB features of a colour (CV_8UC3, BGR) or grey (CV_8UC1) image.
  ExtractedFeatures Extract(const cv::Mat& image);
  // The features of the image last given to Extract once more, with the whole budget spent outside the pixels
  // `excluded` marks (CV_8UC1, non-zero = excluded): features::OrbExtractor::ExtractOutside.
  ExtractedFeatures ExtractOutside(const cv::Mat& excluded);

  // Tracks the next frame with the keypoints whose keep flag is non-zero (keep is empty: all). The frame's depth
  // (metres) and colour are sampled at the kept keypoints. Throws std::invalid_argument when keep has the wrong
  // size or the images do not match the camera size.
  TrackResult Track(const core::RgbdFrame& frame, const ExtractedFeatures& features, std::span<const std::uint8_t> keep);

  // Lets local mapping and loop closing finish their queues and stops them, then adjusts every map once more
  // (FinalAdjustmentOptions) and places each frame that is not a keyframe again by its own inliers in the adjusted
  // map (Tracker::PlaceFramesInAdjustedMap); the outputs below then show the final map.
  void Finish();
  // How long Finish's final adjustment took, ms (0 when there was none).
  double FinalAdjustmentMilliseconds() const { return final_adjustment_ms_; }
  // Writes the main map to a map file (map_file.h; after Finish, the final map). Throws core::InputError naming the
  // file when it cannot be written.
  void SaveMap(const std::filesystem::path& path) const;
  // The vocabulary's identity (bow::Vocabulary::identity), as a map file records it.
  const std::string& VocabularyIdentity() const { return vocabulary_.identity(); }

  // The maps frames were tracked in, by id (one, unless tracking was lost long in new ground and the new map was
  // never merged). The main map is the one with the most tracked frames (of a tie, the first): the trajectory, the
  // keyframes, the map points and the map file are its.
  std::vector<MapSummary> Maps() const;
  MapId MainMap() const;  // MainMapOf(Maps())
  // Every frame tracked in the map (by default the main one), placed relative to its reference keyframe as the map
  // finally has it (after a final adjustment, where its own inliers put it in the adjusted map).
  core::Trajectory FrameTrajectory() const;
  core::Trajectory FrameTrajectory(MapId map) const;
  // The main map's keyframes' poses, by id.
  core::Trajectory KeyFrameTrajectory() const;
  std::vector<MapPointSample> MapPoints() const;
  std::size_t NumKeyFrames() const;  // in the main map
  // Every map's points, keyframes and edges, copied under the map's shared lock. Safe to call from another thread
  // while tracking and local mapping go on (the viewer does); its cost is the copy, about 1 ms for 20,000 points.
  AtlasView ViewAtlas() const;
  // The loops closed so far, in order; and the merges of two maps.
  std::vector<LoopClosure> LoopClosures() const;
  std::vector<LoopClosure> MapMerges() const;
  LoopCloser::Timings LoopClosingTimings() const;

 private:
  SystemOptions options_;
  std::shared_ptr<const Sensor> sensor_;
  features::OrbExtractor extractor_;
  const bow::Vocabulary vocabulary_;
  Map map_;
  LocalMapper local_mapper_;
  LoopCloser loop_closer_;
  Tracker tracker_;
  double final_adjustment_ms_ = 0.0;
  std::uint64_t next_frame_id_ = 0;
  cv::Mat gray_;
};

}  // namespace hoidslam::slam
