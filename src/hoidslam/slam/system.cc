#include "hoidslam/slam/system.h"

#include <algorithm>
#include <cstring>
#include <shared_mutex>
#include <stdexcept>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/descriptor_distance.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/shipped_dir.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/slam/data/map_file.h"

namespace hoidslam::slam {

std::filesystem::path ShippedVocabulary() { return core::ShippedDir() / "data" / "vocabulary" / "orb-k10-l5.hbow"; }

void SystemOptions::Check() const {
  if (!(bf > 0.0)) throw core::InputError::ForParameter("Camera.bf", fmt::format("must be > 0, got {}", bf));
  if (!(close_depth > 0.0)) {
    throw core::InputError::ForParameter("ThDepth", fmt::format("must give a close depth > 0 m, got {}", close_depth));
  }
  orb.Check();
  tracking.Check();
  mapping.Check();
  loop_closing.Check();
  final_adjustment.Check();
  if (localization && load_map.empty()) {
    throw core::InputError::ForParameter("--localization", "needs a map to track against (--load-map)");
  }
}

namespace {

const SystemOptions& Checked(const SystemOptions& options) {
  options.Check();
  return options;
}

// The bundle adjustment of the deterministic mode runs on one thread: Ceres sums in a fixed order then.
LocalMapperOptions MapperOptions(const SystemOptions& options) {
  LocalMapperOptions mapping = options.mapping;
  if (options.deterministic) mapping.bundle_adjustment.num_threads = 1;
  return mapping;
}

// Frames keep their inliers to be placed again after the final adjustment, when there is one.
TrackerOptions TrackingOptions(const SystemOptions& options) {
  TrackerOptions tracking = options.tracking;
  tracking.record_inliers = options.final_adjustment.enabled && !options.localization;
  return tracking;
}

// Local mapping hands each keyframe it has mapped to loop closing, when it closes loops or merges maps. (The closer
// is constructed after the mapper, but no keyframe is mapped before both stand.)
std::function<void(KeyFrame*)> MappedCallback(const SystemOptions& options, LoopCloser& loop_closer) {
  if (!options.loop_closing.enabled && !options.loop_closing.merge_maps) return {};
  return [&loop_closer](KeyFrame* keyframe) { loop_closer.Insert(keyframe); };
}

// Where a frame stands in the final map: its reference keyframe's map, and its pose.
std::pair<MapId, core::Pose> Place(const Tracker::FrameRecord& record) {
  const auto [reference, T_cr] = record.Resolved();
  return {reference->map_id(), (T_cr * reference->T_cw()).inverse()};
}

}  // namespace

System::System(const SystemOptions& options)
    : options_(Checked(options)),
      extractor_(options.orb),
      vocabulary_(bow::Vocabulary::Load(options.vocabulary)),
      local_mapper_(map_, vocabulary_, MapperOptions(options), MappedCallback(options, loop_closer_)),
      loop_closer_(map_, local_mapper_, options.loop_closing),
      tracker_(map_, vocabulary_, local_mapper_, TrackingOptions(options)) {
  sensor_ = Sensor::Make(options.camera, options.bf, options.close_depth, extractor_.pyramid());
  if (!options.load_map.empty()) {
    std::unique_lock lock(map_.mutex());
    LoadMap(options.load_map, sensor_, vocabulary_, map_);
    tracker_.StartInLoadedMap(options.localization);
  }
  if (!options_.deterministic) {
    local_mapper_.Start();
    loop_closer_.Start();
  }
}

// Local mapping first: it hands keyframes to loop closing.
System::~System() {
  local_mapper_.Stop();
  loop_closer_.Stop();
}

ExtractedFeatures System::Extract(const cv::Mat& image) {
  if (image.type() == CV_8UC3) {
    cv::cvtColor(image, gray_, cv::COLOR_BGR2GRAY);
  } else if (image.type() == CV_8UC1) {
    gray_ = image;
  } else {
    throw std::invalid_argument("System::Extract: expected a CV_8UC3 or CV_8UC1 image");
  }
  ExtractedFeatures features;
  extractor_.Extract(gray_, features.keypoints, features.descriptors);
  return features;
}

ExtractedFeatures System::ExtractOutside(const cv::Mat& excluded) {
  ExtractedFeatures features;
  extractor_.ExtractOutside(excluded, features.keypoints, features.descriptors);
  return features;
}

TrackResult System::Track(const core::RgbdFrame& frame, const ExtractedFeatures& features,
                          std::span<const std::uint8_t> keep) {
  const std::size_t n = features.keypoints.size();
  if (!keep.empty() && keep.size() != n) throw std::invalid_argument("System::Track: one keep flag per keypoint");
  const cv::Size size(options_.camera.width, options_.camera.height);
  if (frame.rgb.size() != size || (!frame.depth.empty() && frame.depth.size() != size)) {
    throw std::invalid_argument(fmt::format("System::Track: images must be {}×{} as the camera settings say",
                                            size.width, size.height));
  }
  std::vector<cv::KeyPoint> kept;
  cv::Mat descriptors;
  if (keep.empty()) {
    kept = features.keypoints;
    descriptors = features.descriptors.clone();
  } else {
    const auto count = static_cast<int>(std::count_if(keep.begin(), keep.end(), [](std::uint8_t k) { return k != 0; }));
    kept.reserve(static_cast<std::size_t>(count));
    descriptors.create(count, core::kOrbDescriptorBytes, CV_8UC1);
    for (std::size_t i = 0; i < n; ++i) {
      if (keep[i] == 0) continue;
      std::memcpy(descriptors.ptr(static_cast<int>(kept.size())), features.descriptors.ptr(static_cast<int>(i)),
                  core::kOrbDescriptorBytes);
      kept.push_back(features.keypoints[i]);
    }
  }
  auto keypoints = std::make_shared<const KeypointSet>(sensor_, std::move(kept), std::move(descriptors), frame.depth,
                                                       frame.rgb);
  Frame tracked(next_frame_id_++, frame.timestamp, std::move(keypoints));
  tracked.depth_delay = frame.depth_delay;
  TrackResult result = tracker_.Track(std::move(tracked));
  if (options_.deterministic && result.keyframe) {
    local_mapper_.ProcessQueue();
    loop_closer_.ProcessQueue();
  }
  return result;
}

void System::Finish() {
  local_mapper_.Stop();
  local_mapper_.ProcessQueue();
  loop_closer_.Stop();
  loop_closer_.ProcessQueue();
  // A map tracked in for localisation stays as it was loaded.
  if (!options_.final_adjustment.enabled || options_.localization) return;
  const core::Stopwatch stopwatch;
#if defined(__GLIBC__)
  // What the joined threads freed is still held by the allocator: handed back first, the adjustment's problem (some
  // 70 MB for 170 keyframes) takes its place rather than adding to the run's peak memory.
  malloc_trim(0);
#endif
  std::vector<MapId> maps;
  {
    std::shared_lock lock(map_.mutex());
    maps = map_.Maps();
  }
  for (const MapId map : maps) loop_closer_.AdjustFinally(map, options_.final_adjustment);
  tracker_.PlaceFramesInAdjustedMap();
  final_adjustment_ms_ = stopwatch.ElapsedMilliseconds();
}

void System::SaveMap(const std::filesystem::path& path) const {
  const MapId main = MainMap();
  std::shared_lock lock(map_.mutex());
  slam::SaveMap(map_, main, *sensor_, vocabulary_, path);
}

std::vector<MapSummary> System::Maps() const {
  std::shared_lock lock(map_.mutex());
  std::vector<MapSummary> maps;
  for (const MapId id : map_.Maps()) maps.push_back({id, 0, map_.NumKeyFrames(id)});
  for (const Tracker::FrameRecord& record : tracker_.records()) {
    if (record.reference == nullptr) continue;
    const MapId id = Place(record).first;
    const auto map = std::find_if(maps.begin(), maps.end(), [id](const MapSummary& m) { return m.id == id; });
    if (map != maps.end()) ++map->frames;
  }
  std::erase_if(maps, [](const MapSummary& m) { return m.frames == 0; });
  return maps;
}

MapId MainMapOf(const std::vector<MapSummary>& maps) {
  const auto main = std::max_element(maps.begin(), maps.end(),
                                     [](const MapSummary& a, const MapSummary& b) { return a.frames < b.frames; });
  return main != maps.end() ? main->id : 0;
}

MapId System::MainMap() const { return MainMapOf(Maps()); }

core::Trajectory System::FrameTrajectory() const { return FrameTrajectory(MainMap()); }

core::Trajectory System::FrameTrajectory(MapId map) const {
  std::shared_lock lock(map_.mutex());
  core::Trajectory trajectory;
  for (const Tracker::FrameRecord& record : tracker_.records()) {
    if (record.reference == nullptr) continue;
    const auto [id, T_wc] = Place(record);
    if (id == map) trajectory.push_back({record.timestamp, T_wc});
  }
  return trajectory;
}

core::Trajectory System::KeyFrameTrajectory() const {
  const MapId main = MainMap();
  std::shared_lock lock(map_.mutex());
  core::Trajectory trajectory;
  for (const KeyFrame* keyframe : map_.KeyFrames(main)) trajectory.push_back({keyframe->timestamp(), keyframe->T_wc()});
  return trajectory;
}

std::vector<MapPointSample> System::MapPoints() const {
  const MapId main = MainMap();
  std::shared_lock lock(map_.mutex());
  std::vector<MapPointSample> samples;
  for (const MapPoint* point : map_.MapPoints(main)) {
    samples.push_back({point->position(), point->color(), static_cast<int>(point->observations().size())});
  }
  return samples;
}

AtlasView System::ViewAtlas() const {
  AtlasView view;
  std::shared_lock lock(map_.mutex());
  const std::vector<MapPoint*> points = map_.MapPoints();
  view.points.reserve(points.size());
  for (const MapPoint* point : points) {
    if (point->observations().empty()) continue;  // not drawn, as Map::MapPoints(map) gives it to no map
    view.points.push_back({point->id(), point->observations().front().keyframe->map_id(),
                           point->position().cast<float>(), point->color()});
  }
  const std::vector<KeyFrame*> keyframes = map_.KeyFrames();
  view.keyframes.reserve(keyframes.size());
  for (const KeyFrame* keyframe : keyframes) {
    view.keyframes.push_back({keyframe->id(), keyframe->map_id(), keyframe->T_wc()});
    for (const auto& [other, weight] : keyframe->covisibles()) {
      if (weight >= AtlasView::kCovisibilityEdgeWeight && other->id() > keyframe->id() && !other->bad()) {
        view.covisibility.emplace_back(keyframe->id(), other->id());
      }
    }
    for (const KeyFrame* other : keyframe->loop_edges()) {  // Map::AddLoopEdge gives both ends the edge
      if (other->id() > keyframe->id() && !other->bad()) view.loops.emplace_back(keyframe->id(), other->id());
    }
  }
  return view;
}

std::size_t System::NumKeyFrames() const {
  const MapId main = MainMap();
  std::shared_lock lock(map_.mutex());
  return map_.NumKeyFrames(main);
}

std::vector<LoopClosure> System::LoopClosures() const {
  std::vector<LoopClosure> loops = loop_closer_.closures();
  std::erase_if(loops, [](const LoopClosure& c) { return c.merged_map.has_value(); });
  return loops;
}

std::vector<LoopClosure> System::MapMerges() const {
  std::vector<LoopClosure> merges = loop_closer_.closures();
  std::erase_if(merges, [](const LoopClosure& c) { return !c.merged_map.has_value(); });
  return merges;
}

LoopCloser::Timings System::LoopClosingTimings() const { return loop_closer_.timings(); }

}  // namespace hoidslam::slam
