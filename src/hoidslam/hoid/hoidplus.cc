#include "hoidslam/hoid/hoidplus.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>

namespace hoidslam::hoid {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
const cv::Mat kNoDepth;  // depth refinement off: no foreground is looked for
// A missed box is carried by its dropped keypoints when it has this many (a median needs a few), else by all
// keypoints inside it.
constexpr std::size_t kMinCarryKeypoints = 5;

float IoU(const cv::Rect2f& a, const cv::Rect2f& b) {
  const float w = std::min(a.x + a.width, b.x + b.width) - std::max(a.x, b.x);
  const float h = std::min(a.y + a.height, b.y + b.height) - std::max(a.y, b.y);
  if (!(w > 0.0F) || !(h > 0.0F)) return 0.0F;
  const float overlap = w * h;
  return overlap / (a.area() + b.area() - overlap);
}

// The longest side, in metres, of anything of a class a person handles, with room for a box that also takes in the
// hands: a box larger than that at the object's depth is a false detection (a desk called a laptop). Nullopt for a
// class hoidslam knows no size of (a user's own).
std::optional<double> LargestHandled(std::string_view label) {
  constexpr std::array<std::pair<std::string_view, double>, 8> kLargest = {{
      {"cup", 0.3}, {"mouse", 0.25}, {"bottle", 0.5}, {"book", 0.6},
      {"laptop", 0.6}, {"keyboard", 0.7}, {"chair", 1.4}, {"tv", 1.6},
  }};
  for (const auto& [name, size] : kLargest) {
    if (name == label) return size;
  }
  return std::nullopt;
}

bool IsInteraction(Reason reason) {
  return reason == Reason::kInteraction || reason == Reason::kDepthConfirmed || reason == Reason::kDepthUnavailable;
}

}  // namespace

void HoidPlusFilter::Track::Vote(const std::string& vote) {
  auto it = std::find_if(label_votes.begin(), label_votes.end(), [&](const auto& v) { return v.first == vote; });
  if (it == label_votes.end()) {
    label_votes.emplace_back(vote, 1);
  } else {
    ++it->second;
  }
  int best = 0;
  for (const auto& [name, count] : label_votes) {
    if (count > best) {
      best = count;
      label = name;
    }
  }
}

HoidPlusFilter::HoidPlusFilter(const core::HoidOptions& options, const core::CameraIntrinsics& camera)
    : options_(options), camera_(camera) {
  options_.Check();
  options_.mode = core::FilterMode::kHoidPlus;
}

HoidPlusFilter::Track* HoidPlusFilter::FindTrack(std::uint64_t id) {
  const auto it = std::find_if(tracks_.begin(), tracks_.end(), [&](const Track& t) { return t.id == id; });
  return it == tracks_.end() ? nullptr : &*it;
}

void HoidPlusFilter::Filter(double timestamp, const cv::Mat& depth, std::span<const core::Detection> detections,
                            std::span<const cv::KeyPoint> keypoints, const cv::Mat& descriptors, JudgedBoxes& boxes,
                            std::vector<std::uint8_t>& keep) {
  CheckDepthImage(depth, "HoidPlusFilter");
  if (!descriptors.empty() && descriptors.rows != static_cast<int>(keypoints.size())) {
    throw std::invalid_argument("HoidPlusFilter: " + std::to_string(descriptors.rows) + " descriptors for " +
                                std::to_string(keypoints.size()) + " keypoints");
  }
  const core::HoidPlusOptions& plus = options_.plus;
  boxes.detections.clear();
  boxes.context.clear();
  if (plus.memory) {
    Associate(timestamp, detections, keypoints, descriptors, boxes);
  } else {
    boxes.detections.assign(detections.begin(), detections.end());
    boxes.context.assign(detections.size(), BoxContext{});
  }
  ClassifyDetections(boxes.detections, options_, {}, boxes.decisions);  // the 2D rule
  const bool use_depth = plus.depth && !depth.empty();
  const cv::Mat& refining_depth = use_depth ? depth : kNoDepth;
  if (use_depth) ConfirmByDepth(depth, boxes);
  if (plus.memory) ApplyMemory(timestamp, depth, refining_depth, boxes);

  std::vector<ExclusionRegion> regions;
  for (std::size_t i = 0; i < boxes.detections.size(); ++i) {
    if (!boxes.decisions[i].dynamic) continue;
    BoxContext& context = boxes.context[i];
    const cv::Rect2f& box = boxes.detections[i].box;
    if (const std::optional<DepthCluster>& foreground = Foreground(refining_depth, boxes, i)) {
      context.region = {.box = GrowBox(box, plus.box_margin), .cut = foreground->cut, .edge_margin = plus.edge_margin};
    } else {
      context.region = {.box = box, .cut = kInf, .edge_margin = 0};
    }
    regions.push_back(context.region);
  }
  MarkKeypointsBehindForeground(keypoints, refining_depth, regions, keep);

  last_points_.resize(keypoints.size());
  for (std::size_t i = 0; i < keypoints.size(); ++i) last_points_[i] = keypoints[i].pt;
  descriptors.copyTo(last_descriptors_);
  last_keep_ = keep;
  last_timestamp_ = timestamp;
  has_last_frame_ = true;
}

void HoidPlusFilter::Associate(double timestamp, std::span<const core::Detection> detections,
                               std::span<const cv::KeyPoint> keypoints, const cv::Mat& descriptors,
                               JudgedBoxes& boxes) {
  const core::HoidPlusOptions& plus = options_.plus;
  for (Track& track : tracks_) track.pending_position.reset();

  // Greedy association, best overlap first: the same label from association_iou on, another label (a confused
  // class) from relabel_iou on, and only for a confirmed track.
  struct Pair {
    float iou;
    std::size_t track, detection;
  };
  std::vector<Pair> pairs;
  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    for (std::size_t d = 0; d < detections.size(); ++d) {
      const float iou = IoU(tracks_[t].box, detections[d].box);
      const bool same = detections[d].label == tracks_[t].label;
      const double needed = same ? plus.association_iou : (tracks_[t].hits >= 2 ? plus.relabel_iou : 2.0);
      if (iou >= needed) pairs.push_back({iou, t, d});
    }
  }
  std::stable_sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.iou > b.iou; });
  std::vector<int> track_of(detections.size(), -1);
  std::vector<bool> track_taken(tracks_.size(), false);
  for (const Pair& p : pairs) {
    if (track_taken[p.track] || track_of[p.detection] >= 0) continue;
    track_taken[p.track] = true;
    track_of[p.detection] = static_cast<int>(p.track);
  }

  const std::size_t old_tracks = tracks_.size();
  for (std::size_t d = 0; d < detections.size(); ++d) {
    const core::Detection& detection = detections[d];
    if (track_of[d] < 0) {
      Track track;
      track.id = next_track_id_++;
      track.box = detection.box;
      track.last_detected = track.last_updated = timestamp;
      track_of[d] = static_cast<int>(tracks_.size());
      tracks_.push_back(std::move(track));
    } else {
      Track& track = tracks_[static_cast<std::size_t>(track_of[d])];
      const double dt = timestamp - track.last_updated;
      if (dt > 0.0) {
        const cv::Point2f shift = BoxCentre(detection.box) - BoxCentre(track.box);
        track.velocity = 0.5F * track.velocity + 0.5F * shift * static_cast<float>(1.0 / dt);
      }
      track.box = detection.box;
      track.last_detected = track.last_updated = timestamp;
      track.missed_frames = 0;
    }
    Track& track = tracks_[static_cast<std::size_t>(track_of[d])];
    track.Vote(detection.label);
    ++track.hits;
    core::Detection judged = detection;
    judged.label = track.label;
    boxes.detections.push_back(std::move(judged));
    boxes.context.push_back(BoxContext{.track = track.id, .missed_frames = 0, .carry = Carry::kNone, .foreground = std::nullopt, .region = {}});
  }

  // Tracks the detector missed: confirmed ones are carried and still judged, until max_missed_seconds.
  for (std::size_t t = 0; t < old_tracks; ++t) {
    if (track_taken[t]) continue;
    Track& track = tracks_[t];
    if (timestamp - track.last_detected > plus.max_missed_seconds) continue;  // erased below
    ++track.missed_frames;
    if (track.hits < 2) continue;  // a single sighting may be a false positive: not carried
    const auto [box, carry] = CarryBox(track, timestamp - track.last_updated, keypoints, descriptors);
    track.box = box;
    track.last_updated = timestamp;
    core::Detection carried;
    carried.label = track.label;
    carried.box = box;
    boxes.detections.push_back(std::move(carried));
    boxes.context.push_back(BoxContext{.track = track.id, .missed_frames = track.missed_frames, .carry = carry, .foreground = std::nullopt, .region = {}});
  }
  std::erase_if(tracks_, [&](const Track& track) { return timestamp - track.last_detected > plus.max_missed_seconds; });
}

std::pair<cv::Rect2f, Carry> HoidPlusFilter::CarryBox(const Track& track, double dt,
                                                      std::span<const cv::KeyPoint> keypoints,
                                                      const cv::Mat& descriptors) const {
  if (has_last_frame_) {
    // The track's own keypoints of the last frame: the dropped ones inside its box, or all inside when few dropped.
    std::vector<std::size_t> previous;
    for (const bool dropped_only : {true, false}) {
      previous.clear();
      for (std::size_t i = 0; i < last_points_.size() && previous.size() < kMaxMotionKeypoints; ++i) {
        if (track.box.contains(last_points_[i]) && (!dropped_only || last_keep_[i] == 0)) previous.push_back(i);
      }
      if (previous.size() >= kMinCarryKeypoints) break;
    }
    if (const std::optional<cv::Point2f> motion = MedianKeypointMotion(
            last_points_, last_descriptors_, previous, keypoints, descriptors, GrowBox(track.box, 0.5))) {
      return {track.box + *motion, Carry::kKeypoints};
    }
  }
  cv::Rect2f moved = track.box;
  moved.x += track.velocity.x * static_cast<float>(dt);
  moved.y += track.velocity.y * static_cast<float>(dt);
  return {moved, Carry::kVelocity};
}

const std::optional<DepthCluster>& HoidPlusFilter::Foreground(const cv::Mat& depth, JudgedBoxes& boxes,
                                                              std::size_t i) const {
  std::optional<DepthCluster>& foreground = boxes.context[i].foreground;
  if (!foreground && !depth.empty()) foreground = ForegroundDepth(depth, boxes.detections[i].box, options_.plus);
  return foreground;
}

void HoidPlusFilter::ConfirmByDepth(const cv::Mat& depth, JudgedBoxes& boxes) const {
  for (std::size_t i = 0; i < boxes.detections.size(); ++i) {
    Decision& decision = boxes.decisions[i];
    if (decision.reason != Reason::kInteraction) continue;
    const auto person = static_cast<std::size_t>(decision.person_index);
    const std::optional<DepthCluster>& object_depth = Foreground(depth, boxes, i);
    const std::optional<DepthCluster>& person_depth = Foreground(depth, boxes, person);
    if (!object_depth || !person_depth) {
      decision.reason = Reason::kDepthUnavailable;  // the 2D verdict stands: dynamic
      continue;
    }
    const cv::Rect2f& box = boxes.detections[i].box;
    decision.depth = object_depth->median;
    decision.extent =
        std::max(box.width / static_cast<float>(camera_.fx), box.height / static_cast<float>(camera_.fy)) *
        object_depth->median;
    const std::optional<double> largest = LargestHandled(boxes.detections[i].label);
    if (options_.plus.size_check && largest && decision.extent > *largest) {
      decision.reason = Reason::kTooLargeToHandle;
      decision.dynamic = false;
      continue;
    }
    // A held object lies within the person's reach: from an arm's length (depth_extent) in front of their nearest
    // part to where their own extent ends behind them, give or take depth_threshold.
    const auto threshold = static_cast<float>(options_.depth_threshold);
    const auto reach = static_cast<float>(options_.plus.depth_extent);
    const bool apart = object_depth->median < person_depth->near - reach - threshold ||
                       object_depth->median > person_depth->cut + threshold;
    decision.person_depth = person_depth->median;
    decision.depth_difference = std::abs(decision.depth - decision.person_depth);
    decision.reason = apart ? Reason::kDepthRejected : Reason::kDepthConfirmed;
    decision.dynamic = !apart;
  }
}

void HoidPlusFilter::ApplyMemory(double timestamp, const cv::Mat& depth, const cv::Mat& refining_depth,
                                 JudgedBoxes& boxes) {
  for (std::size_t i = 0; i < boxes.detections.size(); ++i) {
    BoxContext& context = boxes.context[i];
    Track* track = FindTrack(context.track);
    if (track == nullptr) continue;
    Decision& decision = boxes.decisions[i];
    const bool missed = context.missed_frames > 0;
    if (decision.reason == Reason::kPerson) {
      if (missed) decision.reason = Reason::kCarried;
      continue;
    }
    if (!options_.IsPotentiallyDynamic(boxes.detections[i].label)) continue;
    // A handled object stays dynamic until memory has seen it still: its place after the handling, measured in the
    // world, agrees with where it stood for still_seconds before (a chair a person walked past is released at
    // once, a cup carried away only after standing still for still_seconds where it was put down).
    const bool handled_now = decision.dynamic && IsInteraction(decision.reason);
    if (decision.reason == Reason::kTooLargeToHandle) {
      // No person handles it: whatever memory thought, it is not a handled object.
      track->handled = false;
    } else if (handled_now) {
      track->handled = true;
      track->last_handled = timestamp;
    } else if (track->handled) {
      track->handled = !SeenStill(*track, timestamp);
      decision.dynamic = track->handled;
      decision.reason = track->handled ? Reason::kRecentlyHandled : Reason::kSeenStill;
    }
    if (missed) {
      if (decision.dynamic) decision.reason = Reason::kCarried;
      continue;
    }
    // Where the object stands, once the frame's pose is known; not while a person holds or hides it, when its box
    // shows the person as much as the object.
    if (handled_now) continue;
    const cv::Point2f centre = BoxCentre(boxes.detections[i].box);
    const std::optional<DepthCluster>& foreground = Foreground(refining_depth, boxes, i);
    const float z = foreground ? foreground->median : SampleDepth(depth, centre, options_.sample_box_size);
    if (z > 0.0F && std::isfinite(z)) track->pending_position = camera_.Unproject(centre.x, centre.y, z);
  }
}

bool HoidPlusFilter::SeenStill(const Track& track, double timestamp) const {
  // A place measured since the handling, and places covering the whole stillness window.
  if (track.positions.empty() || track.positions.back().first <= track.last_handled ||
      track.positions.front().first > timestamp - options_.plus.still_seconds) {
    return false;
  }
  const Eigen::Vector3d& latest = track.positions.back().second;
  return std::all_of(track.positions.begin(), track.positions.end(), [&](const auto& p) {
    return (p.second - latest).norm() <= options_.plus.still_distance;
  });
}

void HoidPlusFilter::Localize(const std::optional<core::Pose>& T_cw) {
  for (Track& track : tracks_) {
    if (!track.pending_position) continue;
    if (T_cw) {
      track.positions.emplace_back(last_timestamp_, T_cw->inverse() * *track.pending_position);
      // Keep one position from before the stillness window, so that it shows the window is covered.
      const double window_start = last_timestamp_ - options_.plus.still_seconds;
      while (track.positions.size() >= 2 && track.positions[1].first <= window_start) track.positions.pop_front();
    }
    track.pending_position.reset();
  }
}

std::vector<ExclusionRegion> DynamicRegions(const JudgedBoxes& boxes) {
  std::vector<ExclusionRegion> regions;
  for (std::size_t i = 0; i < boxes.context.size(); ++i) {
    if (boxes.decisions[i].dynamic) regions.push_back(boxes.context[i].region);
  }
  return regions;
}

}  // namespace hoidslam::hoid
