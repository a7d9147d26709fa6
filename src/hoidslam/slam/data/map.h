#pragma once
// The map: keyframes and map points, and every operation that changes the graph between them.
//
// It is an Atlas (ORB-SLAM3): several maps, one active. Each keyframe belongs to one map (KeyFrame::map_id), and
// maps share no point and no covisibility edge, so each has a world frame of its own. Tracking lost for long in new
// ground starts a new map; loop closing merges two maps when one recognises a place of the other. New keyframes
// join the active map.
//
// Ownership: the Map owns all keyframes and map points (unique_ptr arenas) and frees none before it is
// destroyed. Culling and fusion mark entities bad instead of freeing them, so the plain pointers that frames,
// keyframes and the two threads hold are never dangling. Ids come from counters owned by the Map, so a run's
// ids — and every order derived from them — are the same on every run.
//
// Locking: one reader-writer lock, mutex(). Tracking holds it shared while it reads the map for a frame;
// local mapping holds it exclusively while it changes the graph. Bundle adjustment copies its problem out under
// a shared lock, optimises with no lock held, and writes back under an exclusive one. The member functions
// below do not lock: the caller holds the lock, as each function's comment says.

#include <deque>
#include <memory>
#include <optional>
#include <shared_mutex>
#include <vector>

#include "hoidslam/slam/data/keyframe.h"
#include "hoidslam/slam/data/keyframe_database.h"
#include "hoidslam/slam/data/map_point.h"

namespace hoidslam::slam {

class Map {
 public:
  Map() = default;
  Map(const Map&) = delete;
  Map& operator=(const Map&) = delete;

  std::shared_mutex& mutex() const { return mutex_; }

  // --- Exclusive lock held ---
  KeyFrame* CreateKeyFrame(std::uint64_t frame_id, double timestamp, std::shared_ptr<const KeypointSet> keypoints,
                           const core::Pose& T_cw);
  // A new point first seen by keypoint `index` of `keyframe` (and observed by it), of that keypoint's colour unless
  // `color` says otherwise (a loaded point keeps the colour of the keyframe that made it, which may be gone).
  MapPoint* CreateMapPoint(const Eigen::Vector3d& position_w, KeyFrame* keyframe, int index,
                           std::optional<cv::Vec3b> color = std::nullopt);
  // Adds the observation point ↔ keypoint `index` of `keyframe` (replacing what that keypoint saw before). Does
  // nothing when the keyframe already sees the point at another keypoint: one point, one keypoint per keyframe.
  void AddObservation(MapPoint* point, KeyFrame* keyframe, int index);
  // Removes the observation of `point` by `keyframe`; a point left with 2 or fewer observations (counted as in
  // MapPoint::num_observations, so one observation with depth) is erased.
  void EraseObservation(MapPoint* point, KeyFrame* keyframe);
  // Marks the point bad and removes it from every keyframe that saw it.
  void ErasePoint(MapPoint* point);
  // Fuses `point` into `by`: its observations move to `by` (unless the keyframe already sees `by`), and `point`
  // is marked bad with by as its replacement.
  void ReplacePoint(MapPoint* point, MapPoint* by);
  // Recomputes a point's normal, distance range and descriptor from its observations.
  void UpdatePoint(MapPoint* point);
  // Recomputes the keyframe's covisibility edges (in both directions) from shared points; sets its spanning-tree
  // parent to the strongest older covisible keyframe the first time it has one.
  void UpdateConnections(KeyFrame* keyframe);
  // Culls a keyframe: its observations and edges are removed, its children are re-parented to their strongest
  // covisible keyframe among the candidates (its parent and the children already re-parented), and it keeps its
  // pose relative to its parent. A map's first keyframe and the ends of a closed loop are never erased.
  void EraseKeyFrame(KeyFrame* keyframe);
  // Makes `parent` the keyframe's spanning-tree parent (a loaded map's tree, before UpdateConnections would choose
  // one); the keyframe must have none yet.
  void SetParent(KeyFrame* keyframe, KeyFrame* parent);
  // Joins the two ends of a closed loop (KeyFrame::loop_edges).
  void AddLoopEdge(KeyFrame* a, KeyFrame* b);
  // Gives the keyframe its bag of words and enters it into the place-recognition database.
  void IndexKeyFrame(KeyFrame* keyframe, bow::ImageWords words);
  // Opens a new, empty map and makes it the active one; returns its id.
  MapId StartNewMap();
  // Makes map `id` (one with keyframes) the active one. An empty active map is forgotten.
  void ActivateMap(MapId id);
  // Moves map `from` into map `into`: its keyframes and points are carried by T_into_from (from's world into
  // into's), and its keyframes belong to `into` from then on. `into` becomes active if `from` was.
  void MergeMaps(MapId from, MapId into, const core::Pose& T_into_from);

  // --- Shared lock held ---
  const KeyFrameDatabase& database() const { return database_; }
  // Good keyframes / points, by id.
  std::vector<KeyFrame*> KeyFrames() const;
  std::vector<MapPoint*> MapPoints() const;
  std::size_t NumKeyFrames() const { return num_good_keyframes_; }
  // The point of this id, good or bad (a bad one may have been fused into another: MapPoint::Current).
  MapPoint* Point(MapPointId id) const { return points_.at(id).get(); }
  // The same for one map.
  std::vector<KeyFrame*> KeyFrames(MapId map) const;
  std::vector<MapPoint*> MapPoints(MapId map) const;
  std::size_t NumKeyFrames(MapId map) const;
  MapId active_map() const { return active_map_; }
  // The maps that have keyframes, by id.
  std::vector<MapId> Maps() const;
  // Whether the keyframe is the first of its map: it anchors that map's world frame, never moves in an
  // optimisation and is never culled. (A map merged into another keeps the other's.)
  bool IsOrigin(const KeyFrame* keyframe) const;

 private:
  mutable std::shared_mutex mutex_;
  std::deque<std::unique_ptr<KeyFrame>> keyframes_;  // every keyframe ever created, by id
  std::deque<std::unique_ptr<MapPoint>> points_;     // every point ever created, by id
  std::size_t num_good_keyframes_ = 0;
  MapId active_map_ = 0;
  std::vector<KeyFrame*> origins_ = {nullptr};  // per map id: its first keyframe (nullptr: none, or merged away)
  KeyFrameDatabase database_;
};

}  // namespace hoidslam::slam
