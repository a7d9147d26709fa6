#pragma once
// A keyframe: a frame kept in the map, with its keypoints, its pose, the map points its keypoints see, its
// covisibility edges (keyframes that see the same points, weighted by how many) and its place in the spanning
// tree. Ownership and locking as for MapPoint (map_point.h): owned by the Map, never freed before it, read under
// Map::mutex() and changed under it held exclusively.

#include <memory>
#include <utility>
#include <vector>

#include "hoidslam/bow/bow_vector.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/slam/data/keypoints.h"
#include "hoidslam/slam/data/map_point.h"

namespace hoidslam::slam {

class KeyFrame {
 public:
  KeyFrame(KeyFrameId id, MapId map_id, std::uint64_t frame_id, double timestamp,
           std::shared_ptr<const KeypointSet> keypoints, const core::Pose& T_cw);
  KeyFrame(const KeyFrame&) = delete;
  KeyFrame& operator=(const KeyFrame&) = delete;

  KeyFrameId id() const { return id_; }
  // The map it belongs to: the one active when it was made, or the one that map was merged into.
  MapId map_id() const { return map_id_; }
  std::uint64_t frame_id() const { return frame_id_; }
  double timestamp() const { return timestamp_; }
  const KeypointSet& keypoints() const { return *keypoints_; }
  const std::shared_ptr<const KeypointSet>& shared_keypoints() const { return keypoints_; }

  const core::Pose& T_cw() const { return T_cw_; }
  const core::Pose& T_wc() const { return T_wc_; }
  Eigen::Vector3d center() const { return T_wc_.translation(); }
  void SetPose(const core::Pose& T_cw);

  // The map point of each keypoint (nullptr: none). Entries may be bad: check before use.
  const std::vector<MapPoint*>& map_points() const { return map_points_; }
  MapPoint* map_point(int i) const { return map_points_[static_cast<std::size_t>(i)]; }
  // Good map points with at least `min_observations` observations.
  int NumTrackedPoints(int min_observations) const;

  // Covisibility: keyframes sharing points, strongest first (ties by id).
  const std::vector<std::pair<KeyFrame*, int>>& covisibles() const { return covisibles_; }
  std::vector<KeyFrame*> BestCovisibles(std::size_t n) const;
  int Weight(const KeyFrame* other) const;

  KeyFrame* parent() const { return parent_; }
  const std::vector<KeyFrame*>& children() const { return children_; }
  bool bad() const { return bad_; }
  // Keyframes a closed loop joined this one to: edges of the essential graph, and never culled.
  const std::vector<KeyFrame*>& loop_edges() const { return loop_edges_; }
  // Its bag of words and direct index (bow::Vocabulary::Transform of its keypoints): empty until local mapping
  // computes them and enters the keyframe into the place-recognition database.
  const bow::ImageWords& words() const { return words_; }

  // The pose relative to the parent, kept when the keyframe is culled, so frames that referred to it can still
  // be placed (see Map::EraseKeyFrame).
  const core::Pose& T_cp() const { return T_cp_; }

 private:
  friend class Map;  // the graph operations go through the Map

  void AddCovisible(KeyFrame* other, int weight);
  void EraseCovisible(const KeyFrame* other);
  void SortCovisibles();
  void AddChild(KeyFrame* child);
  void SetWords(bow::ImageWords words) { words_ = std::move(words); }
  void AddLoopEdge(KeyFrame* other) { loop_edges_.push_back(other); }
  void EraseChild(const KeyFrame* child);

  KeyFrameId id_;
  MapId map_id_;
  std::uint64_t frame_id_;
  double timestamp_;
  std::shared_ptr<const KeypointSet> keypoints_;
  core::Pose T_cw_;
  core::Pose T_wc_;
  std::vector<MapPoint*> map_points_;
  std::vector<std::pair<KeyFrame*, int>> covisibles_;
  KeyFrame* parent_ = nullptr;
  std::vector<KeyFrame*> children_;  // sorted by id
  bool bad_ = false;
  core::Pose T_cp_ = core::Pose::Identity();
  bow::ImageWords words_;
  std::vector<KeyFrame*> loop_edges_;
};

}  // namespace hoidslam::slam
