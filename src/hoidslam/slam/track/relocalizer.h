#pragma once
// Finding a lost frame in the map again, in small steps: the candidate keyframes (the one tracking last relied on
// and its neighbours, since most losses are short, then those that look most like the frame by their bags of
// words), each tried in order of descriptor matches — PnP RANSAC, pose optimisation, more matches by projection —
// gathering the poses of the places the frame looks like. The tracker chooses among them (the one the motion model
// allows after a short loss; none when two places fit alike), confirms it against the local map and keeps it
// provisional until the next frames agree (tracker.h). Callers hold Map::mutex(), shared at least.

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
  // Poses gathered before one is chosen: a place may look like another (the same desks, the same posters), and the
  // first candidate by descriptor matches is not always the right one. At most max_tries candidates are taken to
  // PnP.
  int max_poses = 3;
  int max_tries = 6;
  // Two poses farther apart than this, the weaker backed by at least ambiguous_share of the stronger's inliers, are
  // two places the frame looks like: with nothing else to tell them apart, neither is taken.
  double ambiguous_distance = 0.3;   // metres
  double ambiguous_angle_deg = 15.0;
  double ambiguous_share = 0.7;

  void Check() const;
};

// A pose a candidate keyframe gave: the frame with the pose and its matches, and the candidate as its reference.
struct RelocalizedPose {
  Frame frame;
  int inliers = 0;
};

class Relocalizer {
 public:
  Relocalizer(const Map& map, const RelocalizationOptions& options, const FrameTrackerOptions& tracking);

  // The keyframes to try for a frame described by `words` (DescribePlace): `reference` and its best neighbours,
  // then the bag-of-words candidates of `map` (every map when nullopt).
  std::vector<KeyFrame*> Candidates(const bow::ImageWords& words, KeyFrame* reference,
                                    std::optional<MapId> map) const;
  // The poses the candidates give, in order of descriptor matches (the best first): PnP RANSAC, pose optimisation
  // and more matches by projection for each, until max_poses poses with min_inliers are found or max_tries
  // candidates were tried. `failure` says why there is none: too few matches, or no pose held.
  std::vector<RelocalizedPose> Relocalize(const Frame& frame, const bow::ImageWords& words,
                                          const std::vector<KeyFrame*>& candidates, TrackingFailure& failure) const;
  // Whether `other` is another place the frame looks about as much like as `best`'s (RelocalizationOptions::
  // ambiguous_*).
  bool Ambiguous(const RelocalizedPose& best, const RelocalizedPose& other) const;
  // Whether two poses are of one place: within ambiguous_distance and ambiguous_angle_deg of each other.
  bool SamePlace(const RelocalizedPose& a, const RelocalizedPose& b) const;

 private:
  // The pose from one candidate's matches, or nullopt.
  std::optional<RelocalizedPose> TryCandidate(const Frame& frame, KeyFrame& candidate,
                                              std::vector<MapPoint*> matches) const;
  // Descriptor matches of the frame to each candidate: (count, index) of those with enough, most first.
  std::vector<std::pair<int, std::size_t>> RankByMatches(const Frame& frame, const bow::ImageWords& words,
                                                         const std::vector<KeyFrame*>& candidates,
                                                         std::vector<std::vector<MapPoint*>>& matches) const;

  const Map& map_;
  RelocalizationOptions options_;
  FrameTrackerOptions tracking_;
};

}  // namespace hoidslam::slam
