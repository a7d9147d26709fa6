#include "hoidslam/viewer/atlas_history.h"

#include <algorithm>
#include <map>

#include <nlohmann/json.hpp>

#include "hoidslam/report/page_json.h"

namespace hoidslam::viewer {
namespace {

bool operator==(const slam::AtlasView::Point& a, const slam::AtlasView::Point& b) {
  return a.map == b.map && a.position == b.position && a.color == b.color;
}

bool operator==(const slam::AtlasView::KeyFrameView& a, const slam::AtlasView::KeyFrameView& b) {
  return a.map == b.map && a.T_wc.matrix() == b.T_wc.matrix();
}

// Puts the entries of `view` into `held` (id → entry with its revision): new or changed ones get `revision`, those
// no longer in the view are removed and listed in `removed`. Returns whether anything changed.
template <typename Entry, typename Value, typename Id>
bool Merge(const std::vector<Value>& view, std::uint64_t revision, std::unordered_map<Id, Entry>& held,
           std::vector<std::pair<std::uint64_t, Id>>& removed) {
  bool changed = false;
  std::unordered_map<Id, Entry> next;
  next.reserve(view.size());
  for (const Value& value : view) {
    const auto it = held.find(value.id);
    if (it != held.end() && it->second.value == value) {
      next.emplace(value.id, it->second);
    } else {
      next.emplace(value.id, Entry{value, revision});
      changed = true;
    }
  }
  for (const auto& [id, entry] : held) {
    if (!next.contains(id)) {
      removed.emplace_back(revision, id);
      changed = true;
    }
  }
  held = std::move(next);
  return changed;
}

template <typename Id>
void Forget(std::vector<std::pair<std::uint64_t, Id>>& removed, std::uint64_t up_to) {
  std::erase_if(removed, [up_to](const auto& r) { return r.first <= up_to; });
}

template <typename Id>
nlohmann::json RemovedSince(const std::vector<std::pair<std::uint64_t, Id>>& removed, std::uint64_t since) {
  nlohmann::json ids = nlohmann::json::array();
  for (const auto& [revision, id] : removed) {
    if (revision > since) ids.push_back(id);
  }
  return ids;
}

nlohmann::json EdgesJson(const std::vector<std::pair<slam::KeyFrameId, slam::KeyFrameId>>& edges) {
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& [a, b] : edges) pairs.push_back({a, b});
  return pairs;
}

}  // namespace

bool AtlasHistory::Update(const slam::AtlasView& atlas, slam::MapId main_map) {
  const std::uint64_t next = revision_ + 1;
  bool changed = Merge(atlas.points, next, points_, removed_points_);
  changed = Merge(atlas.keyframes, next, keyframes_, removed_keyframes_) || changed;
  if (atlas.covisibility != covisibility_) {
    covisibility_ = atlas.covisibility;
    covisibility_revision_ = next;
    changed = true;
  }
  if (atlas.loops != loops_) {
    loops_ = atlas.loops;
    loops_revision_ = next;
    changed = true;
  }
  if (main_map != main_map_) {
    main_map_ = main_map;
    changed = true;
  }
  if (!changed) return false;
  revision_ = next;
  if (revision_ > kRemembered) {
    forgotten_ = revision_ - kRemembered;
    Forget(removed_points_, forgotten_);
    Forget(removed_keyframes_, forgotten_);
  }
  return true;
}

std::string AtlasHistory::EventJsonSince(std::uint64_t since) const {
  const bool full = since == 0 || since < forgotten_ || since > revision_;
  if (full) since = 0;
  report::PointsJson points;
  std::map<slam::MapId, std::pair<std::size_t, std::size_t>> counts;  // map → points, keyframes
  for (const auto& [id, point] : points_) {
    ++counts[point.value.map].first;
    if (point.revision <= since) continue;
    points.Add(id, point.value.map, point.value.position.cast<double>(), point.value.color);
  }
  nlohmann::json keyframes = nlohmann::json::array();
  for (const auto& [id, keyframe] : keyframes_) {
    ++counts[keyframe.value.map].second;
    if (keyframe.revision <= since) continue;
    keyframes.push_back(report::KeyframeJson(id, keyframe.value.map, keyframe.value.T_wc));
  }
  nlohmann::json maps = nlohmann::json::array();
  for (const auto& [map, count] : counts) {
    maps.push_back(report::MapCountsJson(map, count.first, count.second));
  }
  nlohmann::json event = {{"revision", revision_},
                          {"full", full},
                          {"main_map", main_map_},
                          {"maps", std::move(maps)},
                          {"points", std::move(points).ToJson()},
                          {"removed_points", full ? nlohmann::json::array() : RemovedSince(removed_points_, since)},
                          {"keyframes", std::move(keyframes)},
                          {"removed_keyframes",
                           full ? nlohmann::json::array() : RemovedSince(removed_keyframes_, since)}};
  // The edge lists whole when they changed (a page that gets the whole map gets them always).
  if (full || covisibility_revision_ > since) event["covisibility"] = EdgesJson(covisibility_);
  if (full || loops_revision_ > since) event["loops"] = EdgesJson(loops_);
  return event.dump();
}

}  // namespace hoidslam::viewer
