#include "hoidslam/slam/match/matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <numeric>
#include <random>
#include <set>
#include <shared_mutex>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hoidslam/slam/data/map.h"

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::slam::matcher_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::shared_ptr<const Sensor> MakeSensor() {
  return Sensor::Make(core::CameraIntrinsics{}, 40.0, 3.0, features::ScalePyramid::Make(8, 1.2));
}

core::Pose RotationY(double degrees) {
  core::Pose T = core::Pose::Identity();
  T.linear() = Eigen::AngleAxisd(degrees * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T;
}

// T_cw of a camera at `centre` rotated by `degrees` about the world's y axis.
core::Pose CameraAt(const Eigen::Vector3d& centre, double degrees) {
  core::Pose T_wc = RotationY(degrees);
  T_wc.translation() = centre;
  return T_wc.inverse();
}

float WrapDegrees(double a) { return static_cast<float>(std::fmod(std::fmod(a, 360.0) + 360.0, 360.0)); }

// One view's keypoints as the test builds them, before they become a KeypointSet.
struct View {
  std::vector<cv::KeyPoint> keypoints;
  std::vector<std::uint8_t> descriptor_bytes;  // 32 per keypoint
  cv::Mat depth = cv::Mat::zeros(480, 640, CV_32FC1);

  int Add(const Eigen::Vector2d& uv, int level, float angle, const std::uint8_t* descriptor, double z) {
    keypoints.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.0F, angle, 1.0F, level);
    descriptor_bytes.insert(descriptor_bytes.end(), descriptor, descriptor + 32);
    if (z > 0.0) depth.at<float>(static_cast<int>(std::lround(uv.y())), static_cast<int>(std::lround(uv.x()))) =
        static_cast<float>(z);
    return static_cast<int>(keypoints.size()) - 1;
  }
  std::shared_ptr<const KeypointSet> Build(const std::shared_ptr<const Sensor>& sensor) const {
    cv::Mat d(static_cast<int>(keypoints.size()), 32, CV_8UC1);
    std::copy(descriptor_bytes.begin(), descriptor_bytes.end(), d.data);
    return std::make_shared<const KeypointSet>(sensor, keypoints, d, depth, cv::Mat());
  }
};

// Points on a 40 px lattice of view A at 1.5-4 m, seen again from view B (8 cm and 2° away), each with its own
// random descriptor (5 bits flipped in view B). Map points are made in keyframe A. One more point is seen in A
// but projects just left of B's image, where B has a keypoint with its descriptor: a decoy.
class MatcherTest : public ::testing::Test {
 protected:
  // `rotated`: points whose keypoint in view B turns by +90° instead of -5°. `duplicate`: view B gets a second
  // keypoint, 3 px away and identical, for one point (duplicated_).
  void Build(const std::set<int>& rotated = {}, bool duplicate = false) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_int_distribution<int> level(0, 2), byte(0, 255), bit(0, 255);
    const core::Pose T_wc_b = T_cw_b_.inverse();

    for (int v = 40; v <= 440; v += 40) {
      for (int u = 40; u <= 600; u += 40) {
        const double z = 1.5 + 2.5 * unit(rng);
        world_.push_back(sensor_->intrinsics.Unproject(u, v, z));  // view A is the world frame
      }
    }
    outside_ = static_cast<int>(world_.size());
    world_.push_back(T_wc_b * sensor_->intrinsics.Unproject(-4.0, 240.0, 2.0));

    View a, b;
    const int n = static_cast<int>(world_.size());
    b_index_.assign(static_cast<std::size_t>(n), -1);
    std::vector<int> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);  // view B lists its keypoints in another order
    std::vector<std::array<std::uint8_t, 32>> descriptors(static_cast<std::size_t>(n));
    std::vector<int> levels(static_cast<std::size_t>(n));
    std::vector<float> angles(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      for (auto& x : descriptors[k]) x = static_cast<std::uint8_t>(byte(rng));
      levels[k] = level(rng);
      angles[k] = static_cast<float>(360.0 * unit(rng));
      const Eigen::Vector2d uv = sensor_->camera.Project(world_[k]);
      ASSERT_TRUE(sensor_->InImage(uv.x(), uv.y())) << i;
      EXPECT_EQ(a.Add(uv, levels[k], angles[k], descriptors[k].data(), world_[k].z()), i);
    }
    for (const int i : order) {
      const auto k = static_cast<std::size_t>(i);
      const Eigen::Vector3d p_b = T_cw_b_ * world_[k];
      const Eigen::Vector2d uv = sensor_->camera.Project(p_b);
      std::array<std::uint8_t, 32> d = descriptors[k];
      const int flips = i == outside_ ? 3 : 5;
      for (int f = 0; f < flips; ++f) {
        const int at = bit(rng);
        d[static_cast<std::size_t>(at / 8)] ^= static_cast<std::uint8_t>(1U << (at % 8));
      }
      const float angle = WrapDegrees(angles[k] + (rotated.contains(i) ? 90.0 : -5.0));
      if (i == outside_) {
        ASSERT_LT(uv.x(), 0.0);
        decoy_ = b.Add(Eigen::Vector2d(1.0, uv.y()), levels[k], angle, d.data(), 0.0);
        continue;
      }
      if (p_b.z() <= 0.0 || !sensor_->InImage(uv.x(), uv.y())) continue;
      b_index_[k] = b.Add(uv, levels[k], angle, d.data(), p_b.z());
      ++num_visible_;
      if (duplicate && duplicated_ < 0 && uv.x() > 100.0 && uv.x() < 540.0) {
        duplicated_ = i;
        duplicate_ = b.Add(uv + Eigen::Vector2d(3.0, 0.0), levels[k], angle, d.data(), 0.0);
      }
    }
    ASSERT_GT(num_visible_, 120);
    ASSERT_LT(num_visible_, n - 1);  // some points leave view B

    set_a_ = a.Build(sensor_);
    set_b_ = b.Build(sensor_);
    keyframe_a_ = map_.CreateKeyFrame(0, 0.0, set_a_, T_cw_a_);
    for (int i = 0; i < n; ++i) points_.push_back(map_.CreateMapPoint(world_[static_cast<std::size_t>(i)], keyframe_a_, i));
    ASSERT_EQ(set_a_->num_with_depth(), n);
  }

  Frame LastFrame() const {
    Frame f(0, 0.0, set_a_);
    f.T_cw = T_cw_a_;
    for (std::size_t i = 0; i < points_.size(); ++i) f.map_points[i] = points_[i];
    return f;
  }
  Frame CurrentFrame() const {
    Frame f(1, 1.0 / 30.0, set_b_);
    f.T_cw = T_cw_b_;
    return f;
  }
  // The map points as predicted in view B.
  std::vector<ProjectedPoint> ProjectedIntoB() const {
    std::vector<ProjectedPoint> projected;
    for (const MapPoint* p : points_) {
      ProjectedPoint pp;
      if (ProjectIntoFrame(*p, T_cw_b_, *sensor_, 0.5, pp)) projected.push_back(pp);
    }
    return projected;
  }
  // Every point visible in B matched to its own keypoint, nothing else matched.
  void ExpectTrueMatches(const std::vector<MapPoint*>& matches, const std::set<int>& unmatched = {}) {
    std::vector<MapPoint*> expected(static_cast<std::size_t>(set_b_->size()), nullptr);
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (b_index_[i] >= 0 && !unmatched.contains(static_cast<int>(i))) {
        expected[static_cast<std::size_t>(b_index_[i])] = points_[i];
      }
    }
    for (std::size_t j = 0; j < expected.size(); ++j) {
      EXPECT_EQ(matches[j], expected[j]) << "keypoint " << j << (static_cast<int>(j) == decoy_ ? " (decoy)" : "");
    }
  }

  std::shared_ptr<const Sensor> sensor_ = MakeSensor();
  core::Pose T_cw_a_ = core::Pose::Identity();
  core::Pose T_cw_b_ = CameraAt(Eigen::Vector3d(0.08, 0.02, 0.03), 2.0);
  std::vector<Eigen::Vector3d> world_;
  std::vector<int> b_index_;  // per point, its keypoint in view B or -1
  int outside_ = -1;
  int decoy_ = -1;
  int duplicated_ = -1;
  int duplicate_ = -1;
  int num_visible_ = 0;
  std::shared_ptr<const KeypointSet> set_a_, set_b_;
  Map map_;
  KeyFrame* keyframe_a_ = nullptr;
  std::vector<MapPoint*> points_;
};

TEST_F(MatcherTest, SearchByProjectionFromLastFrameFindsTrueCorrespondences) {
  ASSERT_NO_FATAL_FAILURE(Build());
  const Frame last = LastFrame();
  Frame current = CurrentFrame();
  EXPECT_EQ(SearchByProjection(current, last, 7.0), num_visible_);
  // The point left of the image is not looked for, though the decoy at the border has its descriptor.
  ExpectTrueMatches(current.map_points);
  EXPECT_EQ(current.map_points[static_cast<std::size_t>(decoy_)], nullptr);
}

TEST_F(MatcherTest, SearchByProjectionWithWrongPoseAndSmallRadiusFindsNothing) {
  ASSERT_NO_FATAL_FAILURE(Build());
  const Frame last = LastFrame();
  Frame current = CurrentFrame();
  current.T_cw = RotationY(4.0) * T_cw_b_;  // predictions ~37 px off
  EXPECT_EQ(SearchByProjection(current, last, 2.0), 0);
  for (const MapPoint* p : current.map_points) EXPECT_EQ(p, nullptr);
  // The same prediction with a window wide enough finds them again.
  Frame wide = CurrentFrame();
  wide.T_cw = current.T_cw;
  EXPECT_GT(SearchByProjection(wide, last, 45.0), num_visible_ / 2);
}

TEST_F(MatcherTest, SearchByProjectionUsesOnlyGoodInliersAndFreeKeypoints) {
  ASSERT_NO_FATAL_FAILURE(Build());
  Frame last = LastFrame();
  for (std::size_t i = 0; i < points_.size(); i += 2) last.outlier[i] = 1;
  {
    std::unique_lock lock(map_.mutex());
    map_.ErasePoint(points_[1]);
  }
  Frame current = CurrentFrame();
  // A keypoint already matched to a point that keyframes see keeps its match: point `first` (odd, so it would
  // be searched for) loses its keypoint to point 0.
  int first = 3;
  while (b_index_[static_cast<std::size_t>(first)] < 0) first += 2;
  const auto taken = static_cast<std::size_t>(b_index_[static_cast<std::size_t>(first)]);
  current.map_points[taken] = points_[0];
  std::set<int> unmatched = {1, first};
  for (int i = 0; i < static_cast<int>(points_.size()); i += 2) unmatched.insert(i);
  int expected = 0;
  for (std::size_t i = 0; i < points_.size(); ++i) expected += b_index_[i] >= 0 && !unmatched.contains(static_cast<int>(i));
  EXPECT_EQ(SearchByProjection(current, last, 7.0), expected);
  std::vector<MapPoint*> matches = current.map_points;
  ASSERT_EQ(matches[taken], points_[0]);
  matches[taken] = nullptr;
  ExpectTrueMatches(matches, unmatched);
}

TEST_F(MatcherTest, SearchByProjectionDropsMatchesWithInconsistentRotation) {
  ASSERT_NO_FATAL_FAILURE(Build({20, 50, 80}));
  ASSERT_GE(b_index_[20], 0);
  ASSERT_GE(b_index_[50], 0);
  ASSERT_GE(b_index_[80], 0);
  const Frame last = LastFrame();
  Frame current = CurrentFrame();
  EXPECT_EQ(SearchByProjection(current, last, 7.0), num_visible_ - 3);
  ExpectTrueMatches(current.map_points, {20, 50, 80});
}

TEST_F(MatcherTest, SearchByProjectionOfProjectedPoints) {
  ASSERT_NO_FATAL_FAILURE(Build({}, true));
  ASSERT_GE(duplicated_, 0);
  const std::vector<ProjectedPoint> projected = ProjectedIntoB();
  ASSERT_EQ(static_cast<int>(projected.size()), num_visible_);  // the outside point is not among them
  Frame current = CurrentFrame();
  // Two identical keypoints of one level for one point: ambiguous, left unmatched.
  EXPECT_EQ(SearchByProjection(current, projected, 3.0), num_visible_ - 1);
  ExpectTrueMatches(current.map_points, {duplicated_});
  EXPECT_EQ(current.map_points[static_cast<std::size_t>(duplicate_)], nullptr);
  EXPECT_EQ(current.map_points[static_cast<std::size_t>(decoy_)], nullptr);

  // A second pass finds nothing new: every keypoint that could match is taken.
  EXPECT_EQ(SearchByProjection(current, projected, 3.0), 0);
}

TEST_F(MatcherTest, SearchByProjectionKeepsToTheDescriptorLimitItIsGiven) {
  ASSERT_NO_FATAL_FAILURE(Build());
  const std::vector<ProjectedPoint> projected = ProjectedIntoB();
  // View B's descriptors are 5 bit flips off view A's (fewer bits where a flip undid another).
  Frame strict = CurrentFrame();
  const int close = SearchByProjection(strict, projected, 3.0, 4);
  EXPECT_LT(close, num_visible_ / 2);
  int within = 0;
  for (int j = 0; j < set_b_->size(); ++j) {
    const MapPoint* p = strict.map_points[static_cast<std::size_t>(j)];
    if (p == nullptr) continue;
    EXPECT_LE(DescriptorDistance(*p, *set_b_, j), 4) << "keypoint " << j;
    ++within;
  }
  EXPECT_EQ(within, close);
  Frame enough = CurrentFrame();
  EXPECT_EQ(SearchByProjection(enough, projected, 3.0, 5), num_visible_);
  ExpectTrueMatches(enough.map_points);
}

TEST_F(MatcherTest, SearchByDescriptorMatchesByDescriptorAlone) {
  ASSERT_NO_FATAL_FAILURE(Build());
  std::vector<MapPoint*> matches;
  EXPECT_EQ(SearchByDescriptor(*keyframe_a_, CurrentFrame(), matches), num_visible_ + 1);
  ASSERT_EQ(static_cast<int>(matches.size()), set_b_->size());
  // Position plays no part: the decoy carries the outside point's descriptor and gets it.
  EXPECT_EQ(matches[static_cast<std::size_t>(decoy_)], points_[static_cast<std::size_t>(outside_)]);
  matches[static_cast<std::size_t>(decoy_)] = nullptr;
  ExpectTrueMatches(matches);
}

// The direct index of n keypoints: keypoint i under node node_of(i).
bow::FeatureVector DirectIndex(int n, const std::function<bow::NodeId(int)>& node_of) {
  std::map<bow::NodeId, std::vector<int>> nodes;
  for (int i = 0; i < n; ++i) nodes[node_of(i)].push_back(i);
  bow::FeatureVector features;
  for (auto& [node, keypoints] : nodes) features.push_back({node, std::move(keypoints)});
  return features;
}

TEST_F(MatcherTest, SearchByBoWComparesOnlyKeypointsUnderTheSameNode) {
  ASSERT_NO_FATAL_FAILURE(Build());
  map_.IndexKeyFrame(keyframe_a_, {{}, DirectIndex(set_a_->size(), [](int) { return 5U; })});
  // Every keypoint of both under one node: the same matches as comparing every descriptor.
  std::vector<MapPoint*> all, guided;
  SearchByDescriptor(*keyframe_a_, CurrentFrame(), all);
  EXPECT_EQ(SearchByBoW(*keyframe_a_, CurrentFrame(), DirectIndex(set_b_->size(), [](int) { return 5U; }), guided),
            num_visible_ + 1);
  EXPECT_EQ(guided, all);
  // The frame's odd keypoints under another node: only its even ones are matched, each to what it was before.
  const int matched = SearchByBoW(*keyframe_a_, CurrentFrame(),
                                  DirectIndex(set_b_->size(), [](int j) { return j % 2 == 0 ? 5U : 6U; }), guided);
  EXPECT_GT(matched, 0);
  EXPECT_LT(matched, num_visible_);
  for (std::size_t j = 0; j < guided.size(); ++j) {
    if (j % 2 == 1) {
      EXPECT_EQ(guided[j], nullptr) << j;
    } else if (guided[j] != nullptr) {
      EXPECT_EQ(guided[j], all[j]) << j;
    }
  }
}

TEST_F(MatcherTest, SearchByDescriptorRejectsAmbiguousMatches) {
  ASSERT_NO_FATAL_FAILURE(Build({}, true));
  std::vector<MapPoint*> matches;
  EXPECT_EQ(SearchByDescriptor(*keyframe_a_, CurrentFrame(), matches), num_visible_);
  EXPECT_EQ(matches[static_cast<std::size_t>(duplicate_)], nullptr);
  matches[static_cast<std::size_t>(decoy_)] = nullptr;
  ExpectTrueMatches(matches, {duplicated_});
}

TEST_F(MatcherTest, SearchByDescriptorSkipsBadPoints) {
  ASSERT_NO_FATAL_FAILURE(Build());
  {
    std::unique_lock lock(map_.mutex());
    for (int i = 0; i < 10; ++i) map_.ErasePoint(points_[static_cast<std::size_t>(i)]);
  }
  std::vector<MapPoint*> matches;
  int visible_erased = 0;
  for (int i = 0; i < 10; ++i) visible_erased += b_index_[static_cast<std::size_t>(i)] >= 0;
  EXPECT_EQ(SearchByDescriptor(*keyframe_a_, CurrentFrame(), matches), num_visible_ + 1 - visible_erased);
  matches[static_cast<std::size_t>(decoy_)] = nullptr;
  ExpectTrueMatches(matches, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9});
}

// --- NearestTwo ---

// A descriptor `bits` Hamming bits from the all-zero one: its first `bits` bits set.
std::array<std::uint8_t, 32> BitsFromZero(int bits) {
  std::array<std::uint8_t, 32> descriptor{};
  for (int b = 0; b < bits; ++b) descriptor[static_cast<std::size_t>(b / 8)] |= static_cast<std::uint8_t>(1U << (b % 8));
  return descriptor;
}

TEST(NearestTwo, KeepsTheNearestAndTheSecondNearestDistance) {
  const std::array<std::uint8_t, 32> zero{};
  NearestTwo nearest(zero.data());
  EXPECT_EQ(nearest.best(), -1);
  EXPECT_EQ(nearest.best_distance(), 256);
  EXPECT_EQ(nearest.second_distance(), 256);
  const auto offer = [&](int index, int bits) {
    const std::array<std::uint8_t, 32> candidate = BitsFromZero(bits);
    nearest.Offer(index, candidate.data());
  };
  offer(7, 30);
  EXPECT_EQ(nearest.best(), 7);
  EXPECT_EQ(nearest.second_distance(), 256);
  offer(8, 10);
  offer(9, 20);
  offer(10, 10);  // as near as the nearest: the first offered stays the nearest, and the second is as near
  EXPECT_EQ(nearest.best(), 8);
  EXPECT_EQ(nearest.best_distance(), 10);
  EXPECT_EQ(nearest.second_distance(), 10);
}

TEST(NearestTwo, TakesANearestOnlyWithinItsLimit) {
  const std::array<std::uint8_t, 32> zero{};
  const std::array<std::uint8_t, 32> far = BitsFromZero(60), beyond = BitsFromZero(51), limit = BitsFromZero(50),
                                     near = BitsFromZero(40);
  NearestTwo nearest(zero.data(), 50);
  nearest.Offer(1, far.data());
  EXPECT_EQ(nearest.best(), -1);
  EXPECT_EQ(nearest.best_distance(), 51);
  EXPECT_EQ(nearest.second_distance(), 60);
  nearest.Offer(2, limit.data());
  EXPECT_EQ(nearest.best(), 2);
  EXPECT_EQ(nearest.best_distance(), 50);
  EXPECT_EQ(nearest.second_distance(), 51);  // as if a candidate at 51 had been offered first
  nearest.Offer(3, beyond.data());
  nearest.Offer(4, near.data());
  EXPECT_EQ(nearest.best(), 4);
  EXPECT_EQ(nearest.best_distance(), 40);
  EXPECT_EQ(nearest.second_distance(), 50);
}

// --- KeepConsistentRotations ---

class RotationTest : public ::testing::Test {
 protected:
  // `count` matches with the given angle change.
  void Add(int count, float change) {
    for (int i = 0; i < count; ++i) {
      matches_.push_back(&point_);
      changes_.push_back(change);
    }
  }
  void AddUnmatched() {
    matches_.push_back(nullptr);
    changes_.push_back(std::numeric_limits<float>::quiet_NaN());  // never read
  }
  int Kept(std::size_t from, std::size_t to) const {
    return static_cast<int>(std::count(matches_.begin() + static_cast<std::ptrdiff_t>(from),
                                       matches_.begin() + static_cast<std::ptrdiff_t>(to), &point_));
  }

  MapPoint point_{0, Eigen::Vector3d::Zero(), 0, cv::Mat::zeros(1, 32, CV_8UC1), cv::Vec3b()};
  std::vector<MapPoint*> matches_;
  std::vector<float> changes_;
};

TEST_F(RotationTest, KeepsTheThreeFullestBins) {
  Add(30, 5.0F);    // bin 0
  AddUnmatched();
  Add(10, 17.0F);   // bin 1
  Add(5, 29.0F);    // bin 2
  Add(2, 180.0F);   // bin 15: the fourth fullest
  AddUnmatched();
  KeepConsistentRotations(matches_, changes_);
  EXPECT_EQ(Kept(0, 31), 30);
  EXPECT_EQ(Kept(31, 46), 15);
  EXPECT_EQ(Kept(46, 48), 0);
  EXPECT_EQ(matches_[30], nullptr);
  EXPECT_EQ(matches_[48], nullptr);
}

TEST_F(RotationTest, DropsBinsBelowATenthOfTheFullest) {
  Add(40, 5.0F);
  Add(3, 100.0F);  // 3 < 4
  Add(4, 200.0F);  // 4 >= 4
  KeepConsistentRotations(matches_, changes_);
  EXPECT_EQ(Kept(0, 40), 40);
  EXPECT_EQ(Kept(40, 43), 0);
  EXPECT_EQ(Kept(43, 47), 4);
}

TEST_F(RotationTest, WrapsAngleChanges) {
  Add(20, -5.0F);   // = 355°
  Add(20, 355.5F);  // the same bin
  Add(5, 170.0F + 720.0F);
  Add(1, 90.0F);    // third fullest, but below a tenth of 40
  KeepConsistentRotations(matches_, changes_);
  EXPECT_EQ(Kept(0, 45), 45);
  EXPECT_EQ(Kept(45, 46), 0);
}

// --- ProjectIntoFrame ---

class ProjectIntoFrameTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // A point 2 m in front of the origin, seen at level 0 along +z.
    View view;
    const std::array<std::uint8_t, 32> d{};
    view.Add(Eigen::Vector2d(sensor_->camera.cx, sensor_->camera.cy), 0, 0.0F, d.data(), 2.0);
    view.Add(Eigen::Vector2d(10, 10), 0, 0.0F, d.data(), 0.0);
    KeyFrame* kf = map_.CreateKeyFrame(0, 0.0, view.Build(sensor_), core::Pose::Identity());
    point_ = map_.CreateMapPoint(Eigen::Vector3d(0, 0, 2), kf, 0);
  }
  bool Project(const core::Pose& T_cw, double min_view_cos = 0.5) {
    return ProjectIntoFrame(*point_, T_cw, *sensor_, min_view_cos, projected_);
  }
  // A camera `distance` from the point, looking at it from `degrees` off its normal.
  static core::Pose LookingAtPoint(double degrees, double distance) {
    const double a = degrees * kDeg;
    const Eigen::Vector3d z(std::sin(a), 0.0, std::cos(a));
    core::Pose T_wc = core::Pose::Identity();
    T_wc.linear().col(0) = Eigen::Vector3d(std::cos(a), 0.0, -std::sin(a));
    T_wc.linear().col(1) = Eigen::Vector3d::UnitY();
    T_wc.linear().col(2) = z;
    T_wc.translation() = Eigen::Vector3d(0, 0, 2) - distance * z;
    return T_wc.inverse();
  }

  std::shared_ptr<const Sensor> sensor_ = MakeSensor();
  Map map_;
  MapPoint* point_ = nullptr;
  ProjectedPoint projected_;
};

TEST_F(ProjectIntoFrameTest, ProjectsAVisiblePoint) {
  ASSERT_NEAR(point_->max_distance(), 2.4, 1e-6);
  ASSERT_NEAR(point_->min_distance(), 0.8 * 2.0 / std::pow(1.2, 7), 1e-6);
  ASSERT_TRUE(Project(core::Pose::Identity()));
  EXPECT_EQ(projected_.point, point_);
  EXPECT_NEAR(projected_.uv.x(), sensor_->camera.cx, 1e-9);
  EXPECT_NEAR(projected_.uv.y(), sensor_->camera.cy, 1e-9);
  EXPECT_NEAR(projected_.ur, sensor_->camera.cx - 40.0 / 2.0, 1e-9);
  EXPECT_EQ(projected_.level, 0);
  EXPECT_NEAR(projected_.view_cos, 1.0, 1e-12);
  // Nearer, it is expected at a coarser level: 2 m / 1.5 m = 1.2^1.58.
  ASSERT_TRUE(Project(CameraAt(Eigen::Vector3d(0, 0, 0.5), 0.0)));
  EXPECT_EQ(projected_.level, 2);
}

TEST_F(ProjectIntoFrameTest, RejectsPointsBehindTheCameraOrOutsideTheImage) {
  EXPECT_FALSE(Project(RotationY(180.0)));
  EXPECT_FALSE(Project(CameraAt(Eigen::Vector3d(0, 0, 2.5), 0.0)));  // the camera passed it
  EXPECT_FALSE(Project(RotationY(45.0)));  // in range and head-on, but 535 px off centre
  EXPECT_TRUE(Project(RotationY(10.0)));
}

TEST_F(ProjectIntoFrameTest, RejectsPointsOutsideTheDistanceRange) {
  EXPECT_FALSE(Project(CameraAt(Eigen::Vector3d(0, 0, -0.5), 0.0)));  // 2.5 m > 2.4 m
  EXPECT_TRUE(Project(CameraAt(Eigen::Vector3d(0, 0, -0.3), 0.0)));   // 2.3 m
  EXPECT_FALSE(Project(CameraAt(Eigen::Vector3d(0, 0, 1.6), 0.0)));   // 0.4 m < 0.447 m
  EXPECT_TRUE(Project(CameraAt(Eigen::Vector3d(0, 0, 1.5), 0.0)));    // 0.5 m
  EXPECT_EQ(projected_.level, 7);
}

TEST_F(ProjectIntoFrameTest, RejectsObliqueViews) {
  ASSERT_TRUE(Project(LookingAtPoint(40.0, 2.0)));
  EXPECT_NEAR(projected_.view_cos, std::cos(40.0 * kDeg), 1e-9);
  EXPECT_NEAR(projected_.uv.x(), sensor_->camera.cx, 1e-9);  // looked at head-on
  EXPECT_FALSE(Project(LookingAtPoint(70.0, 2.0)));
  EXPECT_TRUE(Project(LookingAtPoint(70.0, 2.0), 0.3));
}

}  // namespace
}  // namespace hoidslam::slam::matcher_test
