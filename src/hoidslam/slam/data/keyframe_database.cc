#include "hoidslam/slam/data/keyframe_database.h"

#include <algorithm>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "hoidslam/slam/data/keyframe.h"

namespace hoidslam::slam {
namespace {

constexpr double kMinSharedWordsShare = 0.8;   // of the most words a keyframe shares with the frame
constexpr std::size_t kGroupNeighbours = 10;   // covisible keyframes that add their score to a keyframe's credit
constexpr double kMinCreditShare = 0.75;       // of the best credit, for a group's best keyframe to be returned

}  // namespace

void KeyFrameDatabase::Add(KeyFrame* keyframe) {
  for (const bow::WordWeight& w : keyframe->words().bow) {
    if (w.word >= keyframes_by_word_.size()) keyframes_by_word_.resize(w.word + 1);
    keyframes_by_word_[w.word].push_back(keyframe);
  }
}

void KeyFrameDatabase::Erase(const KeyFrame* keyframe) {
  for (const bow::WordWeight& w : keyframe->words().bow) {
    if (w.word < keyframes_by_word_.size()) std::erase(keyframes_by_word_[w.word], keyframe);
  }
}

std::vector<KeyFrame*> KeyFrameDatabase::RelocalizationCandidates(const bow::BowVector& words,
                                                                  std::size_t max_candidates,
                                                                  std::optional<MapId> map) const {
  return Candidates(
      words, [map](const KeyFrame& k) { return !map || k.map_id() == *map; }, 0.0, max_candidates);
}

std::vector<KeyFrame*> KeyFrameDatabase::LoopCandidates(const KeyFrame& keyframe, double min_score) const {
  std::unordered_set<const KeyFrame*> connected = {&keyframe};
  for (const auto& [neighbour, weight] : keyframe.covisibles()) connected.insert(neighbour);
  return Candidates(
      keyframe.words().bow,
      [&](const KeyFrame& k) { return k.map_id() == keyframe.map_id() && !connected.contains(&k); }, min_score,
      std::numeric_limits<std::size_t>::max());
}

std::vector<KeyFrame*> KeyFrameDatabase::MergeCandidates(const KeyFrame& keyframe, double min_score) const {
  return Candidates(
      keyframe.words().bow, [&](const KeyFrame& k) { return k.map_id() != keyframe.map_id(); }, min_score,
      std::numeric_limits<std::size_t>::max());
}

std::vector<KeyFrame*> KeyFrameDatabase::Candidates(const bow::BowVector& words,
                                                    const std::function<bool(const KeyFrame&)>& take,
                                                    double min_score, std::size_t max_candidates) const {
  std::unordered_map<KeyFrame*, int> shared;
  for (const bow::WordWeight& w : words) {
    if (w.word >= keyframes_by_word_.size()) continue;
    for (KeyFrame* keyframe : keyframes_by_word_[w.word]) {
      if (!keyframe->bad() && take(*keyframe)) ++shared[keyframe];
    }
  }
  int most_shared = 0;
  for (const auto& [keyframe, count] : shared) most_shared = std::max(most_shared, count);
  const double min_shared = kMinSharedWordsShare * most_shared;

  std::unordered_map<KeyFrame*, double> scores;
  for (const auto& [keyframe, count] : shared) {
    if (count < min_shared) continue;
    const double score = bow::Score(words, keyframe->words().bow);
    if (score >= min_score) scores[keyframe] = score;
  }
  struct Group {
    double credit = 0.0;
    KeyFrame* best = nullptr;
  };
  std::vector<Group> groups;
  double best_credit = 0.0;
  for (const auto& [keyframe, score] : scores) {
    Group group{score, keyframe};
    double best_score = score;
    for (KeyFrame* neighbour : keyframe->BestCovisibles(kGroupNeighbours)) {
      const auto score = scores.find(neighbour);
      if (score == scores.end()) continue;
      group.credit += score->second;
      if (score->second > best_score) {
        best_score = score->second;
        group.best = neighbour;
      }
    }
    best_credit = std::max(best_credit, group.credit);
    groups.push_back(group);
  }
  // Best credit first; the unordered maps' order must not decide: ties by keyframe id.
  std::sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) {
    return a.credit != b.credit ? a.credit > b.credit : a.best->id() < b.best->id();
  });
  std::vector<KeyFrame*> candidates;
  for (const Group& group : groups) {
    if (group.credit < kMinCreditShare * best_credit || candidates.size() >= max_candidates) break;
    if (std::find(candidates.begin(), candidates.end(), group.best) == candidates.end()) {
      candidates.push_back(group.best);
    }
  }
  return candidates;
}

}  // namespace hoidslam::slam
