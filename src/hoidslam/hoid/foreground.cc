#include "hoidslam/hoid/foreground.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace hoidslam::hoid {
namespace {

constexpr std::size_t kTargetSamples = 500;
constexpr std::size_t kMinSamples = 10;
constexpr double kMinDepth = 0.05;  // metres: the histogram's origin, below any RGB-D sensor's range

// The integer pixels whose position p satisfies low <= p < high, clipped to [0, limit).
std::pair<int, int> PixelsInside(float low, float high, int limit) {
  const double first = std::clamp(std::ceil(static_cast<double>(low)), 0.0, static_cast<double>(limit));
  const double end = std::clamp(std::ceil(static_cast<double>(high)), 0.0, static_cast<double>(limit));
  return {static_cast<int>(first), std::max(static_cast<int>(first), static_cast<int>(end))};
}

// Whether pixel (x, y), inside the region's box, is dropped by it.
bool Dropped(const ExclusionRegion& region, const cv::Mat& depth, int x, int y) {
  if (depth.empty() || std::isinf(region.cut)) return true;
  if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) return true;
  if (!IsValidDepth(depth.at<float>(y, x))) return true;
  const int m = region.edge_margin;
  for (int row = std::max(0, y - m); row <= std::min(depth.rows - 1, y + m); ++row) {
    const float* line = depth.ptr<float>(row);
    for (int col = std::max(0, x - m); col <= std::min(depth.cols - 1, x + m); ++col) {
      if (IsValidDepth(line[col]) && line[col] < region.cut) return true;
    }
  }
  return false;
}

}  // namespace

std::optional<DepthCluster> ForegroundDepth(const cv::Mat& depth, const cv::Rect2f& box,
                                            const core::HoidPlusOptions& options) {
  CheckDepthImage(depth, "ForegroundDepth");
  if (depth.empty() || !(box.width > 0.0F) || !(box.height > 0.0F)) return std::nullopt;
  const auto [x0, x1] = PixelsInside(box.x, box.x + box.width, depth.cols);
  const auto [y0, y1] = PixelsInside(box.y, box.y + box.height, depth.rows);
  const double area = static_cast<double>(x1 - x0) * static_cast<double>(y1 - y0);
  if (area <= 0.0) return std::nullopt;
  const int stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(area / kTargetSamples))));

  // Each sample also gets a centre weight: 1 at the box's centre, falling to 0 at its edges.
  const float cx = box.x + box.width * 0.5F;
  const float cy = box.y + box.height * 0.5F;
  struct Sample {
    float depth;
    float centre_weight;
    int bin;  // in the histogram below
  };
  std::vector<Sample> samples;
  samples.reserve(kTargetSamples + 2 * static_cast<std::size_t>(std::sqrt(kTargetSamples)) + 1);
  for (int y = y0 + stride / 2; y < y1; y += stride) {
    const float* row = depth.ptr<float>(y);
    const float wy = 1.0F - std::min(1.0F, std::abs(static_cast<float>(y) - cy) / (box.height * 0.5F));
    for (int x = x0 + stride / 2; x < x1; x += stride) {
      if (!IsValidDepth(row[x])) continue;
      const float wx = 1.0F - std::min(1.0F, std::abs(static_cast<float>(x) - cx) / (box.width * 0.5F));
      samples.push_back({row[x], wx * wy, 0});  // binned below
    }
  }
  if (samples.size() < kMinSamples) return std::nullopt;

  // A histogram over log depth (bins a fixed share of the depth wide, as sensor noise grows with depth), smoothed
  // and cut into modes where the density falls below options.valley of the mode's peak so far. Floors and desks
  // run through every depth, so a plain gap between modes rarely exists indoors; a valley does.
  const double log_step = std::log1p(options.depth_bin);
  const auto bin_of = [&](float d) {
    return static_cast<int>(std::floor((std::log(static_cast<double>(d)) - std::log(kMinDepth)) / log_step));
  };
  const auto bin_edge = [&](int bin) { return static_cast<float>(std::exp(std::log(kMinDepth) + log_step * bin)); };
  int lowest = std::numeric_limits<int>::max(), highest = std::numeric_limits<int>::min();
  for (Sample& s : samples) {
    s.bin = bin_of(s.depth);
    lowest = std::min(lowest, s.bin);
    highest = std::max(highest, s.bin);
  }
  const auto bins = static_cast<std::size_t>(highest - lowest + 1) + 2;  // a zero bin on each side
  std::vector<double> count(bins, 0.0), centre(bins, 0.0);
  for (const Sample& s : samples) {
    const auto b = static_cast<std::size_t>(s.bin - lowest + 1);
    count[b] += 1.0;
    centre[b] += s.centre_weight;
  }
  std::vector<double> smooth(bins, 0.0);
  for (std::size_t b = 1; b + 1 < bins; ++b) smooth[b] = 0.25 * count[b - 1] + 0.5 * count[b] + 0.25 * count[b + 1];
  struct Mode {
    std::size_t first = 0, end = 0;  // bins [first, end)
    double count = 0.0, centre = 0.0;
  };
  std::vector<Mode> modes;
  for (std::size_t b = 1; b + 1 < bins;) {
    while (b + 1 < bins && !(smooth[b] > 0.0)) ++b;
    if (b + 1 >= bins) break;
    Mode mode{b, b, 0.0, 0.0};
    double peak = 0.0;
    while (b + 1 < bins && smooth[b] > 0.0 && smooth[b] >= options.valley * peak) {
      peak = std::max(peak, smooth[b]);
      mode.count += count[b];
      mode.centre += centre[b];
      ++b;
    }
    mode.end = b;
    modes.push_back(mode);
  }
  // Two readings of "the thing the box was drawn around", and the foreground spans both: the mode that holds the
  // box's centre (a person behind a desk) and the nearest mode holding options.foreground_share of the samples (a
  // person cut off by the image border, or beside what the box's centre shows). Dropping what lies between costs
  // a few static keypoints; keeping a moving one costs the pose.
  const auto central = std::max_element(modes.begin(), modes.end(),
                                        [](const Mode& a, const Mode& b) { return a.centre < b.centre; });
  const auto nearest = std::find_if(modes.begin(), modes.end(), [&](const Mode& m) {
    return m.count >= options.foreground_share * static_cast<double>(samples.size());
  });
  const Mode& near_mode = nearest == modes.end() ? *central : *nearest;
  const std::size_t first = std::min(central->first, near_mode.first);
  const std::size_t end = std::max(central->end, near_mode.end);

  const auto median_between = [&](std::size_t from, std::size_t to) {
    const float low = bin_edge(static_cast<int>(from) - 1 + lowest);
    const float high = bin_edge(static_cast<int>(to) - 1 + lowest);
    std::vector<float> inside;
    for (const Sample& s : samples) {
      if (s.depth >= low && s.depth < high) inside.push_back(s.depth);
    }
    const auto mid = inside.begin() + static_cast<std::ptrdiff_t>(inside.size() / 2);
    std::nth_element(inside.begin(), mid, inside.end());
    return *mid;  // every mode holds samples
  };
  DepthCluster cluster;
  cluster.near = bin_edge(static_cast<int>(first) - 1 + lowest);
  cluster.far = bin_edge(static_cast<int>(end) - 1 + lowest);  // the upper edge of the last bin
  cluster.median = median_between(central->first, central->end);
  cluster.samples = samples.size();
  const auto extent = static_cast<float>(options.depth_extent);
  cluster.cut = std::max({cluster.far, cluster.median + extent, median_between(near_mode.first, near_mode.end) + extent});
  return cluster;
}

void MarkKeypointsBehindForeground(std::span<const cv::KeyPoint> keypoints, const cv::Mat& depth,
                                   std::span<const ExclusionRegion> regions, std::vector<std::uint8_t>& keep) {
  CheckDepthImage(depth, "MarkKeypointsBehindForeground");
  keep.assign(keypoints.size(), 1);
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const cv::Point2f p = keypoints[i].pt;
    const int x = static_cast<int>(std::lround(p.x));
    const int y = static_cast<int>(std::lround(p.y));
    for (const ExclusionRegion& region : regions) {
      if (region.box.contains(p) && Dropped(region, depth, x, y)) {
        keep[i] = 0;
        break;
      }
    }
  }
}

cv::Mat PaintExclusionRegions(std::span<const ExclusionRegion> regions, const cv::Mat& depth, cv::Size size) {
  CheckDepthImage(depth, "PaintExclusionRegions");
  if (!depth.empty() && depth.size() != size) throw std::invalid_argument("PaintExclusionRegions: depth size differs");
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  for (const ExclusionRegion& region : regions) {
    const auto [x0, x1] = PixelsInside(region.box.x, region.box.x + region.box.width, size.width);
    const auto [y0, y1] = PixelsInside(region.box.y, region.box.y + region.box.height, size.height);
    if (x0 >= x1 || y0 >= y1) continue;
    const cv::Rect inside(x0, y0, x1 - x0, y1 - y0);
    cv::Mat roi = mask(inside);
    if (depth.empty() || std::isinf(region.cut)) {
      roi.setTo(255);
      continue;
    }
    // The test of Dropped, for a whole box at once: the foreground nearer than the cut, grown by the edge margin
    // (taking in the depths up to the margin outside the box), or no valid depth.
    const cv::Rect reach = cv::Rect(x0 - region.edge_margin, y0 - region.edge_margin, x1 - x0 + 2 * region.edge_margin,
                                    y1 - y0 + 2 * region.edge_margin) & cv::Rect(0, 0, size.width, size.height);
    const cv::Mat near_depth = depth(reach);
    cv::Mat foreground = (near_depth > 0.0F) & (near_depth < region.cut);
    if (region.edge_margin > 0) {
      const int side = 2 * region.edge_margin + 1;
      cv::dilate(foreground, foreground, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)), cv::Point(-1, -1),
                 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    }
    const cv::Mat grown = foreground(inside - reach.tl());
    const cv::Mat box_depth = depth(inside);
    const cv::Mat invalid = ~((box_depth > 0.0F) & (box_depth < std::numeric_limits<float>::infinity()));
    roi.setTo(255, grown | invalid);
  }
  return mask;
}

cv::Rect2f GrowBox(const cv::Rect2f& box, double margin) {
  const auto dx = static_cast<float>(margin * box.width);
  const auto dy = static_cast<float>(margin * box.height);
  return {box.x - dx, box.y - dy, box.width + 2.0F * dx, box.height + 2.0F * dy};
}

}  // namespace hoidslam::hoid
