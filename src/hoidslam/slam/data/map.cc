#include "hoidslam/slam/data/map.h"

#include <algorithm>
#include <map>

namespace hoidslam::slam {
namespace {

// Keyframes sharing this many points are connected in the covisibility graph (ORB-SLAM's threshold).
constexpr int kMinCovisibilityWeight = 15;

// The good (not bad) entities of an arena that `keep` takes, in id order.
template <typename T, typename Keep>
std::vector<T*> Good(const std::deque<std::unique_ptr<T>>& arena, Keep keep) {
  std::vector<T*> good;
  for (const auto& entity : arena) {
    if (!entity->bad() && keep(*entity)) good.push_back(entity.get());
  }
  return good;
}

}  // namespace

KeyFrame* Map::CreateKeyFrame(std::uint64_t frame_id, double timestamp, std::shared_ptr<const KeypointSet> keypoints,
                              const core::Pose& T_cw) {
  keyframes_.push_back(
      std::make_unique<KeyFrame>(keyframes_.size(), active_map_, frame_id, timestamp, std::move(keypoints), T_cw));
  ++num_good_keyframes_;
  KeyFrame* keyframe = keyframes_.back().get();
  if (origins_[active_map_] == nullptr) origins_[active_map_] = keyframe;
  return keyframe;
}

MapPoint* Map::CreateMapPoint(const Eigen::Vector3d& position_w, KeyFrame* keyframe, int index,
                              std::optional<cv::Vec3b> color) {
  const KeypointSet& keypoints = keyframe->keypoints();
  const cv::Mat descriptor(1, 32, CV_8UC1, const_cast<std::uint8_t*>(keypoints.descriptor(index)));
  points_.push_back(
      std::make_unique<MapPoint>(points_.size(), position_w, keyframe->id(), descriptor,
                                 color.value_or(keypoints.color(index))));
  MapPoint* point = points_.back().get();
  AddObservation(point, keyframe, index);
  point->UpdateFromObservations();
  return point;
}

void Map::AddObservation(MapPoint* point, KeyFrame* keyframe, int index) {
  const int seen_at = point->IndexIn(keyframe);
  if (seen_at >= 0 && seen_at != index) return;
  MapPoint*& slot = keyframe->map_points_[static_cast<std::size_t>(index)];
  if (slot != nullptr && slot != point) slot->EraseObservation(keyframe);
  slot = point;
  point->AddObservation(keyframe, index);
}

void Map::EraseObservation(MapPoint* point, KeyFrame* keyframe) {
  const int index = point->IndexIn(keyframe);
  if (index < 0) return;
  keyframe->map_points_[static_cast<std::size_t>(index)] = nullptr;
  point->EraseObservation(keyframe);
  if (point->num_observations() <= 2) ErasePoint(point);
}

void Map::ErasePoint(MapPoint* point) {
  if (point->bad_) return;
  point->bad_ = true;
  for (const MapPoint::Observation& o : point->observations_) {
    MapPoint*& slot = o.keyframe->map_points_[static_cast<std::size_t>(o.index)];
    if (slot == point) slot = nullptr;
  }
  point->observations_.clear();
  point->num_observations_ = 0;
}

void Map::ReplacePoint(MapPoint* point, MapPoint* by) {
  if (point == by || point->bad_ || by->bad_) return;
  const std::vector<MapPoint::Observation> observations = point->observations_;
  ErasePoint(point);
  point->replaced_by_ = by;
  for (const MapPoint::Observation& o : observations) {
    if (by->IndexIn(o.keyframe) < 0) AddObservation(by, o.keyframe, o.index);
  }
  by->IncreaseVisible(point->visible_.load(std::memory_order_relaxed));
  by->IncreaseFound(point->found_.load(std::memory_order_relaxed));
  by->UpdateFromObservations();
}

void Map::UpdatePoint(MapPoint* point) {
  if (!point->bad_) point->UpdateFromObservations();
}

void Map::UpdateConnections(KeyFrame* keyframe) {
  // Shared points per other keyframe, keyed by id so the result does not depend on memory addresses.
  std::map<KeyFrameId, std::pair<KeyFrame*, int>> shared;
  for (const MapPoint* point : keyframe->map_points_) {
    if (point == nullptr || point->bad_) continue;
    for (const MapPoint::Observation& o : point->observations_) {
      if (o.keyframe == keyframe || o.keyframe->bad_) continue;
      auto& entry = shared[o.keyframe->id()];
      entry.first = o.keyframe;
      ++entry.second;
    }
  }
  std::vector<std::pair<KeyFrame*, int>> connected;
  std::pair<KeyFrame*, int> strongest{nullptr, 0};
  for (const auto& [id, entry] : shared) {
    if (entry.second > strongest.second) strongest = entry;
    if (entry.second >= kMinCovisibilityWeight) connected.push_back(entry);
  }
  if (connected.empty() && strongest.first != nullptr) connected.push_back(strongest);

  for (const auto& [other, weight] : keyframe->covisibles_) {
    const bool still = std::any_of(connected.begin(), connected.end(), [o = other](const auto& c) { return c.first == o; });
    if (!still) other->EraseCovisible(keyframe);
  }
  for (const auto& [other, weight] : connected) other->AddCovisible(keyframe, weight);
  keyframe->covisibles_ = std::move(connected);
  keyframe->SortCovisibles();

  // The parent is the strongest older neighbour. Every keyframe's descendants are younger than it (children are
  // attached to older parents, and a culled keyframe's children move within its own subtree), so an older parent
  // can never be a descendant: the tree stays a tree even for a keyframe that finds its first neighbour late.
  if (keyframe->parent_ == nullptr && !IsOrigin(keyframe)) {
    for (const auto& [other, weight] : keyframe->covisibles_) {
      if (other->id() < keyframe->id()) {
        keyframe->parent_ = other;
        other->AddChild(keyframe);
        break;
      }
    }
  }
}

void Map::EraseKeyFrame(KeyFrame* keyframe) {
  // A map's first keyframe anchors its world frame; one never connected has no parent to hand its children to; the
  // ends of a closed loop (or a merge) hold the essential graph together.
  if (keyframe->bad_ || IsOrigin(keyframe) || keyframe->parent_ == nullptr || !keyframe->loop_edges_.empty()) {
    return;
  }
  for (const auto& [other, weight] : keyframe->covisibles_) other->EraseCovisible(keyframe);
  for (MapPoint* point : keyframe->map_points_) {
    if (point != nullptr) EraseObservation(point, keyframe);
  }

  // Re-parent the children: repeatedly attach the child with the strongest edge to a candidate parent, where the
  // candidates are this keyframe's parent and the children already attached, so the tree stays connected.
  std::vector<KeyFrame*> candidates = {keyframe->parent_};
  std::vector<KeyFrame*> children = keyframe->children_;
  while (!children.empty()) {
    KeyFrame* best_child = nullptr;
    KeyFrame* best_parent = nullptr;
    int best_weight = 0;
    for (KeyFrame* child : children) {
      for (KeyFrame* candidate : candidates) {
        const int weight = child->Weight(candidate);
        if (weight > best_weight) {
          best_weight = weight;
          best_child = child;
          best_parent = candidate;
        }
      }
    }
    if (best_child == nullptr) break;
    best_child->parent_ = best_parent;
    best_parent->AddChild(best_child);
    candidates.push_back(best_child);
    std::erase(children, best_child);
  }
  for (KeyFrame* child : children) {
    child->parent_ = keyframe->parent_;
    keyframe->parent_->AddChild(child);
  }

  keyframe->parent_->EraseChild(keyframe);
  keyframe->children_.clear();
  keyframe->covisibles_.clear();
  keyframe->T_cp_ = keyframe->T_cw_ * keyframe->parent_->T_wc_;
  keyframe->bad_ = true;
  --num_good_keyframes_;
  database_.Erase(keyframe);
}

void Map::IndexKeyFrame(KeyFrame* keyframe, bow::ImageWords words) {
  keyframe->SetWords(std::move(words));
  database_.Add(keyframe);
}

std::vector<KeyFrame*> Map::KeyFrames() const {
  return Good(keyframes_, [](const KeyFrame&) { return true; });
}

std::vector<MapPoint*> Map::MapPoints() const {
  return Good(points_, [](const MapPoint&) { return true; });
}

std::vector<KeyFrame*> Map::KeyFrames(MapId map) const {
  return Good(keyframes_, [map](const KeyFrame& keyframe) { return keyframe.map_id() == map; });
}

std::vector<MapPoint*> Map::MapPoints(MapId map) const {
  // A point is seen only by keyframes of its map; a good point is seen by at least one.
  return Good(points_, [map](const MapPoint& point) {
    return !point.observations().empty() && point.observations().front().keyframe->map_id() == map;
  });
}

std::size_t Map::NumKeyFrames(MapId map) const {
  return static_cast<std::size_t>(std::count_if(keyframes_.begin(), keyframes_.end(), [map](const auto& keyframe) {
    return !keyframe->bad_ && keyframe->map_id_ == map;
  }));
}

std::vector<MapId> Map::Maps() const {
  std::vector<MapId> maps;
  for (MapId id = 0; id < origins_.size(); ++id) {
    if (origins_[id] != nullptr) maps.push_back(id);
  }
  return maps;
}

bool Map::IsOrigin(const KeyFrame* keyframe) const { return origins_[keyframe->map_id_] == keyframe; }

MapId Map::StartNewMap() {
  active_map_ = static_cast<MapId>(origins_.size());
  origins_.push_back(nullptr);
  return active_map_;
}

void Map::ActivateMap(MapId id) { active_map_ = id; }

void Map::MergeMaps(MapId from, MapId into, const core::Pose& T_into_from) {
  const core::Pose T_from_into = T_into_from.inverse();
  const std::vector<MapPoint*> moved = MapPoints(from);
  for (MapPoint* point : moved) point->SetPosition(T_into_from * point->position());
  // Culled keyframes too: they keep their pose relative to their parent, and their map is their parent's.
  for (const auto& keyframe : keyframes_) {
    if (keyframe->map_id_ != from) continue;
    keyframe->SetPose(keyframe->T_cw() * T_from_into);
    keyframe->map_id_ = into;
  }
  for (MapPoint* point : moved) UpdatePoint(point);  // its viewing directions turned
  origins_[from] = nullptr;
  if (active_map_ == from) active_map_ = into;
}

void Map::SetParent(KeyFrame* keyframe, KeyFrame* parent) {
  keyframe->parent_ = parent;
  parent->AddChild(keyframe);
}

void Map::AddLoopEdge(KeyFrame* a, KeyFrame* b) {
  a->AddLoopEdge(b);
  b->AddLoopEdge(a);
}

}  // namespace hoidslam::slam
