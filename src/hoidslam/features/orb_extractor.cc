#include "hoidslam/features/orb_extractor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>


namespace hoidslam::features {
namespace {

constexpr int kPatchSize = 31;      // side of the BRIEF patch; the keypoint size at level 0
constexpr int kHalfPatch = 15;      // radius of the orientation disk, half the BRIEF patch
constexpr int kEdgeThreshold = 19;  // keypoints lie at least this far inside their level image (ORB-SLAM)
constexpr int kFastBorder = 3;      // cv::FAST reports no corner within 3 px of its image's edge
constexpr int kCellSize = 30;       // side of the cells the FAST thresholds are chosen in
// ExtractOutside keeps its keypoints this many (level-0) pixels away from what is excluded: a corner closer than
// that is made by the pixels of a person's outline, which move with the person. (Without it, walking_xyz with
// hoid2d drifted to 74 mm ATE; with it, 3.3 mm.) Not more, nor in pixels of each level: between people who fill
// the view the static world left is a few narrow strips.
constexpr int kExcludedMargin = 8;
constexpr int kDescriptorBytes = core::kOrbDescriptorBytes;
constexpr int kTests = kDescriptorBytes * 8;
// A test point of the 31×31 patch, rotated, lands up to round(15·√2) = 21 px from the keypoint: 2 px past the
// edge for a keypoint 19 px inside. The smoothed levels carry a reflected border that covers this.
constexpr int kBlurBorder = 3;
static_assert(kEdgeThreshold + kBlurBorder > 21);
static_assert(kEdgeThreshold > kHalfPatch);  // the orientation disk stays inside the level image

// The 256 BRIEF tests: pairs of points of the patch around a keypoint, at angle 0.
struct BriefPattern {
  std::array<float, 2 * kTests> x{};
  std::array<float, 2 * kTests> y{};
};

// Sampled once, BRIEF's G II: both points of a pair isotropic Gaussian about the centre with sigma = S / 5
// (S = 31), drawn again until inside the patch; identical or repeated pairs are drawn again too. The Gaussian is
// Box–Muller on std::mt19937's output, which the standard fixes, where std::normal_distribution's algorithm is
// up to the library: every platform gets the same pattern.
const BriefPattern& Pattern() {
  static const BriefPattern pattern = [] {
    std::mt19937 rng(20240531U);
    const auto uniform = [&rng] { return (static_cast<double>(rng()) + 0.5) / 4294967296.0; };  // in (0, 1)
    const double sigma = kPatchSize / 5.0;
    const auto point = [&] {
      for (;;) {
        const double radius = sigma * std::sqrt(-2.0 * std::log(uniform()));
        const double theta = 2.0 * std::numbers::pi * uniform();
        const auto x = static_cast<int>(std::lround(radius * std::cos(theta)));
        const auto y = static_cast<int>(std::lround(radius * std::sin(theta)));
        if (std::abs(x) <= kHalfPatch && std::abs(y) <= kHalfPatch) return std::pair{x, y};
      }
    };
    BriefPattern p;
    std::set<std::pair<std::pair<int, int>, std::pair<int, int>>> seen;
    for (int t = 0; t < kTests;) {
      const auto a = point();
      const auto b = point();
      if (a == b || !seen.insert(std::minmax(a, b)).second) continue;
      p.x[2 * t] = static_cast<float>(a.first);
      p.y[2 * t] = static_cast<float>(a.second);
      p.x[2 * t + 1] = static_cast<float>(b.first);
      p.y[2 * t + 1] = static_cast<float>(b.second);
      ++t;
    }
    return p;
  }();
  return pattern;
}

// Half-widths of the orientation disk's rows: row v holds the pixels u with |u| <= half_width[|v|], u² + v² <= 15².
const std::array<int, kHalfPatch + 1>& DiskHalfWidths() {
  static const std::array<int, kHalfPatch + 1> half_width = [] {
    std::array<int, kHalfPatch + 1> w{};
    for (int v = 0; v <= kHalfPatch; ++v) {
      w[static_cast<std::size_t>(v)] = static_cast<int>(std::floor(std::sqrt(kHalfPatch * kHalfPatch - v * v)));
    }
    return w;
  }();
  return half_width;
}

// Orientation by intensity centroid: the direction, in degrees [0, 360), from the pixel (x, y) to the centroid of
// the disk of radius 15 around it (y down, so angles turn clockwise on screen).
float Orientation(const cv::Mat& image, int x, int y) {
  const auto& half_width = DiskHalfWidths();
  const auto step = static_cast<std::ptrdiff_t>(image.step1());
  const std::uint8_t* center = image.ptr<std::uint8_t>(y) + x;
  int m10 = 0;
  int m01 = 0;
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * center[u];
  // Rows v and -v together: they share the u weights and have opposite v weights.
  for (int v = 1; v <= kHalfPatch; ++v) {
    const std::uint8_t* below = center + v * step;
    const std::uint8_t* above = center - v * step;
    const int w = half_width[static_cast<std::size_t>(v)];
    int difference = 0;
    for (int u = -w; u <= w; ++u) {
      m10 += u * (below[u] + above[u]);
      difference += below[u] - above[u];
    }
    m01 += v * difference;
  }
  float degrees = std::atan2(static_cast<float>(m01), static_cast<float>(m10)) * (180.0F / std::numbers::pi_v<float>);
  if (degrees < 0.0F) degrees += 360.0F;
  return degrees >= 360.0F ? 0.0F : degrees;  // -tiny + 360 rounds to 360
}

// Rounds to the nearest integer, ties to even (as cvRound), for |v| < 2^22: adding 1.5 · 2^23 leaves no bits
// for a fraction. Plain float arithmetic, so the loop in Describe vectorises (and relies on IEEE rounding: no
// -ffast-math).
inline float RoundToInteger(float v) {
  constexpr float kMagic = 12582912.0F;
  return (v + kMagic) - kMagic;
}

// Rotated BRIEF: bit t of the descriptor is set when the smoothed image is darker at the first point of test t
// than at the second, both rotated by the keypoint's angle about it.
void Describe(const cv::Mat& blurred, int x, int y, float angle_degrees, std::uint8_t* out) {
  const BriefPattern& pattern = Pattern();
  const float radians = angle_degrees * (std::numbers::pi_v<float> / 180.0F);
  const float c = std::cos(radians);
  const float s = std::sin(radians);
  const auto step = static_cast<float>(blurred.step1());
  // Offsets are exact in float: |offset| <= 21 · step + 21, far below 2^24.
  std::array<int, 2 * kTests> offset;
  for (std::size_t i = 0; i < offset.size(); ++i) {
    const float rx = RoundToInteger(pattern.x[i] * c - pattern.y[i] * s);
    const float ry = RoundToInteger(pattern.x[i] * s + pattern.y[i] * c);
    offset[i] = static_cast<int>(ry * step + rx);
  }
  const std::uint8_t* center = blurred.ptr<std::uint8_t>(y) + x;
  for (int byte = 0; byte < kDescriptorBytes; ++byte) {
    unsigned value = 0;
    for (int bit = 0; bit < 8; ++bit) {
      const auto t = static_cast<std::size_t>(2 * (8 * byte + bit));
      value |= static_cast<unsigned>(center[offset[t]] < center[offset[t + 1]]) << bit;
    }
    out[byte] = static_cast<std::uint8_t>(value);
  }
}

// The 7-tap Gaussian of sigma 2 the BRIEF tests are smoothed with, in x and then in y. Computed once and applied
// with cv::sepFilter2D, which here takes 0.55 ms over the levels of a 640×480 frame where cv::GaussianBlur
// takes 0.9 ms.
const cv::Matx<float, 7, 1>& SmoothingKernel() {
  static const cv::Matx<float, 7, 1> kernel(cv::getGaussianKernel(7, 2.0, CV_32F));
  return kernel;
}

// Fills a border of `b` pixels around buffer's inner (rows - 2b) × (cols - 2b) image by reflection about the
// edge pixels (cv::BORDER_REFLECT_101: ... 2 1 | 0 1 2 ...).
void ReflectBorder(cv::Mat& buffer, int b) {
  const int rows = buffer.rows - 2 * b;
  const int cols = buffer.cols - 2 * b;
  for (int r = b; r < b + rows; ++r) {
    std::uint8_t* row = buffer.ptr<std::uint8_t>(r);
    for (int k = 1; k <= b; ++k) {
      row[b - k] = row[b + k];
      row[b + cols - 1 + k] = row[b + cols - 1 - k];
    }
  }
  const auto width = static_cast<std::size_t>(buffer.cols);
  for (int k = 1; k <= b; ++k) {
    std::memcpy(buffer.ptr(b - k), buffer.ptr(b + k), width);
    std::memcpy(buffer.ptr(b + rows - 1 + k), buffer.ptr(b + rows - 1 - k), width);
  }
}

// Where FAST looks in a level image: all but a band of kEdgeThreshold - 3 px, so that with FAST's own 3 px
// border corners land at least kEdgeThreshold inside.
cv::Rect SearchArea(const cv::Mat& image) {
  constexpr int kBorder = kEdgeThreshold - kFastBorder;
  return {kBorder, kBorder, image.cols - 2 * kBorder, image.rows - 2 * kBorder};
}

// Whether a level image is large enough to hold a keypoint kEdgeThreshold inside its edges.
bool Usable(const cv::Mat& image) { return image.cols > 2 * kEdgeThreshold && image.rows > 2 * kEdgeThreshold; }

// ORB-SLAM's split of n features over the levels: a geometric series of ratio 1 / scale_factor (the levels'
// side, not their area: ORB-SLAM's own choice, which leaves the coarse levels more than the area would), rounded,
// the last level taking what is left.
std::vector<int> FeaturesPerLevel(int n, int levels, double scale_factor) {
  const double ratio = 1.0 / scale_factor;
  double wanted = n * (1.0 - ratio) / (1.0 - std::pow(ratio, levels));
  std::vector<int> per_level(static_cast<std::size_t>(levels), 0);
  int sum = 0;
  for (int l = 0; l + 1 < levels; ++l) {
    per_level[static_cast<std::size_t>(l)] = std::min(cvRound(wanted), n - sum);
    sum += per_level[static_cast<std::size_t>(l)];
    wanted *= ratio;
  }
  per_level.back() = n - sum;
  return per_level;
}

}  // namespace

ScalePyramid ScalePyramid::Make(int levels, double factor) {
  if (levels < 1 || !(factor > 1.0)) {
    throw std::invalid_argument("ScalePyramid::Make: need levels >= 1 and factor > 1, got levels " +
                                std::to_string(levels) + ", factor " + std::to_string(factor));
  }
  ScalePyramid p;
  double scale = 1.0;
  for (int l = 0; l < levels; ++l) {
    p.scale.push_back(static_cast<float>(scale));
    p.inv_scale.push_back(static_cast<float>(1.0 / scale));
    p.sigma2.push_back(static_cast<float>(scale * scale));
    p.inv_sigma2.push_back(static_cast<float>(1.0 / (scale * scale)));
    scale *= factor;
  }
  return p;
}

OrbExtractor::OrbExtractor(const core::OrbOptions& options) : options_(options) {
  options_.Check();
  pyramid_ = ScalePyramid::Make(options_.n_levels, options_.scale_factor);
  features_per_level_ = FeaturesPerLevel(options_.n_features, options_.n_levels, options_.scale_factor);
  levels_.resize(static_cast<std::size_t>(options_.n_levels));
}

const cv::Mat& OrbExtractor::Brightened(const cv::Mat& gray) {
  if (options_.dim_mean <= 0.0) return gray;
  const double mean = cv::mean(gray)[0];
  if (mean >= options_.dim_mean || mean <= 0.0) return gray;
  // At most max_gain: the darker the image, the more of what is raised is the sensor's noise. A covered lens is
  // raised too (its mean, a few grey levels, is what lights dimmed to a tenth leave of a room): the corners its
  // noise makes have descriptors that match nothing.
  const double gain = std::min(options_.max_gain, options_.dim_mean / mean);
  gray.convertTo(brightened_, CV_8U, gain);
  return brightened_;
}

void OrbExtractor::BuildPyramid(const cv::Mat& gray) {
  levels_[0].image = gray;
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    const cv::Size size(cvRound(gray.cols * pyramid_.inv_scale[l]), cvRound(gray.rows * pyramid_.inv_scale[l]));
    if (size.width < 1 || size.height < 1) {
      levels_[l].image.release();
      continue;
    }
    // From the level above, as ORB-SLAM does: bilinear interpolation only averages neighbouring pixels, so
    // stepping down by 1.2 at a time blurs enough, while a jump from level 0 (up to 1.2^7 ≈ 3.6×) would alias.
    cv::resize(levels_[l - 1].image, levels_[l].image, size, 0.0, 0.0, cv::INTER_LINEAR);
  }
  for (Level& level : levels_) level.blurred_ready = false;
}

template <typename Work>
void OrbExtractor::ForEachLevel(const Work& work) {
  // One task per level, largest first, which OpenCV's threads share out as each becomes free. Each level writes
  // only its own buffers, so the result does not depend on the threads.
  const int count = static_cast<int>(levels_.size());
  cv::parallel_for_(
      cv::Range(0, count),
      [&work](const cv::Range& range) {
        for (int l = range.start; l < range.end; ++l) work(l);
      },
      count);
}

void OrbExtractor::DetectCorners(int index, const cv::Mat& excluded) {
  Level& level = levels_[static_cast<std::size_t>(index)];
  const cv::Mat& image = level.image;
  level.corners.clear();
  const cv::Rect search = SearchArea(image);
  const cv::Rect band(kEdgeThreshold, kEdgeThreshold, image.cols - 2 * kEdgeThreshold, image.rows - 2 * kEdgeThreshold);

  // Cells tile the band, as ORB-SLAM's do: about kCellSize wide.
  const int columns = std::max(1, search.width / kCellSize);
  const int rows = std::max(1, search.height / kCellSize);
  const int cell_width = (search.width + columns - 1) / columns;
  const int cell_height = (search.height + rows - 1) / rows;
  const auto cell = [&](int r, int col) {
    return cv::Rect(kEdgeThreshold + col * cell_width, kEdgeThreshold + r * cell_height, cell_width, cell_height) &
           band;
  };

  // Whether the corner at level pixel (x, y) may be kept: the pixel its level-0 position rounds to is not
  // excluded. The position is computed as Collect computes it, so the test agrees with one on the keypoint.
  // And it keeps the margin: the level's mask, grown by kExcludedMargin, is clear there too.
  const float scale = pyramid_.scale[static_cast<std::size_t>(index)];
  const auto outside = [&](int x, int y) {
    if (excluded.empty()) return true;
    const auto x0 = static_cast<int>(std::lround(static_cast<float>(x) * scale));
    const auto y0 = static_cast<int>(std::lround(static_cast<float>(y) * scale));
    return excluded.at<std::uint8_t>(std::min(y0, excluded.rows - 1), std::min(x0, excluded.cols - 1)) == 0 &&
           level.excluded.at<std::uint8_t>(y, x) == 0;
  };
  // Level 0's grown mask is ExtractOutside's, made before the levels start.
  if (!excluded.empty() && index > 0) {
    cv::resize(levels_[0].excluded, level.excluded, image.size(), 0.0, 0.0, cv::INTER_NEAREST);
  }

  // A cell keeps its corners scoring >= iniThFAST if it has any, else its corners scoring >= minThFAST: what
  // ORB-SLAM gets by running FAST per cell at iniThFAST and again at minThFAST where that yields nothing. Here
  // FAST runs once over the level at iniThFAST, then at minThFAST only over the runs of cells left empty. Both
  // equal one pass at minThFAST followed by that per-cell choice: a pixel's FAST score does not depend on the
  // threshold, so non-maximum suppression keeps a corner scoring >= iniThFAST at the low threshold exactly when it
  // keeps it at the high one (the extra corners it then competes with score lower); and the window of the empty
  // cells reaches one pixel past them, so their corners are suppressed by the same neighbours. (ORB-SLAM
  // suppresses within each cell only, so it may keep a few more corners along cell borders.) With a mask, the
  // corners at iniThFAST are those of the first pass, and a cell counts as empty when none of them lies outside.
  const auto add = [&](const cv::Rect& window, const cv::Rect& keep) {
    for (const cv::KeyPoint& kp : level.fast) {
      const int x = cvRound(kp.pt.x) + window.x;
      const int y = cvRound(kp.pt.y) + window.y;
      if (keep.contains(cv::Point(x, y)) && outside(x, y)) level.corners.push_back({x, y, kp.response});
    }
  };
  if (excluded.empty()) {
    cv::FAST(image(search), level.fast, options_.ini_th_fast, true, cv::FastFeatureDetector::TYPE_9_16);
    add(search, band);
    level.strong = level.corners;
  } else {
    for (const Corner& c : level.strong) {
      if (outside(c.x, c.y)) level.corners.push_back(c);
    }
  }
  level.cell_strong.assign(static_cast<std::size_t>(columns * rows), 0);
  for (const Corner& c : level.corners) {
    level.cell_strong[static_cast<std::size_t>((c.y - kEdgeThreshold) / cell_height * columns +
                                               (c.x - kEdgeThreshold) / cell_width)] = 1;
  }
  // A cell is searched again at minThFAST when it has no strong corner and some pixel outside the mask.
  const auto searched = [&](int r, int col) {
    if (level.cell_strong[static_cast<std::size_t>(r * columns + col)] != 0) return false;
    if (excluded.empty()) return true;
    const cv::Rect box = cell(r, col);
    return !box.empty() && cv::countNonZero(level.excluded(box)) < box.area();
  };
  for (int r = 0; r < rows; ++r) {
    for (int col = 0; col < columns;) {
      if (!searched(r, col)) {
        ++col;
        continue;
      }
      int end = col + 1;
      while (end < columns && searched(r, end)) ++end;
      cv::Rect run(kEdgeThreshold + col * cell_width, kEdgeThreshold + r * cell_height, (end - col) * cell_width,
                   cell_height);
      run &= band;
      col = end;
      if (run.empty()) continue;
      // FAST's 3 px border plus the one pixel of neighbours non-maximum suppression looks at.
      constexpr int kMargin = kFastBorder + 1;
      const cv::Rect window =
          cv::Rect(run.x - kMargin, run.y - kMargin, run.width + 2 * kMargin, run.height + 2 * kMargin) & search;
      cv::FAST(image(window), level.fast, options_.min_th_fast, true, cv::FastFeatureDetector::TYPE_9_16);
      add(window, run);
    }
  }
}

void OrbExtractor::SelectAndDescribe(int index, int budget, Described Level::*out) {
  const auto l = static_cast<std::size_t>(index);
  Level& level = levels_[l];
  Described& result = level.*out;
  result.keypoints.clear();
  result.descriptors.create(0, kDescriptorBytes, CV_8UC1);
  if (budget == 0 || level.corners.empty()) return;
  const cv::Mat& image = level.image;
  // The quadtree spans the FAST search area, as ORB-SLAM's does.
  level.distributor.Distribute(level.corners, SearchArea(image), budget, level.selected);
  if (level.selected.empty()) return;

  // Where Extract kept the same corner: its index there, else -1.
  const bool reuse = out == &Level::outside;
  const auto extracted_index = [&](const Corner& c) {
    if (!reuse) return -1;
    const std::pair<int, int> key(c.y * image.cols + c.x, -1);
    const auto it = std::lower_bound(level.extracted_at.begin(), level.extracted_at.end(), key);
    return it != level.extracted_at.end() && it->first == key.first ? it->second : -1;
  };
  std::vector<int>& from = level.reused;
  from.clear();
  const float size = kPatchSize * pyramid_.scale[l];
  for (int i : level.selected) {
    const Corner& c = level.corners[static_cast<std::size_t>(i)];
    const int known = extracted_index(c);
    const float angle = known >= 0 ? level.extracted.keypoints[static_cast<std::size_t>(known)].angle
                                   : Orientation(image, c.x, c.y);
    result.keypoints.emplace_back(static_cast<float>(c.x), static_cast<float>(c.y), size, angle, c.response, index);
    from.push_back(known);
  }

  result.descriptors.create(static_cast<int>(result.keypoints.size()), kDescriptorBytes, CV_8UC1);
  const bool all_known = std::none_of(from.begin(), from.end(), [](int known) { return known < 0; });
  // Smoothed into the inside of a bordered buffer, once a frame. Isolated: level 0 may be a view into a larger
  // image, whose pixels beyond the view must not count.
  const cv::Rect inside(kBlurBorder, kBlurBorder, image.cols, image.rows);
  if (!level.blurred_ready && !all_known) {
    level.blurred.create(image.rows + 2 * kBlurBorder, image.cols + 2 * kBlurBorder, CV_8UC1);
    cv::Mat target = level.blurred(inside);
    const cv::Matx<float, 7, 1>& kernel = SmoothingKernel();
    cv::sepFilter2D(image, target, CV_8U, kernel, kernel, cv::Point(-1, -1), 0.0,
                    cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED);
    ReflectBorder(level.blurred, kBlurBorder);
    level.blurred_ready = true;
  }
  for (std::size_t i = 0; i < result.keypoints.size(); ++i) {
    auto* row = result.descriptors.ptr<std::uint8_t>(static_cast<int>(i));
    if (from[i] >= 0) {
      std::memcpy(row, level.extracted.descriptors.ptr<std::uint8_t>(from[i]), kDescriptorBytes);
      continue;
    }
    const cv::KeyPoint& kp = result.keypoints[i];
    Describe(level.blurred(inside), static_cast<int>(kp.pt.x), static_cast<int>(kp.pt.y), kp.angle, row);
  }
}

void OrbExtractor::Extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  if (gray.empty()) throw std::invalid_argument("OrbExtractor::Extract: the image is empty");
  if (gray.type() != CV_8UC1) {
    throw std::invalid_argument("OrbExtractor::Extract: expected a grayscale CV_8UC1 image, got " +
                                cv::typeToString(gray.type()));
  }
  BuildPyramid(Brightened(gray));
  ForEachLevel([this](int l) {
    Level& level = levels_[static_cast<std::size_t>(l)];
    level.strong.clear();
    level.corners.clear();
    level.extracted.keypoints.clear();
    if (!Usable(level.image)) return;
    DetectCorners(l, cv::Mat());
    SelectAndDescribe(l, features_per_level_[static_cast<std::size_t>(l)], &Level::extracted);
  });
  Collect(&Level::extracted, keypoints, descriptors);
}

void OrbExtractor::ExtractOutside(const cv::Mat& excluded, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  const cv::Mat& image = levels_[0].image;
  if (image.empty()) throw std::logic_error("OrbExtractor::ExtractOutside: no image extracted from yet");
  if (excluded.size() != image.size() || excluded.type() != CV_8UC1) {
    throw std::invalid_argument(fmt::format("OrbExtractor::ExtractOutside: the mask must be {}×{} CV_8UC1, got {}×{} {}",
                                            image.cols, image.rows, excluded.cols, excluded.rows,
                                            cv::typeToString(excluded.type())));
  }
  // The margin, grown once at level 0 into the extractor's own buffer (the caller's mask is not ours to change).
  const int side = 2 * kExcludedMargin + 1;
  cv::dilate(excluded, levels_[0].excluded, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)));
  ForEachLevel([&](int l) {
    Level& level = levels_[static_cast<std::size_t>(l)];
    // Where Extract's keypoints lie, for SelectAndDescribe to find the corners it described already.
    level.extracted_at.clear();
    for (std::size_t i = 0; i < level.extracted.keypoints.size(); ++i) {
      const cv::Point2f& pt = level.extracted.keypoints[i].pt;
      level.extracted_at.emplace_back(static_cast<int>(pt.y) * level.image.cols + static_cast<int>(pt.x),
                                      static_cast<int>(i));
    }
    std::sort(level.extracted_at.begin(), level.extracted_at.end());
    if (Usable(level.image)) DetectCorners(l, excluded);
  });
  // A level whose part outside the mask has fewer corners than its share passes the rest on, to the finest
  // levels first (the most corners, the most precise positions).
  std::vector<int> budget = features_per_level_;
  int spare = 0;
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    const int corners = static_cast<int>(levels_[l].corners.size());
    if (corners < budget[l]) {
      spare += budget[l] - corners;
      budget[l] = corners;
    }
  }
  for (std::size_t l = 0; l < levels_.size() && spare > 0; ++l) {
    const int more = std::min(spare, static_cast<int>(levels_[l].corners.size()) - budget[l]);
    budget[l] += more;
    spare -= more;
  }
  ForEachLevel([&](int l) { SelectAndDescribe(l, budget[static_cast<std::size_t>(l)], &Level::outside); });
  Collect(&Level::outside, keypoints, descriptors);
}

void OrbExtractor::Collect(Described Level::*result, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) const {
  std::size_t total = 0;
  for (const Level& level : levels_) total += (level.*result).keypoints.size();
  keypoints.clear();
  keypoints.reserve(total);
  descriptors = cv::Mat(static_cast<int>(total), kDescriptorBytes, CV_8UC1);
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    const Described& described = levels_[l].*result;
    if (described.keypoints.empty()) continue;
    const int row = static_cast<int>(keypoints.size());
    described.descriptors.copyTo(descriptors.rowRange(row, row + described.descriptors.rows));
    for (cv::KeyPoint kp : described.keypoints) {
      kp.pt *= pyramid_.scale[l];
      keypoints.push_back(kp);
    }
  }
}

}  // namespace hoidslam::features
