#pragma once
// The place-recognition database: an inverted index from each vocabulary word to the keyframes whose bag of words
// holds it, so that the keyframes that look like a frame are found without comparing it with every keyframe.
// Only keypoints the exclusion filter kept ever reach a keyframe, so a place is never recognised by a person.
//
// Owned by the Map and locked with it (map.h): queried under its lock shared, changed under it exclusively.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "hoidslam/bow/bow_vector.h"
#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/slam/data/keypoints.h"
#include "hoidslam/slam/data/map_point.h"

namespace hoidslam::slam {

class KeyFrame;

// The level of the vocabulary's tree whose nodes group keypoints for guided matching (SearchByBoW in
// match/matcher.h): this many levels above the words (with the shipped k 10, L 5: the 100 nodes of level 2, as
// ORB-SLAM's 4 levels up of its L 6). Keyframes and lost frames are described with it (bow::Vocabulary::Transform).
inline constexpr int kBowMatchingLevelsUp = 3;

// The bag of words and direct index of a keyframe's or lost frame's keypoints, for place recognition and SearchByBoW.
inline bow::ImageWords DescribePlace(const bow::Vocabulary& vocabulary, const KeypointSet& keypoints) {
  return vocabulary.Transform(keypoints.descriptors(), kBowMatchingLevelsUp);
}

class KeyFrameDatabase {
 public:
  // Indexes the keyframe by the words of its bag of words (KeyFrame::words()).
  void Add(KeyFrame* keyframe);
  void Erase(const KeyFrame* keyframe);

  // ORB-SLAM's relocalisation candidates for a frame's bag of words: of the keyframes sharing a word with it,
  // those sharing at least 80 % as many words as the best are scored (bow::Score); each is credited with the
  // scores of its 10 best covisible keyframes among them, since a place is seen by several keyframes, and the best
  // of each group whose credit reaches 75 % of the best credit is returned, best credit first (ties by id), at most
  // `max_candidates` of them. Only keyframes of `map` when given, else of every map.
  std::vector<KeyFrame*> RelocalizationCandidates(const bow::BowVector& words, std::size_t max_candidates,
                                                  std::optional<MapId> map = std::nullopt) const;
  // ORB-SLAM's loop candidates for a keyframe: the same, but from the keyframes not connected to it in the
  // covisibility graph (a loop joins what tracking did not), and only those scoring at least `min_score` — the
  // score of its least similar covisible keyframe, so a candidate must look at least as much like it as its own
  // neighbours do. All groups within 75 % of the best credit are returned. Only keyframes of its own map.
  std::vector<KeyFrame*> LoopCandidates(const KeyFrame& keyframe, double min_score) const;
  // The same from the keyframes of the other maps: places where two maps can be merged.
  std::vector<KeyFrame*> MergeCandidates(const KeyFrame& keyframe, double min_score) const;

 private:
  // All of the above: only keyframes `take` accepts, and scoring at least `min_score`, take part.
  std::vector<KeyFrame*> Candidates(const bow::BowVector& words, const std::function<bool(const KeyFrame&)>& take,
                                    double min_score, std::size_t max_candidates) const;

  std::vector<std::vector<KeyFrame*>> keyframes_by_word_;
};

}  // namespace hoidslam::slam
