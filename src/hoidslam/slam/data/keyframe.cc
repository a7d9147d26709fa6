#include "hoidslam/slam/data/keyframe.h"

#include <algorithm>

namespace hoidslam::slam {

KeyFrame::KeyFrame(KeyFrameId id, MapId map_id, std::uint64_t frame_id, double timestamp,
                   std::shared_ptr<const KeypointSet> keypoints, const core::Pose& T_cw)
    : id_(id), map_id_(map_id), frame_id_(frame_id), timestamp_(timestamp), keypoints_(std::move(keypoints)),
      map_points_(static_cast<std::size_t>(keypoints_->size()), nullptr) {
  SetPose(T_cw);
}

void KeyFrame::SetPose(const core::Pose& T_cw) {
  T_cw_ = T_cw;
  T_wc_ = T_cw.inverse();
}

int KeyFrame::NumTrackedPoints(int min_observations) const {
  int n = 0;
  for (const MapPoint* p : map_points_) {
    if (p != nullptr && !p->bad() && p->num_observations() >= min_observations) ++n;
  }
  return n;
}

std::vector<KeyFrame*> KeyFrame::BestCovisibles(std::size_t n) const {
  std::vector<KeyFrame*> best;
  best.reserve(std::min(n, covisibles_.size()));
  for (std::size_t i = 0; i < covisibles_.size() && best.size() < n; ++i) best.push_back(covisibles_[i].first);
  return best;
}

int KeyFrame::Weight(const KeyFrame* other) const {
  for (const auto& [keyframe, weight] : covisibles_) {
    if (keyframe == other) return weight;
  }
  return 0;
}

void KeyFrame::AddCovisible(KeyFrame* other, int weight) {
  for (auto& entry : covisibles_) {
    if (entry.first == other) {
      entry.second = weight;
      SortCovisibles();
      return;
    }
  }
  covisibles_.emplace_back(other, weight);
  SortCovisibles();
}

void KeyFrame::EraseCovisible(const KeyFrame* other) {
  std::erase_if(covisibles_, [other](const auto& entry) { return entry.first == other; });
}

void KeyFrame::SortCovisibles() {
  std::sort(covisibles_.begin(), covisibles_.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second : a.first->id() < b.first->id();
  });
}

void KeyFrame::AddChild(KeyFrame* child) {
  const auto at = std::lower_bound(children_.begin(), children_.end(), child,
                                   [](const KeyFrame* a, const KeyFrame* b) { return a->id() < b->id(); });
  if (at == children_.end() || *at != child) children_.insert(at, child);
}

void KeyFrame::EraseChild(const KeyFrame* child) { std::erase(children_, child); }

}  // namespace hoidslam::slam
