#include "hoidslam/features/orb_extractor.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/features/quadtree.h"
#include "support/shared_data.h"

namespace hoidslam::features {
namespace {

constexpr const char* kTumFrame = "data/tum/fr3_walking_xyz_pair/rgb/1341846313.592026.png";

// Random filled rectangles and discs of random grey, spread uniformly, over a noisy background: texture with
// corners at many scales and no repeated structure. `contrast` scales the grey levels about mid-grey.
cv::Mat TexturedImage(cv::Size size, unsigned seed, double contrast = 1.0) {
  std::mt19937 rng(seed);
  cv::Mat image(size, CV_8UC1);
  cv::randu(image, 100, 156);
  std::uniform_int_distribution<int> px(-20, size.width + 20);
  std::uniform_int_distribution<int> py(-20, size.height + 20);
  std::uniform_int_distribution<int> extent(5, 45);
  std::uniform_int_distribution<int> grey(0, 255);
  const int shapes = size.area() / 200;
  for (int i = 0; i < shapes; ++i) {
    const cv::Scalar colour(128.0 + contrast * (grey(rng) - 128));
    if (i % 2 == 0) {
      cv::rectangle(image, cv::Rect(px(rng), py(rng), extent(rng), extent(rng)), colour, cv::FILLED);
    } else {
      cv::circle(image, cv::Point(px(rng), py(rng)), extent(rng) / 2, colour, cv::FILLED, cv::LINE_AA);
    }
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.7);
  return image;
}

struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

Features Extract(const cv::Mat& gray, const core::OrbOptions& options = {}) {
  OrbExtractor extractor(options);
  Features f;
  extractor.Extract(gray, f.keypoints, f.descriptors);
  return f;
}

// Mutual nearest neighbours by Hamming distance, at most `max_distance` bits apart: pairs (index in a, in b).
std::vector<std::pair<int, int>> MatchMutual(const cv::Mat& a, const cv::Mat& b, int max_distance) {
  const auto nearest = [](const cv::Mat& from, const cv::Mat& to, int i) {
    int best = -1;
    int best_distance = 257;
    for (int j = 0; j < to.rows; ++j) {
      const int d = DescriptorDistance(from.ptr(i), to.ptr(j));
      if (d < best_distance) {
        best_distance = d;
        best = j;
      }
    }
    return std::pair{best, best_distance};
  };
  std::vector<std::pair<int, int>> matches;
  for (int i = 0; i < a.rows; ++i) {
    const auto [j, d] = nearest(a, b, i);
    if (j >= 0 && d <= max_distance && nearest(b, a, j).first == i) matches.emplace_back(i, j);
  }
  return matches;
}

// Difference of two angles in degrees, in [0, 180].
double AngleDifference(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// ---- scale pyramid and options ------------------------------------------------------------------------------------

TEST(ScalePyramid, FactorsArePowersOfTheScaleFactor) {
  const ScalePyramid p = ScalePyramid::Make(8, 1.2);
  ASSERT_EQ(p.levels(), 8);
  for (int l = 0; l < 8; ++l) {
    const auto i = static_cast<std::size_t>(l);
    const double s = std::pow(1.2, l);
    EXPECT_NEAR(p.scale[i], s, 1e-5 * s);
    EXPECT_NEAR(p.inv_scale[i], 1.0 / s, 1e-6);
    EXPECT_NEAR(p.sigma2[i], s * s, 1e-5 * s * s);
    EXPECT_NEAR(p.inv_sigma2[i], 1.0 / (s * s), 1e-6);
  }
  EXPECT_EQ(p.scale[0], 1.0F);
  EXPECT_NEAR(p.scale[7], 3.5831808, 1e-5);
  EXPECT_EQ(ScalePyramid::Make(1, 2.0).levels(), 1);
  EXPECT_THROW(ScalePyramid::Make(0, 1.2), std::invalid_argument);
  EXPECT_THROW(ScalePyramid::Make(8, 1.0), std::invalid_argument);
}

TEST(OrbExtractor, BadOptionsThrowInputError) {
  const auto with = [](auto change) {
    core::OrbOptions o;
    change(o);
    return o;
  };
  EXPECT_THROW(OrbExtractor(with([](auto& o) { o.n_features = 0; })), core::InputError);
  EXPECT_THROW(OrbExtractor(with([](auto& o) { o.scale_factor = 1.0; })), core::InputError);
  EXPECT_THROW(OrbExtractor(with([](auto& o) { o.n_levels = 0; })), core::InputError);
  EXPECT_THROW(OrbExtractor(with([](auto& o) { o.ini_th_fast = 0; })), core::InputError);
  EXPECT_THROW(OrbExtractor(with([](auto& o) { o.min_th_fast = 21; })), core::InputError);
  EXPECT_THROW(OrbExtractor(with([](auto& o) { o.dim_mean = -1.0; })), core::InputError);
  EXPECT_THROW(OrbExtractor(with([](auto& o) { o.max_gain = 0.5; })), core::InputError);
  EXPECT_NO_THROW(OrbExtractor(core::OrbOptions{}));
}

TEST(OrbExtractor, FeaturesPerLevelFollowOrbSlamsSeries) {
  const OrbExtractor extractor(core::OrbOptions{});
  const std::vector<int>& n = extractor.features_per_level();
  ASSERT_EQ(n.size(), 8U);
  // 1000 · (1 - 1/1.2) / (1 - 1.2^-8) = 217.1, then each level 1/1.2 of the one before; the last takes the rest.
  const std::vector<int> expected = {217, 181, 151, 126, 105, 87, 73, 60};
  EXPECT_EQ(n, expected);
  int sum = 0;
  for (int k : n) sum += k;
  EXPECT_EQ(sum, 1000);

  core::OrbOptions few;
  few.n_features = 3;
  few.n_levels = 8;
  const OrbExtractor small(few);
  sum = 0;
  for (int k : small.features_per_level()) {
    EXPECT_GE(k, 0);
    sum += k;
  }
  EXPECT_EQ(sum, 3);
}

// ---- input checks -------------------------------------------------------------------------------------------------

TEST(OrbExtractor, RejectsEmptyAndNonGrayImages) {
  OrbExtractor extractor(core::OrbOptions{});
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  EXPECT_THROW(extractor.Extract(cv::Mat(), keypoints, descriptors), std::invalid_argument);
  try {
    extractor.Extract(cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(0)), keypoints, descriptors);
    FAIL() << "a colour image was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("CV_8UC1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("CV_8UC3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(extractor.Extract(cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)), keypoints, descriptors),
               std::invalid_argument);
}

TEST(OrbExtractor, SmallAndFlatImagesGiveFewOrNoKeypoints) {
  OrbExtractor extractor(core::OrbOptions{});
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(20, 20), cv::Size(38, 200), cv::Size(45, 45)}) {
    extractor.Extract(TexturedImage(size, 1), keypoints, descriptors);
    EXPECT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));
    for (const cv::KeyPoint& kp : keypoints) {
      EXPECT_GE(kp.pt.x, 19.0F);
      EXPECT_LT(kp.pt.x, static_cast<float>(size.width - 19));
    }
    if (size.width <= 38) {
      EXPECT_TRUE(keypoints.empty()) << size;
    }
  }
  extractor.Extract(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)), keypoints, descriptors);
  EXPECT_TRUE(keypoints.empty());
  EXPECT_EQ(descriptors.rows, 0);

  // More levels than the image has room for: the small ones simply give nothing.
  core::OrbOptions deep;
  deep.n_levels = 30;
  OrbExtractor deep_extractor(deep);
  deep_extractor.Extract(TexturedImage({640, 480}, 2), keypoints, descriptors);
  EXPECT_GT(keypoints.size(), 300U);
  for (const cv::KeyPoint& kp : keypoints) EXPECT_LT(kp.octave, 16);  // 1.2^16 ≈ 18: level 16 is 35 px high
}

// ---- what comes out -----------------------------------------------------------------------------------------------

TEST(OrbExtractor, TexturedImageGivesAboutNFeatures) {
  for (const int n : {1000, 500, 2000}) {
    core::OrbOptions options;
    options.n_features = n;
    const Features f = Extract(TexturedImage({640, 480}, 3), options);
    EXPECT_LE(static_cast<int>(f.keypoints.size()), n);
    EXPECT_GE(static_cast<int>(f.keypoints.size()), 0.9 * n);
    EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
    EXPECT_EQ(f.descriptors.cols, 32);
    EXPECT_EQ(f.descriptors.type(), CV_8UC1);
  }
}

TEST(OrbExtractor, KeypointFieldsAreInRange) {
  const cv::Mat image = TexturedImage({640, 480}, 4);
  OrbExtractor extractor(core::OrbOptions{});
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.Extract(image, keypoints, descriptors);
  const ScalePyramid& p = extractor.pyramid();
  std::vector<int> per_level(8, 0);
  int previous_octave = 0;
  for (const cv::KeyPoint& kp : keypoints) {
    ASSERT_GE(kp.octave, 0);
    ASSERT_LT(kp.octave, 8);
    const auto l = static_cast<std::size_t>(kp.octave);
    ++per_level[l];
    EXPECT_GE(kp.octave, previous_octave) << "keypoints come level by level";
    previous_octave = kp.octave;
    EXPECT_FLOAT_EQ(kp.size, 31.0F * p.scale[l]);
    EXPECT_GE(kp.angle, 0.0F);
    EXPECT_LT(kp.angle, 360.0F);
    EXPECT_GE(kp.response, 7.0F);  // minThFAST
    // At least 19 px of the level image on every side.
    const float level_x = kp.pt.x * p.inv_scale[l];
    const float level_y = kp.pt.y * p.inv_scale[l];
    const float level_w = std::round(640.0F * p.inv_scale[l]);
    const float level_h = std::round(480.0F * p.inv_scale[l]);
    EXPECT_GE(level_x, 19.0F - 1e-3F);
    EXPECT_GE(level_y, 19.0F - 1e-3F);
    EXPECT_LE(level_x, level_w - 20.0F + 1e-3F);
    EXPECT_LE(level_y, level_h - 20.0F + 1e-3F);
    // Integer level pixels.
    EXPECT_NEAR(level_x, std::round(level_x), 1e-3F);
  }
  for (std::size_t l = 0; l < 8; ++l) {
    EXPECT_LE(per_level[l], extractor.features_per_level()[l]);
    EXPECT_GE(per_level[l], 0.9 * extractor.features_per_level()[l]) << "level " << l;
  }
}

TEST(OrbExtractor, KeypointsSpreadOverUniformTexture) {
  const Features f = Extract(TexturedImage({640, 480}, 5));
  int quadrant[2][2] = {};
  for (const cv::KeyPoint& kp : f.keypoints) ++quadrant[kp.pt.y < 240 ? 0 : 1][kp.pt.x < 320 ? 0 : 1];
  for (const auto& row : quadrant) {
    for (const int count : row) EXPECT_GE(count, 0.2 * static_cast<double>(f.keypoints.size()));
  }
}

TEST(OrbExtractor, LowContrastHalfStillGetsItsShare) {
  // Left half full contrast, right half at a fifth.
  cv::Mat image = TexturedImage({640, 480}, 6);
  TexturedImage({640, 480}, 7, 0.2).colRange(320, 640).copyTo(image.colRange(320, 640));
  const Features f = Extract(image);
  ASSERT_GE(f.keypoints.size(), 900U);
  const auto right_share = [](const std::vector<cv::KeyPoint>& keypoints) {
    const auto right = std::count_if(keypoints.begin(), keypoints.end(), [](const auto& kp) { return kp.pt.x >= 320; });
    return static_cast<double>(right) / static_cast<double>(keypoints.size());
  };
  // The strongest FAST corners alone would leave the right half nearly bare.
  std::vector<cv::KeyPoint> strongest;
  cv::FAST(image, strongest, 7, true);
  cv::KeyPointsFilter::retainBest(strongest, static_cast<int>(f.keypoints.size()));
  EXPECT_LT(right_share(strongest), 0.1);
  EXPECT_GT(right_share(f.keypoints), 0.25);
}

TEST(OrbExtractor, DescriptorBitsAreInformative) {
  const Features f = Extract(TexturedImage({640, 480}, 8));
  ASSERT_GT(f.descriptors.rows, 500);
  std::vector<int> ones(256, 0);
  for (int r = 0; r < f.descriptors.rows; ++r) {
    for (int b = 0; b < 256; ++b)
      ones[static_cast<std::size_t>(b)] += (f.descriptors.at<std::uint8_t>(r, b / 8) >> (b % 8)) & 1;
  }
  // Every test is sometimes true and sometimes false, and on average about half are.
  double total = 0.0;
  for (const int k : ones) {
    EXPECT_GT(k, f.descriptors.rows / 20);
    EXPECT_LT(k, f.descriptors.rows - f.descriptors.rows / 20);
    total += k;
  }
  EXPECT_NEAR(total / (256.0 * f.descriptors.rows), 0.5, 0.1);
}

// ---- determinism ----------------------------------------------------------------------------------------------------

void ExpectIdentical(const Features& a, const Features& b) {
  ASSERT_EQ(a.keypoints.size(), b.keypoints.size());
  for (std::size_t i = 0; i < a.keypoints.size(); ++i) {
    EXPECT_EQ(a.keypoints[i].pt, b.keypoints[i].pt) << i;
    EXPECT_EQ(a.keypoints[i].angle, b.keypoints[i].angle) << i;
    EXPECT_EQ(a.keypoints[i].response, b.keypoints[i].response) << i;
    EXPECT_EQ(a.keypoints[i].octave, b.keypoints[i].octave) << i;
  }
  ASSERT_EQ(a.descriptors.size(), b.descriptors.size());
  EXPECT_EQ(cv::norm(a.descriptors, b.descriptors, cv::NORM_HAMMING), 0.0);
}

TEST(OrbExtractor, SameImageGivesSameFeatures) {
  const cv::Mat image = TexturedImage({640, 480}, 9);
  OrbExtractor extractor(core::OrbOptions{});
  Features first;
  extractor.Extract(image, first.keypoints, first.descriptors);
  const cv::Mat kept = first.descriptors;
  const cv::Mat kept_copy = first.descriptors.clone();
  // Another image in between: no state may leak from one frame to the next.
  Features other;
  extractor.Extract(TexturedImage({640, 480}, 10), other.keypoints, other.descriptors);
  Features second;
  extractor.Extract(image, second.keypoints, second.descriptors);
  ExpectIdentical(first, second);
  ExpectIdentical(first, Extract(image));  // a fresh extractor too
  // Descriptors handed out earlier are never overwritten.
  extractor.Extract(TexturedImage({640, 480}, 11), first.keypoints, first.descriptors);
  EXPECT_EQ(cv::norm(kept, kept_copy, cv::NORM_HAMMING), 0.0);
}

TEST(OrbExtractor, ThreadCountDoesNotChangeTheResult) {
  const cv::Mat image = TexturedImage({640, 480}, 18);
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const Features one = Extract(image);
  cv::setNumThreads(4);  // more tasks than this machine may have cores
  const Features four = Extract(image);
  cv::setNumThreads(threads);
  ExpectIdentical(one, four);
  ExpectIdentical(one, Extract(image));
}

TEST(OrbExtractor, ViewIntoLargerImageEqualsItsCopy) {
  // The pixels around a view must not leak into the features (e.g. through the smoothing's border).
  const cv::Mat large = TexturedImage({700, 540}, 12);
  const cv::Mat view = large(cv::Rect(30, 30, 640, 480));
  ExpectIdentical(Extract(view), Extract(view.clone()));
}

// The extractor's one FAST pass at iniThFAST plus passes at minThFAST over the empty cells must give exactly
// what one pass at minThFAST and the per-cell choice give (the comment in DetectLevel). Checked at level 0,
// where the level image is the input, with this reference written out plainly.
std::vector<cv::Point2f> ReferenceLevel0(const cv::Mat& gray, int n, const core::OrbOptions& options) {
  const cv::Rect search(16, 16, gray.cols - 32, gray.rows - 32);
  std::vector<cv::KeyPoint> fast;
  cv::FAST(gray(search), fast, options.min_th_fast, true);
  const int columns = search.width / 30;
  const int rows = search.height / 30;
  const int cell_w = (search.width + columns - 1) / columns;
  const int cell_h = (search.height + rows - 1) / rows;
  std::vector<Corner> all;
  std::vector<float> cell_max(static_cast<std::size_t>(columns * rows), 0.0F);
  const auto cell = [&](const Corner& c) {
    return static_cast<std::size_t>((c.y - 19) / cell_h * columns + (c.x - 19) / cell_w);
  };
  for (const cv::KeyPoint& kp : fast) {
    const Corner c{static_cast<int>(kp.pt.x) + 16, static_cast<int>(kp.pt.y) + 16, kp.response};
    if (c.x < 19 || c.y < 19 || c.x >= gray.cols - 19 || c.y >= gray.rows - 19) continue;
    all.push_back(c);
    cell_max[cell(c)] = std::max(cell_max[cell(c)], c.response);
  }
  std::vector<Corner> kept;
  const auto strong = static_cast<float>(options.ini_th_fast);
  for (const Corner& c : all) {
    if (c.response >= strong || cell_max[cell(c)] < strong) kept.push_back(c);
  }
  QuadtreeDistributor quadtree;
  std::vector<int> selected;
  quadtree.Distribute(kept, search, n, selected);
  std::vector<cv::Point2f> points;
  for (int i : selected) {
    points.emplace_back(static_cast<float>(kept[static_cast<std::size_t>(i)].x),
                        static_cast<float>(kept[static_cast<std::size_t>(i)].y));
  }
  return points;
}

void ExpectLevel0MatchesReference(const cv::Mat& gray) {
  const core::OrbOptions options;
  OrbExtractor extractor(options);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.Extract(gray, keypoints, descriptors);
  std::vector<cv::Point2f> level0;
  for (const cv::KeyPoint& kp : keypoints) {
    if (kp.octave == 0) level0.push_back(kp.pt);
  }
  EXPECT_EQ(level0, ReferenceLevel0(gray, extractor.features_per_level()[0], options));
}

TEST(OrbExtractor, CellThresholdsEqualOnePassAtTheLowThreshold) {
  // The low-contrast half has cells with corners at minThFAST only.
  cv::Mat image = TexturedImage({640, 480}, 13);
  TexturedImage({640, 480}, 14, 0.12).colRange(320, 640).copyTo(image.colRange(320, 640));
  ExpectLevel0MatchesReference(image);
}

TEST(OrbExtractor, CellThresholdsEqualOnePassAtTheLowThresholdOnTumFrame) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, kTumFrame);
  const cv::Mat gray = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(gray.empty());
  ExpectLevel0MatchesReference(gray);
}

// ---- invariance -----------------------------------------------------------------------------------------------------

struct Agreement {
  int matches = 0;
  int correct = 0;                   // mapped position within tolerance
  std::vector<double> angle_errors;  // of the correct ones, degrees
};

// Matches the features of `a` and `b` and checks them against the map a -> b (2×3 affine): correct when the
// keypoint of a, mapped, lands within 2.5 px (times its level's scale) of its match, and its angle turned by
// `turn` degrees agrees with the match's.
Agreement Compare(const Features& a, const Features& b, const cv::Matx23d& map, double turn) {
  Agreement result;
  for (const auto& [i, j] : MatchMutual(a.descriptors, b.descriptors, 64)) {
    const cv::KeyPoint& ka = a.keypoints[static_cast<std::size_t>(i)];
    const cv::KeyPoint& kb = b.keypoints[static_cast<std::size_t>(j)];
    ++result.matches;
    const cv::Vec3d p(ka.pt.x, ka.pt.y, 1.0);
    const cv::Vec2d mapped = map * p;
    const double tolerance = 2.5 * std::max(ka.size, kb.size) / 31.0;
    if (std::hypot(mapped[0] - kb.pt.x, mapped[1] - kb.pt.y) > tolerance) continue;
    ++result.correct;
    result.angle_errors.push_back(AngleDifference(ka.angle - turn, kb.angle));
  }
  return result;
}

void ExpectRotationInvariant(const cv::Mat& image, double degrees) {
  SCOPED_TRACE("rotation " + std::to_string(degrees));
  const cv::Point2f centre((image.cols - 1) * 0.5F, (image.rows - 1) * 0.5F);
  const cv::Mat rotation = cv::getRotationMatrix2D(centre, degrees, 1.0);
  cv::Mat rotated;
  cv::warpAffine(image, rotated, rotation, image.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  const Features a = Extract(image);
  const Features b = Extract(rotated);
  // getRotationMatrix2D turns counter-clockwise on screen; with y down that lowers the keypoint angles.
  const Agreement agreement = Compare(a, b, cv::Matx23d(rotation), degrees);
  EXPECT_GE(agreement.correct, 200);
  EXPECT_GE(agreement.correct, 0.6 * agreement.matches);
  ASSERT_FALSE(agreement.angle_errors.empty());
  EXPECT_LT(Median(agreement.angle_errors), 3.0);
  const auto within =
      std::count_if(agreement.angle_errors.begin(), agreement.angle_errors.end(), [](double e) { return e < 10.0; });
  EXPECT_GE(static_cast<double>(within), 0.9 * static_cast<double>(agreement.angle_errors.size()));
}

TEST(OrbExtractor, RotatedImageMatches) {
  const cv::Mat image = TexturedImage({480, 480}, 15);
  for (const double degrees : {30.0, 60.0, 90.0, 135.0}) ExpectRotationInvariant(image, degrees);
}

TEST(OrbExtractor, RotatedTumFrameMatches) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, kTumFrame);
  const cv::Mat gray = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(gray.empty());
  ExpectRotationInvariant(gray, 45.0);
}

void ExpectScaleInvariant(const cv::Mat& image) {
  cv::Mat small;
  cv::resize(image, small, cv::Size(), 1.0 / 1.2, 1.0 / 1.2, cv::INTER_AREA);
  const double sx = static_cast<double>(small.cols) / image.cols;
  const double sy = static_cast<double>(small.rows) / image.rows;
  // Pixel centres: x_small + 0.5 = (x + 0.5) · s.
  const cv::Matx23d map(sx, 0.0, 0.5 * sx - 0.5, 0.0, sy, 0.5 * sy - 0.5);
  const Agreement agreement = Compare(Extract(image), Extract(small), map, 0.0);
  EXPECT_GE(agreement.correct, 200);
  EXPECT_GE(agreement.correct, 0.6 * agreement.matches);
  ASSERT_FALSE(agreement.angle_errors.empty());
  EXPECT_LT(Median(agreement.angle_errors), 3.0);
}

TEST(OrbExtractor, DownscaledImageMatches) { ExpectScaleInvariant(TexturedImage({640, 480}, 16)); }

TEST(OrbExtractor, DownscaledTumFrameMatches) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, kTumFrame);
  const cv::Mat gray = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(gray.empty());
  ExpectScaleInvariant(gray);
}

TEST(OrbExtractor, TumFrameGivesAboutNFeatures) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, kTumFrame);
  const cv::Mat gray = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(gray.size(), cv::Size(640, 480));
  const Features f = Extract(gray);
  EXPECT_LE(f.keypoints.size(), 1000U);
  EXPECT_GE(f.keypoints.size(), 900U);
  int quadrant[2][2] = {};
  for (const cv::KeyPoint& kp : f.keypoints) ++quadrant[kp.pt.y < 240 ? 0 : 1][kp.pt.x < 320 ? 0 : 1];
  for (const auto& row : quadrant) {
    for (const int count : row) EXPECT_GE(count, 100);
  }
}

// A photo at half its contrast (as on the synthetic office's walls) under lights dimmed to a fifth, with the
// sensor's noise added after, as in the office's dark moments: FAST's absolute thresholds find few corners there;
// brightened, the lit image's keypoints come back with descriptors that match them (a gain changes no BRIEF test).
TEST(OrbExtractor, DimImageIsBrightenedAndMatchesTheLitOne) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, "data/textures/home.jpg");
  cv::Mat photo = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(photo.empty());
  cv::resize(photo, photo, {640, 480}, 0.0, 0.0, cv::INTER_AREA);
  cv::Mat lit;
  photo.convertTo(lit, CV_8U, 0.5, 40.0);
  cv::Mat noise(lit.size(), CV_16SC1);
  cv::randn(noise, 0.0, 1.0);
  cv::Mat dim;
  cv::Mat(lit * 0.2).convertTo(dim, CV_16SC1);
  cv::Mat(dim + noise).convertTo(dim, CV_8UC1);
  ASSERT_LT(cv::mean(dim)[0], core::OrbOptions{}.dim_mean);

  core::OrbOptions never;
  never.dim_mean = 0.0;
  const Features lit_features = Extract(lit);
  const Features unaided = Extract(dim, never);
  const Features brightened = Extract(dim);
  EXPECT_LT(unaided.keypoints.size(), 500U);
  EXPECT_GE(brightened.keypoints.size(), 900U);
  const cv::Matx23d identity(1, 0, 0, 0, 1, 0);
  const Agreement agreement = Compare(lit_features, brightened, identity, 0.0);
  EXPECT_GE(agreement.correct, 350);
  EXPECT_GE(agreement.correct, 2 * Compare(lit_features, unaided, identity, 0.0).correct);
}

TEST(OrbExtractor, BrightImagesAreLeftAlone) {
  core::OrbOptions never;
  never.dim_mean = 0.0;
  // Mean about 128: the same features with and without the option.
  const cv::Mat textured = TexturedImage({640, 480}, 21);
  ExpectIdentical(Extract(textured), Extract(textured, never));
}

// ---- descriptor distance --------------------------------------------------------------------------------------------

// ---- extraction outside a mask -------------------------------------------------------------------------------------

// Whether the keypoint lies on a marked pixel: the pixel its position rounds to, as the exclusion filter tests it.
bool OnMask(const cv::Mat& mask, const cv::KeyPoint& kp) {
  return mask.at<std::uint8_t>(static_cast<int>(std::lround(kp.pt.y)), static_cast<int>(std::lround(kp.pt.x))) != 0;
}

// People standing across most of a 640×480 frame: three tall boxes that leave a fifth of the image, in two
// narrow gaps between them and above two of them.
cv::Mat CrowdMask() {
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  for (const cv::Rect& person : {cv::Rect(0, 80, 200, 400), cv::Rect(230, 0, 200, 480), cv::Rect(470, 100, 170, 380)}) {
    mask(person).setTo(255);
  }
  return mask;
}

Features ExtractOutside(OrbExtractor& extractor, const cv::Mat& image, const cv::Mat& mask) {
  Features first;
  extractor.Extract(image, first.keypoints, first.descriptors);
  Features f;
  extractor.ExtractOutside(mask, f.keypoints, f.descriptors);
  return f;
}

TEST(OrbExtractor, ExtractOutsideAnEmptyMaskEqualsExtract) {
  const cv::Mat image = TexturedImage({640, 480}, 21);
  OrbExtractor extractor(core::OrbOptions{});
  ExpectIdentical(ExtractOutside(extractor, image, cv::Mat::zeros(480, 640, CV_8UC1)), Extract(image));
}

TEST(OrbExtractor, ExtractOutsideSpendsTheBudgetOnWhatTheMaskLeaves) {
  const cv::Mat image = TexturedImage({640, 480}, 22);
  const cv::Mat mask = CrowdMask();
  ASSERT_LT(cv::countNonZero(mask == 0), 0.25 * mask.total());
  OrbExtractor extractor(core::OrbOptions{});
  const Features all = Extract(image);
  const auto outside = [&](const std::vector<cv::KeyPoint>& keypoints) {
    return std::count_if(keypoints.begin(), keypoints.end(), [&](const auto& kp) { return !OnMask(mask, kp); });
  };
  // Spread over the whole image, about a fifth of the budget lands where the mask leaves.
  EXPECT_LT(outside(all.keypoints), 350);

  const Features f = ExtractOutside(extractor, image, mask);
  EXPECT_EQ(outside(f.keypoints), static_cast<long>(f.keypoints.size())) << "no keypoint on the mask";
  // Nor near it: a corner by a person's outline moves with the person.
  cv::Mat near;
  cv::dilate(mask, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(15, 15)));
  for (const cv::KeyPoint& kp : f.keypoints) ASSERT_FALSE(OnMask(near, kp)) << kp.pt;
  EXPECT_GE(f.keypoints.size(), 950U);
  EXPECT_LE(f.keypoints.size(), 1000U);
  EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
  // Spread over every part the mask leaves, not crowded into one.
  const auto in = [&](const cv::Rect& part) {
    return std::count_if(f.keypoints.begin(), f.keypoints.end(), [&](const auto& kp) { return part.contains(kp.pt); });
  };
  EXPECT_GT(in({200, 0, 30, 480}), 100) << "the gap between the first two people";
  EXPECT_GT(in({430, 0, 40, 480}), 100) << "the gap between the last two";
  EXPECT_GT(in({0, 0, 200, 80}), 100) << "above the first";
  EXPECT_GT(in({470, 0, 170, 100}), 100) << "above the last";
  // Every keypoint and descriptor is one the same corner gets from a full extraction: same position, angle and
  // bits, where both have it.
  int common = 0;
  for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
    for (std::size_t j = 0; j < all.keypoints.size(); ++j) {
      if (all.keypoints[j].pt != f.keypoints[i].pt || all.keypoints[j].octave != f.keypoints[i].octave) continue;
      ++common;
      EXPECT_EQ(all.keypoints[j].angle, f.keypoints[i].angle);
      EXPECT_EQ(DescriptorDistance(all.descriptors.row(static_cast<int>(j)), f.descriptors.row(static_cast<int>(i))),
                0);
    }
  }
  EXPECT_GT(common, 50);
}

TEST(OrbExtractor, ExtractOutsideSearchesCellsWhoseStrongCornersAreAllMasked) {
  // Full-contrast texture in 12 px stripes, faint texture in the 36 px between them: every cell has strong
  // corners, all on the stripes. With the stripes masked, only a second look at minThFAST finds the faint corners
  // between them (beyond the margin kept from the mask).
  cv::Mat image = TexturedImage({640, 480}, 23, 0.15);
  const cv::Mat strong = TexturedImage({640, 480}, 24);
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < 480; y += 48) {
    strong.rowRange(y, y + 12).copyTo(image.rowRange(y, y + 12));
    mask.rowRange(std::max(0, y - 3), std::min(480, y + 15)).setTo(255);
  }
  OrbExtractor extractor(core::OrbOptions{});
  const Features f = ExtractOutside(extractor, image, mask);
  for (const cv::KeyPoint& kp : f.keypoints) ASSERT_FALSE(OnMask(mask, kp));
  EXPECT_GE(f.keypoints.size(), 500U);
  const auto faint = std::count_if(f.keypoints.begin(), f.keypoints.end(), [](const auto& kp) { return kp.response < 20; });
  EXPECT_GT(faint, static_cast<long>(f.keypoints.size()) / 2);
}

TEST(OrbExtractor, ExtractOutsidePassesALevelsShortfallToOthers) {
  // Where the mask leaves only fine grain (pixel noise, which the coarse levels average away), the coarse levels
  // find few corners: the finest takes their share over.
  cv::Mat image = TexturedImage({640, 480}, 25);
  cv::Mat grain(480, 640, CV_8UC1);
  cv::randu(grain, 100, 156);
  cv::GaussianBlur(grain, grain, cv::Size(3, 3), 0.6);
  grain.colRange(0, 320).copyTo(image.colRange(0, 320));
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  mask.colRange(320, 640).setTo(255);
  OrbExtractor extractor(core::OrbOptions{});
  const Features f = ExtractOutside(extractor, image, mask);
  std::vector<int> per_level(8, 0);
  for (const cv::KeyPoint& kp : f.keypoints) ++per_level[static_cast<std::size_t>(kp.octave)];
  EXPECT_LT(per_level[7], extractor.features_per_level()[7]) << "the coarsest level has too few corners there";
  EXPECT_GT(per_level[0], extractor.features_per_level()[0]) << "the finest takes over what the others cannot use";
  EXPECT_GE(f.keypoints.size(), 990U);
}

TEST(OrbExtractor, ExtractOutsideIsDeterministicAndThreadIndependent) {
  const cv::Mat image = TexturedImage({640, 480}, 26);
  const cv::Mat mask = CrowdMask();
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  OrbExtractor one(core::OrbOptions{});
  const Features a = ExtractOutside(one, image, mask);
  cv::setNumThreads(4);
  OrbExtractor four(core::OrbOptions{});
  const Features b = ExtractOutside(four, image, mask);
  cv::setNumThreads(threads);
  ExpectIdentical(a, b);
  // Again after another frame: nothing of the earlier frame is reused.
  ExtractOutside(one, TexturedImage({640, 480}, 27), cv::Mat::zeros(480, 640, CV_8UC1));
  ExpectIdentical(a, ExtractOutside(one, image, mask));
}

TEST(OrbExtractor, ExtractOutsideDescribesEveryKeypointAsExtractDoes) {
  // ExtractOutside takes the orientation and descriptor of a corner the first extraction kept from there, and
  // computes the rest: both must be what Extract itself gives at that corner. An extraction with five times the
  // budget keeps nearly every corner, and is the reference.
  const cv::Mat image = TexturedImage({640, 480}, 28);
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(200, 60, 240, 420)).setTo(255);
  OrbExtractor extractor(core::OrbOptions{});
  Features first;
  extractor.Extract(image, first.keypoints, first.descriptors);
  Features outside;
  extractor.ExtractOutside(mask, outside.keypoints, outside.descriptors);
  core::OrbOptions many;
  many.n_features = 5000;
  const Features reference = Extract(image, many);
  const auto find = [](const Features& f, const cv::KeyPoint& kp) {
    for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
      if (f.keypoints[i].pt == kp.pt && f.keypoints[i].octave == kp.octave) return static_cast<int>(i);
    }
    return -1;
  };
  int reused = 0;
  int computed = 0;  // and found in the reference
  for (std::size_t i = 0; i < outside.keypoints.size(); ++i) {
    const cv::KeyPoint& kp = outside.keypoints[i];
    const int r = find(reference, kp);
    if (r < 0) continue;
    (find(first, kp) >= 0 ? reused : computed) += 1;
    EXPECT_EQ(kp.angle, reference.keypoints[static_cast<std::size_t>(r)].angle) << kp.pt;
    EXPECT_EQ(cv::norm(outside.descriptors.row(static_cast<int>(i)), reference.descriptors.row(r), cv::NORM_HAMMING), 0)
        << kp.pt;
  }
  EXPECT_GT(reused, 300) << "most corners outside the mask were kept the first time";
  EXPECT_GT(computed, 100) << "the budget freed by the mask goes to corners the first extraction did not keep";
}

TEST(OrbExtractor, ExtractOutsideNeedsAnExtractionAndAMaskOfTheImagesSize) {
  OrbExtractor extractor(core::OrbOptions{});
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  EXPECT_THROW(extractor.ExtractOutside(cv::Mat::zeros(480, 640, CV_8UC1), keypoints, descriptors), std::logic_error);
  extractor.Extract(TexturedImage({640, 480}, 28), keypoints, descriptors);
  EXPECT_THROW(extractor.ExtractOutside(cv::Mat::zeros(240, 320, CV_8UC1), keypoints, descriptors),
               std::invalid_argument);
  EXPECT_THROW(extractor.ExtractOutside(cv::Mat::zeros(480, 640, CV_32FC1), keypoints, descriptors),
               std::invalid_argument);
}

TEST(OrbExtractor, ExtractOutsideOnTumFrameKeepsNearlyTheBudget) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, kTumFrame);
  const cv::Mat gray = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  OrbExtractor extractor(core::OrbOptions{});
  const Features f = ExtractOutside(extractor, gray, CrowdMask());
  EXPECT_GE(f.keypoints.size(), 900U);
  for (const cv::KeyPoint& kp : f.keypoints) ASSERT_FALSE(OnMask(CrowdMask(), kp));
}

TEST(DescriptorDistance, CountsDifferingBits) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> byte(0, 255);
  // 33-byte rows, compared one byte in: the 32-byte descriptors need no alignment.
  std::vector<std::uint8_t> a(33);
  std::vector<std::uint8_t> b(33);
  for (int trial = 0; trial < 200; ++trial) {
    for (std::size_t i = 0; i < 33; ++i) {
      a[i] = static_cast<std::uint8_t>(byte(rng));
      b[i] = static_cast<std::uint8_t>(byte(rng));
    }
    int expected = 0;
    for (std::size_t i = 1; i < 33; ++i) expected += static_cast<int>(std::bitset<8>(a[i] ^ b[i]).count());
    EXPECT_EQ(DescriptorDistance(a.data() + 1, b.data() + 1), expected);
  }
  std::vector<std::uint8_t> zeros(32, 0);
  std::vector<std::uint8_t> ones(32, 0xFF);
  EXPECT_EQ(DescriptorDistance(zeros.data(), zeros.data()), 0);
  EXPECT_EQ(DescriptorDistance(zeros.data(), ones.data()), 256);
  ones[31] = 0x7F;
  EXPECT_EQ(DescriptorDistance(zeros.data(), ones.data()), 255);
}

TEST(DescriptorDistance, MatRowsAgreeWithOpenCvHamming) {
  cv::Mat d(50, 32, CV_8UC1);
  cv::randu(d, 0, 256);
  for (int i = 1; i < d.rows; ++i) {
    EXPECT_EQ(DescriptorDistance(d.row(0), d.row(i)), static_cast<int>(cv::norm(d.row(0), d.row(i), cv::NORM_HAMMING)));
  }
}

}  // namespace
}  // namespace hoidslam::features
