#include "hoidslam/hoid/filter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace hoidslam::hoid {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Box edges in double, so that an overlap ratio equal to a decimal threshold (40 px² of 100 px² against 0.4)
// compares equal to it: both are the double nearest the same value.
struct Edges {
  double x0, y0, x1, y1;

  explicit Edges(const cv::Rect2f& box)
      : x0(box.x), y0(box.y), x1(x0 + static_cast<double>(box.width)), y1(y0 + static_cast<double>(box.height)) {}

  double Area() const { return (x1 - x0) * (y1 - y0); }
};

double OverlapArea(const Edges& a, const Edges& b) {
  const double w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0);
  const double h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
  return w > 0.0 && h > 0.0 ? w * h : 0.0;
}

// How an object's depth compares with one interacting person's.
enum class DepthMatch { kAgrees, kDiffers, kUnavailable };

// Mode hoid3d, for an object that passed the 2D rule: which interacting person decides, by the rules in the
// header. Persons are offered in detection order; on equal ratios the first offered is kept.
class DepthVote {
 public:
  struct Candidate {
    int person = -1;
    float ratio = 0.0F;
  };

  void Offer(int person, float ratio, DepthMatch match) {
    Keep(best_, {person, ratio});
    if (match == DepthMatch::kAgrees) Keep(best_agreeing_, {person, ratio});
    if (match == DepthMatch::kUnavailable) Keep(best_unavailable_, {person, ratio});
  }

  std::pair<Reason, Candidate> Verdict() const {
    if (best_agreeing_.person >= 0) return {Reason::kDepthConfirmed, best_agreeing_};
    if (best_unavailable_.person >= 0) return {Reason::kDepthUnavailable, best_unavailable_};
    return {Reason::kDepthRejected, best_};
  }

 private:
  static void Keep(Candidate& kept, Candidate offered) {
    if (kept.person < 0 || offered.ratio > kept.ratio) kept = offered;
  }

  Candidate best_, best_agreeing_, best_unavailable_;
};

// One object (a potentially dynamic class, not a person) in mode hoid2d or hoid3d; the persons' decisions are
// already final, and `decisions[i].depth` caches person i's sampled depth once it is valid.
void ClassifyObject(std::size_t object, std::span<const core::Detection> detections,
                    const core::HoidOptions& options, const cv::Mat& depth, std::span<Decision> decisions) {
  Decision& out = decisions[object];
  const Edges o(detections[object].box);
  const double area = o.Area();
  out.dynamic = false;
  out.reason = Reason::kNoInteraction;
  if (!(area > 0.0)) return;  // also rejects NaN edges

  const bool use_depth = options.mode == core::FilterMode::kHoid3d;
  bool interacts = false;
  bool object_sampled = false;
  DepthVote vote;
  float best_ratio = 0.0F;
  for (std::size_t p = 0; p < detections.size(); ++p) {
    if (decisions[p].reason != Reason::kPerson) continue;
    const double ratio_d = OverlapArea(o, Edges(detections[p].box)) / area;
    const auto ratio = static_cast<float>(ratio_d);
    if (ratio > best_ratio) {
      best_ratio = ratio;
      out.person_index = static_cast<int>(p);
    }
    if (!(ratio_d >= options.min_interaction_area)) continue;
    interacts = true;
    if (!use_depth) continue;
    if (!object_sampled) {
      out.depth = SampleDepth(depth, BoxCentre(detections[object].box), options.sample_box_size);
      object_sampled = true;
    }
    // Persons are shared between objects: a valid depth is sampled once, an invalid one again (rare, and cheap).
    float& person_depth = decisions[p].depth;
    if (!IsValidDepth(person_depth)) {
      person_depth = SampleDepth(depth, BoxCentre(detections[p].box), options.sample_box_size);
    }
    DepthMatch match = DepthMatch::kUnavailable;
    if (IsValidDepth(out.depth) && IsValidDepth(person_depth)) {
      match = std::abs(out.depth - person_depth) < options.depth_threshold ? DepthMatch::kAgrees : DepthMatch::kDiffers;
    }
    vote.Offer(static_cast<int>(p), ratio, match);
  }
  out.interaction_ratio = best_ratio;
  if (!interacts) return;
  if (!use_depth) {
    out.dynamic = true;
    out.reason = Reason::kInteraction;
    return;
  }
  const auto [reason, person] = vote.Verdict();
  out.reason = reason;
  out.dynamic = reason != Reason::kDepthRejected;
  out.person_index = person.person;
  out.interaction_ratio = person.ratio;
  out.person_depth = decisions[static_cast<std::size_t>(person.person)].depth;
  out.depth_difference = std::abs(out.depth - out.person_depth);  // NaN if either is
}

// The keypoint test, over chunks of keypoints copied to local arrays so the inner loop over one dynamic box is
// a branch-free pass the compiler can vectorise.
template <typename Point, typename GetPoint>
void MarkKeypoints(std::span<const Point> keypoints, std::span<const core::Detection> detections,
                   std::span<const Decision> decisions, std::vector<std::uint8_t>& keep, GetPoint get_point) {
  if (decisions.size() != detections.size()) {
    throw std::invalid_argument("MarkKeypointsToKeep: " + std::to_string(decisions.size()) + " decisions for " +
                                std::to_string(detections.size()) + " detections");
  }
  keep.resize(keypoints.size());
  constexpr std::size_t kChunk = 256;
  std::array<float, kChunk> xs;
  std::array<float, kChunk> ys;
  std::array<std::uint32_t, kChunk> inside;
  for (std::size_t begin = 0; begin < keypoints.size(); begin += kChunk) {
    const std::size_t n = std::min(kChunk, keypoints.size() - begin);
    for (std::size_t i = 0; i < n; ++i) {
      const cv::Point2f pt = get_point(keypoints[begin + i]);
      xs[i] = pt.x;
      ys[i] = pt.y;
      inside[i] = 0;
    }
    for (std::size_t d = 0; d < detections.size(); ++d) {
      if (!decisions[d].dynamic) continue;
      const cv::Rect2f& box = detections[d].box;
      // The same float expressions as cv::Rect2f::contains.
      const float x0 = box.x;
      const float x1 = box.x + box.width;
      const float y0 = box.y;
      const float y1 = box.y + box.height;
      for (std::size_t i = 0; i < n; ++i) {
        inside[i] |= static_cast<std::uint32_t>(x0 <= xs[i]) & static_cast<std::uint32_t>(xs[i] < x1) &
                     static_cast<std::uint32_t>(y0 <= ys[i]) & static_cast<std::uint32_t>(ys[i] < y1);
      }
    }
    for (std::size_t i = 0; i < n; ++i) keep[begin + i] = static_cast<std::uint8_t>(inside[i] ^ 1U);
  }
}

}  // namespace

std::string_view ToString(Reason reason) {
  switch (reason) {
    case Reason::kPerson: return "person";
    case Reason::kModeKeepsAll: return "mode_keeps_all";
    case Reason::kNotPotentiallyDynamic: return "not_potentially_dynamic";
    case Reason::kPersonsOnly: return "persons_only";
    case Reason::kClassPrior: return "class_prior";
    case Reason::kNoInteraction: return "no_interaction";
    case Reason::kInteraction: return "interaction";
    case Reason::kDepthConfirmed: return "depth_confirmed";
    case Reason::kDepthRejected: return "depth_rejected";
    case Reason::kDepthUnavailable: return "depth_unavailable";
    case Reason::kCarried: return "carried";
    case Reason::kRecentlyHandled: return "recently_handled";
    case Reason::kSeenStill: return "seen_still";
    case Reason::kTooLargeToHandle: return "too_large_to_handle";
  }
  return "unknown";
}

void CheckDepthImage(const cv::Mat& depth, std::string_view function) {
  if (!depth.empty() && depth.type() != CV_32FC1) {
    throw std::invalid_argument(std::string(function) + ": depth image must be CV_32FC1 (metres), got type " +
                                std::to_string(depth.type()));
  }
}

float SampleDepth(const cv::Mat& depth, cv::Point2f centre, int size) {
  if (size < 1) throw std::invalid_argument("SampleDepth: box size must be >= 1, got " + std::to_string(size));
  CheckDepthImage(depth, "SampleDepth");
  if (depth.empty()) return kNaN;
  if (!std::isfinite(centre.x) || !std::isfinite(centre.y)) return kNaN;
  // Clip in double before converting, so far-off centres cannot overflow an int.
  const double left = std::floor(static_cast<double>(centre.x) - size * 0.5);
  const double top = std::floor(static_cast<double>(centre.y) - size * 0.5);
  const int x0 = static_cast<int>(std::clamp(left, 0.0, static_cast<double>(depth.cols)));
  const int x1 = static_cast<int>(std::clamp(left + size, 0.0, static_cast<double>(depth.cols)));
  const int y0 = static_cast<int>(std::clamp(top, 0.0, static_cast<double>(depth.rows)));
  const int y1 = static_cast<int>(std::clamp(top + size, 0.0, static_cast<double>(depth.rows)));
  const auto capacity = static_cast<std::size_t>(x1 - x0) * static_cast<std::size_t>(y1 - y0);
  if (capacity == 0) return kNaN;

  // The default 20×20 box fits on the stack; only unusually large boxes need the heap.
  constexpr std::size_t kStackSamples = 64 * 64;
  std::array<float, kStackSamples> stack_samples;
  std::vector<float> heap_samples;
  std::span<float> samples(stack_samples);
  if (capacity > kStackSamples) {
    heap_samples.resize(capacity);
    samples = heap_samples;
  }
  // Invalid pixels become +inf, which selection puts after every valid depth, so the median of the n valid
  // values is found among all samples without compacting them (the copy loop stays vectorisable).
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const auto width = static_cast<std::size_t>(x1 - x0);
  std::size_t n = 0;
  for (int y = y0; y < y1; ++y) {
    const float* row = depth.ptr<float>(y) + x0;
    float* out = samples.data() + static_cast<std::size_t>(y - y0) * width;
    for (std::size_t x = 0; x < width; ++x) {
      const bool valid = IsValidDepth(row[x]);
      out[x] = valid ? row[x] : kInf;
      n += static_cast<std::size_t>(valid);
    }
  }
  if (n == 0) return kNaN;
  const auto mid = samples.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(samples.begin(), mid, samples.begin() + static_cast<std::ptrdiff_t>(capacity));
  if (n % 2 == 1) return *mid;
  return 0.5F * (*std::max_element(samples.begin(), mid) + *mid);
}

std::vector<Decision> ClassifyDetections(std::span<const core::Detection> detections,
                                         const core::HoidOptions& options, const cv::Mat& depth) {
  std::vector<Decision> decisions;
  ClassifyDetections(detections, options, depth, decisions);
  return decisions;
}

void ClassifyDetections(std::span<const core::Detection> detections, const core::HoidOptions& options,
                        const cv::Mat& depth, std::vector<Decision>& decisions) {
  options.Check();
  CheckDepthImage(depth, "ClassifyDetections");
  decisions.assign(detections.size(), Decision{});
  if (options.mode == core::FilterMode::kNone) return;  // every default Decision is kModeKeepsAll, static

  // Persons first: the object rules need every person's final decision.
  for (std::size_t i = 0; i < detections.size(); ++i) {
    Decision& d = decisions[i];
    const std::string& label = detections[i].label;
    if (label == options.person_class) {
      d.dynamic = true;
      d.reason = Reason::kPerson;
    } else if (!options.IsPotentiallyDynamic(label)) {
      d.reason = Reason::kNotPotentiallyDynamic;
    } else if (options.mode == core::FilterMode::kPerson) {
      d.reason = Reason::kPersonsOnly;
    } else if (options.mode == core::FilterMode::kClasses) {
      d.dynamic = true;
      d.reason = Reason::kClassPrior;
    } else {
      d.reason = Reason::kNoInteraction;  // provisional: decided below
    }
  }
  for (std::size_t i = 0; i < detections.size(); ++i) {
    if (decisions[i].reason == Reason::kNoInteraction) ClassifyObject(i, detections, options, depth, decisions);
  }
}

void MarkKeypointsToKeep(std::span<const cv::KeyPoint> keypoints, std::span<const core::Detection> detections,
                         std::span<const Decision> decisions, std::vector<std::uint8_t>& keep) {
  MarkKeypoints(keypoints, detections, decisions, keep, [](const cv::KeyPoint& k) { return k.pt; });
}

void MarkKeypointsToKeep(std::span<const cv::Point2f> keypoints, std::span<const core::Detection> detections,
                         std::span<const Decision> decisions, std::vector<std::uint8_t>& keep) {
  MarkKeypoints(keypoints, detections, decisions, keep, [](const cv::Point2f& p) { return p; });
}

}  // namespace hoidslam::hoid
