#pragma once
// Finding a lost frame in the map again, in small steps: the candidate keyframes (the one tracking last relied on
// and its neighbours, since most losses are short, then those that look most like the frame by their bags of
// words), each tried in order of descriptor matches — PnP RANSAC, pose optimisation, more matches by projection —
// and the first pose with enough inliers taken as the first estimate. The tracker confirms it against the local
// map and keeps it provisional until the next frames agree (tracker.h). Callers hold Map::mutex(), shared at least.

#include <functional>
#include <optional>
#include <vector>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/slam/data/frame.h"
#include "hoidslam/slam/data/keyframe.h"
#include "hoidslam/slam/data/map.h"
#include "hoidslam/slam/track/frame_tracker.h"

namespace hoidslam::slam {

struct RelocalizationOptions {
  int candidates = 10;                // keyframes tried from the bag-of-words search, besides the last reference's
  int reference_neighbours = 10;      // neighbours of the last reference keyframe tried first
  float descriptor_ratio = 0.75F;     // ratio test of the descriptor matches to a candidate
  double projection_radius = 4.0;     // pixels: the candidate's points searched for around the estimate
  // Inliers a candidate's pose needs after the search by projection; fewer than min_first_estimate_inliers
  // (FrameTrackerOptions) after PnP or its optimisation and the candidate is passed over at once.
  int min_inliers = 50;

  void Check() const;
};

class Relocalizer {
 public:
  Relocalizer(const Map& map, const RelocalizationOptions& options, const FrameTrackerOptions& tracking);

  // The keyframes to try for a frame described by `words` (DescribePlace): `reference` and its best neighbours,
  // then the bag-of-words candidates of `map` (every map when nullopt).
  std::vector<KeyFrame*> Candidates(const bow::ImageWords& words, KeyFrame* reference,
                                    std::optional<MapId> map) const;
  // The first estimate from the first candidate, by descriptor matches, whose pose gathers min_inliers and that
  // `plausible` (if given) accepts: its frame has the pose and matches, and the candidate as reference keyframe. The
  // frame itself is not changed.
  PoseHypothesis Relocalize(const Frame& frame, const bow::ImageWords& words,
                            const std::vector<KeyFrame*>& candidates,
                            const std::function<bool(const Frame&)>& plausible) const;

 private:
  // The pose from one candidate's matches, or nullopt.
  std::optional<Frame> TryCandidate(const Frame& frame, KeyFrame& candidate, std::vector<MapPoint*> matches) const;
  // Descriptor matches of the frame to each candidate: (count, index) of those with enough, most first.
  std::vector<std::pair<int, std::size_t>> RankByMatches(const Frame& frame, const bow::ImageWords& words,
                                                         const std::vector<KeyFrame*>& candidates,
                                                         std::vector<std::vector<MapPoint*>>& matches) const;

  const Map& map_;
  RelocalizationOptions options_;
  FrameTrackerOptions tracking_;
};

}  // namespace hoidslam::slam
