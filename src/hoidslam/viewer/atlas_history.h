#pragma once
// The map as the pages were told of it: every point and keyframe by id with the revision it last changed in, so
// that a page that has revision r gets only what changed since (added, moved, recoloured, removed), never the whole
// map again. Changes are found by comparing values, so a point moved by a loop closing is sent again however small
// the move. Not thread-safe: the viewer holds it under its own lock.

#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "hoidslam/slam/system.h"

namespace hoidslam::viewer {

class AtlasHistory {
 public:
  // How many revisions of removals are remembered: a page further behind gets the whole map (a `full` message).
  static constexpr std::uint64_t kRemembered = 64;

  // Takes the atlas as it stands; `main_map` is the map the run's outputs write. Returns whether anything changed
  // (then the revision went up by one).
  bool Update(const slam::AtlasView& atlas, slam::MapId main_map);
  std::uint64_t revision() const { return revision_; }

  // The page's `map` event for a page that has everything up to revision `since` (0: nothing yet).
  std::string EventJsonSince(std::uint64_t since) const;

 private:
  struct Point {
    slam::AtlasView::Point value;
    std::uint64_t revision = 0;
  };
  struct KeyFrame {
    slam::AtlasView::KeyFrameView value;
    std::uint64_t revision = 0;
  };
  using Edges = std::vector<std::pair<slam::KeyFrameId, slam::KeyFrameId>>;

  std::uint64_t revision_ = 0;
  slam::MapId main_map_ = 0;
  std::uint64_t main_map_revision_ = 0;
  std::unordered_map<slam::MapPointId, Point> points_;
  std::unordered_map<slam::KeyFrameId, KeyFrame> keyframes_;
  // Removals by revision, oldest first, of the last kRemembered revisions.
  std::vector<std::pair<std::uint64_t, slam::MapPointId>> removed_points_;
  std::vector<std::pair<std::uint64_t, slam::KeyFrameId>> removed_keyframes_;
  std::uint64_t forgotten_ = 0;  // removals of revisions up to this one are no longer remembered
  Edges covisibility_, loops_;
  std::uint64_t covisibility_revision_ = 0, loops_revision_ = 0;
};

}  // namespace hoidslam::viewer
