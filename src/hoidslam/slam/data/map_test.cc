#include "hoidslam/slam/data/map.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hoidslam/features/orb_extractor.h"
#include "support/geometry.h"

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::slam::map_test {
namespace {

std::shared_ptr<const Sensor> MakeSensor() {
  return Sensor::Make(core::CameraIntrinsics{}, 40.0, 3.0, features::ScalePyramid::Make(8, 1.2));
}

// A camera at centre `c` with no rotation, as T_cw.
core::Pose AtCentre(const Eigen::Vector3d& c) { return testing::PoseFromAxisAngle(Eigen::Vector3d::Zero(), -c); }

struct KeypointSpec {
  int n = 100;
  std::vector<int> with_depth;  // keypoint indices with a valid depth (2 m)
  std::vector<int> levels;      // per keypoint; empty: all level 0
  cv::Mat descriptors;          // empty: row i has every byte = i
};

KeypointSpec Spec(int n, std::vector<int> with_depth = {}, std::vector<int> levels = {}, cv::Mat descriptors = {}) {
  KeypointSpec spec;
  spec.n = n;
  spec.with_depth = std::move(with_depth);
  spec.levels = std::move(levels);
  spec.descriptors = std::move(descriptors);
  return spec;
}

// Keypoint i sits alone on a 10 px lattice, so painting its depth touches no other keypoint.
std::shared_ptr<const KeypointSet> MakeKeypoints(const std::shared_ptr<const Sensor>& sensor, const KeypointSpec& spec) {
  std::vector<cv::KeyPoint> kps;
  cv::Mat depth = cv::Mat::zeros(480, 640, CV_32FC1);
  for (int i = 0; i < spec.n; ++i) {
    const float x = 20.0F + 10.0F * static_cast<float>(i % 60);
    const float y = 20.0F + 10.0F * static_cast<float>(i / 60);
    const int level = spec.levels.empty() ? 0 : spec.levels[static_cast<std::size_t>(i)];
    kps.emplace_back(x, y, 31.0F, 0.0F, 1.0F, level);
  }
  for (const int i : spec.with_depth) {
    const cv::KeyPoint& kp = kps[static_cast<std::size_t>(i)];
    depth.at<float>(static_cast<int>(kp.pt.y), static_cast<int>(kp.pt.x)) = 2.0F;
  }
  cv::Mat descriptors = spec.descriptors;
  if (descriptors.empty()) {
    descriptors.create(spec.n, 32, CV_8UC1);
    for (int i = 0; i < spec.n; ++i) descriptors.row(i).setTo(static_cast<std::uint8_t>(i));
  }
  return std::make_shared<const KeypointSet>(sensor, std::move(kps), descriptors, depth, cv::Mat());
}

class MapTest : public ::testing::Test {
 protected:
  KeyFrame* AddKeyFrame(const core::Pose& T_cw, const KeypointSpec& spec = {}) {
    const std::uint64_t frame_id = 10 * map_.NumKeyFrames();
    return map_.CreateKeyFrame(frame_id, 0.1 * static_cast<double>(frame_id), MakeKeypoints(sensor_, spec), T_cw);
  }
  // A point seen by keypoint `index` of every keyframe listed (created in the first).
  MapPoint* SharedPoint(const std::vector<KeyFrame*>& keyframes, int index,
                        const Eigen::Vector3d& position = Eigen::Vector3d(0.0, 0.0, 5.0)) {
    MapPoint* p = map_.CreateMapPoint(position, keyframes.front(), index);
    for (std::size_t k = 1; k < keyframes.size(); ++k) map_.AddObservation(p, keyframes[k], index);
    return p;
  }
  // `count` points seen by both keyframes, at keypoints from `first_index` on.
  void SharePoints(KeyFrame* a, KeyFrame* b, int first_index, int count) {
    for (int i = first_index; i < first_index + count; ++i) SharedPoint({a, b}, i);
  }
  void ExpectSymmetricWeights() {
    const std::vector<KeyFrame*> all = map_.KeyFrames();
    for (KeyFrame* a : all) {
      for (KeyFrame* b : all) EXPECT_EQ(a->Weight(b), b->Weight(a)) << a->id() << " " << b->id();
    }
  }

  std::shared_ptr<const Sensor> sensor_ = MakeSensor();
  Map map_;
};

TEST_F(MapTest, ObservationsCountDepthTwiceAndStaySortedByKeyFrame) {
  KeyFrame* kf0 = AddKeyFrame(AtCentre({0, 0, 0}), Spec(10, {0}));
  KeyFrame* kf1 = AddKeyFrame(AtCentre({0.1, 0, 0}), Spec(10, {3}));
  KeyFrame* kf2 = AddKeyFrame(AtCentre({0.2, 0, 0}), Spec(10));
  EXPECT_EQ(kf0->id(), 0U);
  EXPECT_EQ(kf2->id(), 2U);
  EXPECT_TRUE(map_.IsOrigin(kf0));

  MapPoint* p = map_.CreateMapPoint({0, 0, 5}, kf1, 3);  // with depth
  EXPECT_EQ(p->num_observations(), 2);
  EXPECT_EQ(p->reference_keyframe(), kf1);
  EXPECT_EQ(p->first_keyframe_id(), 1U);
  EXPECT_EQ(kf1->map_point(3), p);
  // The descriptor is the creating keypoint's.
  EXPECT_EQ(p->descriptor().at<std::uint8_t>(0, 31), 3);

  map_.AddObservation(p, kf2, 5);  // without depth
  map_.AddObservation(p, kf0, 1);  // without depth: keypoint 0 has it, 1 has not
  EXPECT_EQ(p->num_observations(), 4);
  ASSERT_EQ(p->observations().size(), 3U);
  EXPECT_EQ(p->observations()[0].keyframe, kf0);
  EXPECT_EQ(p->observations()[0].index, 1);
  EXPECT_EQ(p->observations()[1].keyframe, kf1);
  EXPECT_EQ(p->observations()[2].keyframe, kf2);
  EXPECT_EQ(p->observations()[2].index, 5);
  EXPECT_EQ(p->reference_keyframe(), kf1);  // the first observer stays the reference
  EXPECT_EQ(p->IndexIn(kf2), 5);
  EXPECT_EQ(kf0->map_point(1), p);

  // Observing twice from one keyframe changes nothing.
  map_.AddObservation(p, kf2, 5);
  EXPECT_EQ(p->num_observations(), 4);
  EXPECT_EQ(p->observations().size(), 3U);

  // A keypoint takes a new point: the old one loses that observation.
  MapPoint* q = map_.CreateMapPoint({1, 0, 5}, kf0, 0);
  map_.AddObservation(q, kf2, 5);
  EXPECT_EQ(kf2->map_point(5), q);
  EXPECT_EQ(p->IndexIn(kf2), -1);
  EXPECT_EQ(p->num_observations(), 3);
  EXPECT_EQ(q->num_observations(), 3);
  EXPECT_EQ(q->reference_keyframe(), kf0);
}

TEST_F(MapTest, EraseObservationErasesPointLeftWithTwoOrFewer) {
  KeyFrame* kf0 = AddKeyFrame(AtCentre({0, 0, 0}), Spec(10, {0}));
  KeyFrame* kf1 = AddKeyFrame(AtCentre({0.1, 0, 0}), Spec(10));
  KeyFrame* kf2 = AddKeyFrame(AtCentre({0.2, 0, 0}), Spec(10));
  MapPoint* p = SharedPoint({kf0, kf1, kf2}, 0);  // counts 2 + 1 + 1
  ASSERT_EQ(p->num_observations(), 4);

  map_.EraseObservation(p, kf2);
  EXPECT_FALSE(p->bad());
  EXPECT_EQ(p->num_observations(), 3);
  EXPECT_EQ(kf2->map_point(0), nullptr);
  EXPECT_EQ(p->IndexIn(kf2), -1);
  map_.EraseObservation(p, kf2);  // not observed any more: nothing happens
  EXPECT_EQ(p->num_observations(), 3);

  map_.EraseObservation(p, kf1);  // 2 left: erased
  EXPECT_TRUE(p->bad());
  EXPECT_EQ(p->num_observations(), 0);
  EXPECT_TRUE(p->observations().empty());
  EXPECT_EQ(kf0->map_point(0), nullptr);
  EXPECT_EQ(kf1->map_point(0), nullptr);
  EXPECT_TRUE(map_.MapPoints().empty());

  // The reference moves to the earliest remaining observer when its own observation goes.
  MapPoint* q = SharedPoint({kf1, kf0, kf2}, 1);  // created in kf1; 1 + 1 + 1
  ASSERT_EQ(q->reference_keyframe(), kf1);
  map_.EraseObservation(q, kf1);
  EXPECT_TRUE(q->bad());  // 2 left
  MapPoint* r = map_.CreateMapPoint({0, 1, 5}, kf2, 2);
  map_.AddObservation(r, kf0, 0);  // with depth: 1 + 2
  map_.AddObservation(r, kf1, 2);  // 4
  map_.EraseObservation(r, kf2);   // 3
  EXPECT_FALSE(r->bad());
  EXPECT_EQ(r->reference_keyframe(), kf0);
}

TEST_F(MapTest, ReplacePointMovesObservationsAndFollowsTheChain) {
  KeyFrame* kf0 = AddKeyFrame(AtCentre({0, 0, 0}), Spec(10));
  KeyFrame* kf1 = AddKeyFrame(AtCentre({0.1, 0, 0}), Spec(10));
  KeyFrame* kf2 = AddKeyFrame(AtCentre({0.2, 0, 0}), Spec(10));
  KeyFrame* kf3 = AddKeyFrame(AtCentre({0.3, 0, 0}), Spec(10));
  MapPoint* a = SharedPoint({kf0, kf1}, 0);
  MapPoint* b = map_.CreateMapPoint({0, 0, 5}, kf1, 1);
  map_.AddObservation(b, kf2, 0);
  a->IncreaseVisible(3);  // a: visible 4, found 1; b: 1, 1

  map_.ReplacePoint(a, b);
  EXPECT_TRUE(a->bad());
  EXPECT_EQ(a->replaced_by(), b);
  EXPECT_EQ(a->Current(), b);
  EXPECT_EQ(b->Current(), b);
  EXPECT_FALSE(b->bad());
  // kf0 now sees b; kf1 saw both, so it keeps b at its own keypoint and loses a's.
  EXPECT_EQ(kf0->map_point(0), b);
  EXPECT_EQ(kf1->map_point(0), nullptr);
  EXPECT_EQ(kf1->map_point(1), b);
  EXPECT_EQ(b->IndexIn(kf0), 0);
  EXPECT_EQ(b->IndexIn(kf1), 1);
  EXPECT_EQ(b->num_observations(), 3);
  EXPECT_EQ(b->observations().front().keyframe, kf0);
  EXPECT_FLOAT_EQ(b->FoundRatio(), 2.0F / 5.0F);  // the statistics add up

  MapPoint* c = map_.CreateMapPoint({0, 0, 5}, kf3, 2);
  map_.AddObservation(c, kf2, 5);
  map_.ReplacePoint(b, c);
  EXPECT_EQ(a->Current(), c);  // a → b → c
  EXPECT_EQ(kf0->map_point(0), c);
  EXPECT_EQ(kf2->map_point(0), nullptr);
  EXPECT_EQ(kf2->map_point(5), c);
  EXPECT_EQ(c->num_observations(), 4);  // kf0, kf1, kf2, kf3
  EXPECT_EQ(map_.MapPoints(), (std::vector<MapPoint*>{c}));

  // Replacing a bad point or a point by itself does nothing.
  map_.ReplacePoint(a, c);
  EXPECT_EQ(a->replaced_by(), b);
  map_.ReplacePoint(c, c);
  EXPECT_FALSE(c->bad());
}

TEST_F(MapTest, UpdateConnectionsBuildsSymmetricWeightsAndParent) {
  KeyFrame* kf0 = AddKeyFrame(AtCentre({0, 0, 0}));
  KeyFrame* kf1 = AddKeyFrame(AtCentre({0.1, 0, 0}));
  KeyFrame* kf2 = AddKeyFrame(AtCentre({0.2, 0, 0}));
  KeyFrame* kf3 = AddKeyFrame(AtCentre({0.3, 0, 0}));
  SharePoints(kf1, kf0, 0, 20);
  SharePoints(kf1, kf2, 20, 15);  // exactly the threshold
  SharePoints(kf1, kf3, 40, 14);
  // Points that were shared but are bad now count for nothing.
  for (int i = 60; i < 70; ++i) map_.ErasePoint(SharedPoint({kf1, kf3}, i));

  map_.UpdateConnections(kf1);
  ASSERT_EQ(kf1->covisibles().size(), 2U);  // kf3's 14 are below the threshold of 15
  EXPECT_EQ(kf1->covisibles()[0], std::make_pair(kf0, 20));
  EXPECT_EQ(kf1->covisibles()[1], std::make_pair(kf2, 15));
  EXPECT_EQ(kf0->Weight(kf1), 20);
  EXPECT_EQ(kf2->Weight(kf1), 15);
  EXPECT_EQ(kf3->Weight(kf1), 0);
  EXPECT_EQ(kf1->Weight(kf3), 0);
  EXPECT_EQ(kf1->parent(), kf0);
  EXPECT_EQ(kf0->children(), (std::vector<KeyFrame*>{kf1}));
  EXPECT_EQ(kf1->BestCovisibles(1), (std::vector<KeyFrame*>{kf0}));

  // With nothing above the threshold the strongest edge is kept.
  map_.UpdateConnections(kf3);
  ASSERT_EQ(kf3->covisibles().size(), 1U);
  EXPECT_EQ(kf3->covisibles()[0], std::make_pair(kf1, 14));
  EXPECT_EQ(kf1->Weight(kf3), 14);
  EXPECT_EQ(kf3->parent(), kf1);

  // The first keyframe never gets a parent.
  map_.UpdateConnections(kf0);
  EXPECT_EQ(kf0->parent(), nullptr);
  EXPECT_EQ(kf0->Weight(kf1), 20);
  ExpectSymmetricWeights();

  // Edges that fall below the threshold go, in both directions; the parent stays.
  map_.ErasePoint(kf2->map_point(20));
  map_.UpdateConnections(kf1);
  EXPECT_EQ(kf1->Weight(kf2), 0);
  EXPECT_EQ(kf2->Weight(kf1), 0);
  EXPECT_EQ(kf1->Weight(kf0), 20);
  EXPECT_EQ(kf1->parent(), kf0);
  ExpectSymmetricWeights();
}

TEST_F(MapTest, AKeyFrameConnectedLateNeverTakesItsOwnChildAsParent) {
  // kf1 shares nothing when it is made; kf2 then attaches to it; when kf1 finds neighbours later its strongest
  // one is its own child kf2, which must not become its parent (a cycle would hang trajectory placement).
  KeyFrame* kf0 = AddKeyFrame(AtCentre({0, 0, 0}));
  KeyFrame* kf1 = AddKeyFrame(AtCentre({0.1, 0, 0}));
  map_.UpdateConnections(kf1);
  EXPECT_EQ(kf1->parent(), nullptr);
  KeyFrame* kf2 = AddKeyFrame(AtCentre({0.2, 0, 0}));
  SharePoints(kf2, kf1, 0, 40);
  map_.UpdateConnections(kf2);
  ASSERT_EQ(kf2->parent(), kf1);
  SharePoints(kf1, kf0, 40, 20);
  map_.UpdateConnections(kf1);
  EXPECT_EQ(kf1->covisibles().front().first, kf2);  // the strongest neighbour is younger
  EXPECT_EQ(kf1->parent(), kf0);
  // Culling kf1 hands kf2 to kf0, and the chain from the culled keyframe ends at a good one.
  map_.EraseKeyFrame(kf1);
  EXPECT_EQ(kf2->parent(), kf0);
  EXPECT_FALSE(kf1->parent()->bad());
}

TEST_F(MapTest, EraseKeyFrameReparentsChildrenAndKeepsRelativePose) {
  KeyFrame* kf0 = AddKeyFrame(testing::PoseFromAxisAngle({0.1, -0.2, 0.05}, {0.3, 0.1, -0.2}), Spec(200));
  KeyFrame* kf1 = AddKeyFrame(testing::PoseFromAxisAngle({-0.3, 0.1, 0.2}, {0.5, -0.4, 0.1}), Spec(200));
  KeyFrame* kf2 = AddKeyFrame(testing::PoseFromAxisAngle({0.0, 0.4, 0.0}, {1.0, 0.0, 0.3}), Spec(200));
  KeyFrame* kf3 = AddKeyFrame(testing::PoseFromAxisAngle({0.2, 0.0, -0.1}, {0.0, 0.2, 0.4}), Spec(200));
  KeyFrame* kf4 = AddKeyFrame(testing::PoseFromAxisAngle({0.0, 0.0, 0.3}, {0.1, 0.1, 0.1}), Spec(200));
  // The tree kf0 ← kf1 ← {kf2, kf3, kf4}.
  SharePoints(kf0, kf1, 0, 20);
  map_.UpdateConnections(kf1);
  SharePoints(kf1, kf2, 20, 40);
  map_.UpdateConnections(kf2);
  SharePoints(kf1, kf3, 60, 50);
  map_.UpdateConnections(kf3);
  SharePoints(kf1, kf4, 110, 15);
  map_.UpdateConnections(kf4);
  ASSERT_EQ(kf1->children(), (std::vector<KeyFrame*>{kf2, kf3, kf4}));
  // Edges around kf1: kf2–kf0 20, kf3–kf2 30, kf3–kf0 16; kf4 knows only kf1.
  SharePoints(kf2, kf0, 130, 20);
  SharePoints(kf3, kf2, 150, 30);
  SharePoints(kf3, kf0, 180, 16);
  for (KeyFrame* kf : {kf0, kf1, kf2, kf3, kf4}) map_.UpdateConnections(kf);
  ASSERT_EQ(kf3->Weight(kf0), 16);
  ASSERT_EQ(kf2->parent(), kf1);

  map_.EraseKeyFrame(kf1);
  EXPECT_TRUE(kf1->bad());
  // kf2 attaches to kf0 (20 > kf3's 16), then kf3 to kf2 (30 > 16); kf4 has no edge to either, so it goes to
  // kf1's parent.
  EXPECT_EQ(kf2->parent(), kf0);
  EXPECT_EQ(kf3->parent(), kf2);
  EXPECT_EQ(kf4->parent(), kf0);
  EXPECT_EQ(kf0->children(), (std::vector<KeyFrame*>{kf2, kf4}));
  EXPECT_EQ(kf2->children(), (std::vector<KeyFrame*>{kf3}));
  EXPECT_TRUE(kf1->children().empty());
  EXPECT_EQ(kf1->parent(), kf0);
  // Its pose relative to its parent places it as before.
  EXPECT_TRUE((kf1->T_cp() * kf0->T_cw()).isApprox(kf1->T_cw(), 1e-12));
  EXPECT_FALSE(kf1->T_cp().isApprox(kf1->T_cw(), 1e-3));
  // Its edges and observations are gone; the points only it and one other keyframe saw are erased.
  for (KeyFrame* kf : {kf0, kf2, kf3, kf4}) EXPECT_EQ(kf->Weight(kf1), 0);
  EXPECT_TRUE(kf1->covisibles().empty());
  for (MapPoint* p : kf1->map_points()) EXPECT_EQ(p, nullptr);
  EXPECT_EQ(kf0->map_point(0), nullptr);
  EXPECT_EQ(map_.MapPoints().size(), 66U);  // the 20 + 30 + 16 shared without kf1
  EXPECT_EQ(map_.KeyFrames(), (std::vector<KeyFrame*>{kf0, kf2, kf3, kf4}));
  EXPECT_EQ(map_.NumKeyFrames(), 4U);

  // Erasing again, or the first keyframe, does nothing.
  map_.EraseKeyFrame(kf1);
  map_.EraseKeyFrame(kf0);
  EXPECT_FALSE(kf0->bad());
  EXPECT_EQ(map_.NumKeyFrames(), 4U);
  // Nor does erasing a keyframe that was never connected.
  KeyFrame* lone = AddKeyFrame(AtCentre({5, 5, 5}));
  map_.EraseKeyFrame(lone);
  EXPECT_FALSE(lone->bad());
  EXPECT_EQ(map_.NumKeyFrames(), 5U);
}

TEST_F(MapTest, ListsOnlyGoodEntitiesInIdOrder) {
  std::vector<KeyFrame*> kfs;
  for (int k = 0; k < 4; ++k) kfs.push_back(AddKeyFrame(AtCentre({0.1 * k, 0, 0})));
  std::vector<MapPoint*> points;
  for (int i = 0; i < 6; ++i) points.push_back(SharedPoint({kfs[0], kfs[1], kfs[2]}, i));
  for (int k = 0; k < 3; ++k) map_.UpdateConnections(kfs[static_cast<std::size_t>(k)]);
  SharePoints(kfs[2], kfs[3], 10, 20);
  map_.UpdateConnections(kfs[3]);
  map_.ErasePoint(points[1]);
  map_.ErasePoint(points[4]);
  const std::vector<MapPoint*> good = map_.MapPoints();
  ASSERT_EQ(good.size(), 24U);
  EXPECT_EQ(good[0], points[0]);
  EXPECT_EQ(good[1], points[2]);
  EXPECT_EQ(good[2], points[3]);
  EXPECT_EQ(good[3], points[5]);
  for (std::size_t i = 1; i < good.size(); ++i) EXPECT_LT(good[i - 1]->id(), good[i]->id());

  map_.EraseKeyFrame(kfs[1]);
  EXPECT_EQ(map_.KeyFrames(), (std::vector<KeyFrame*>{kfs[0], kfs[2], kfs[3]}));
  EXPECT_EQ(map_.NumKeyFrames(), 3U);
}

TEST_F(MapTest, UpdatePointComputesNormalDistanceRangeAndDescriptor) {
  // Five observations. The third keyframe's descriptor differs from each other one by 10 bits (in disjoint
  // places), so any two others differ by 20: it has the least median distance.
  const int n = 5;
  std::vector<KeyFrame*> kfs;
  const std::vector<Eigen::Vector3d> centres = {{0, 0, 0}, {1, 0, 0}, {-1, 0.5, 0}, {0, -1, 1}, {0.5, 0.5, -1}};
  for (int k = 0; k < n; ++k) {
    cv::Mat d = cv::Mat::zeros(4, 32, CV_8UC1);
    // Keypoint 0 carries the descriptor; keypoint 2 (level 2 in keyframe 1) observes the point in keyframe 1.
    const int index = k == 1 ? 2 : 0;
    if (k != 2) {
      const int slot = k < 2 ? k : k - 1;  // 0..3: bytes 0-1, 2-3, ... hold the 10 flipped bits
      d.at<std::uint8_t>(index, 2 * slot) = 0xFF;
      d.at<std::uint8_t>(index, 2 * slot + 1) = 0x03;
    }
    kfs.push_back(AddKeyFrame(AtCentre(centres[static_cast<std::size_t>(k)]),
                              Spec(4, {}, {0, 0, 2, 0}, d)));
  }
  const Eigen::Vector3d position(0.2, 0.1, 4.0);
  // Created in keyframe 1 (the reference), at level 2.
  MapPoint* p = map_.CreateMapPoint(position, kfs[1], 2);
  for (int k : {0, 2, 3, 4}) map_.AddObservation(p, kfs[static_cast<std::size_t>(k)], 0);
  ASSERT_EQ(p->reference_keyframe(), kfs[1]);
  ASSERT_EQ(features::DescriptorDistance(kfs[0]->keypoints().descriptor(0), kfs[2]->keypoints().descriptor(0)), 10);
  ASSERT_EQ(features::DescriptorDistance(kfs[0]->keypoints().descriptor(0), kfs[1]->keypoints().descriptor(2)), 20);
  // Until updated, the point keeps what its creation gave it.
  EXPECT_EQ(features::DescriptorDistance(p->descriptor().ptr(), kfs[1]->keypoints().descriptor(2)), 0);

  map_.UpdatePoint(p);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& c : centres) normal += (position - c).normalized();
  normal.normalize();
  EXPECT_TRUE(p->normal().isApprox(normal, 1e-9)) << p->normal().transpose();
  EXPECT_NEAR(p->normal().norm(), 1.0, 1e-12);
  const double distance = (position - centres[1]).norm();
  EXPECT_NEAR(p->max_distance(), 1.2 * distance * 1.2 * 1.2, 1e-5);
  EXPECT_NEAR(p->min_distance(), 0.8 * distance * 1.2 * 1.2 / std::pow(1.2, 7), 1e-5);
  EXPECT_EQ(features::DescriptorDistance(p->descriptor().ptr(), kfs[2]->keypoints().descriptor(0)), 0);

  // Without the central observation the medians tie at 20 and the earliest keyframe's descriptor wins.
  map_.EraseObservation(p, kfs[2]);
  map_.UpdatePoint(p);
  EXPECT_EQ(features::DescriptorDistance(p->descriptor().ptr(), kfs[0]->keypoints().descriptor(0)), 0);
}

// A one-row descriptor with bits [first, first + count) set.
cv::Mat Bits(int first, int count) {
  cv::Mat d = cv::Mat::zeros(1, 32, CV_8UC1);
  for (int b = first; b < first + count; ++b) d.at<std::uint8_t>(0, b / 8) |= static_cast<std::uint8_t>(1U << (b % 8));
  return d;
}

TEST_F(MapTest, RepresentativeDescriptorHasTheLeastMedianDistanceNotTheLeastLargest) {
  // A (no bits) is 10 from B, C, D but 100 from the outlier E; X (40 of E's bits) is 40-60 from everyone. A has
  // the least median (10 against X's 50), X the least largest distance (60 against A's 100).
  const std::vector<cv::Mat> descriptors = {Bits(100, 40) /* X */, Bits(0, 10) /* B */, Bits(0, 0) /* A */,
                                            Bits(10, 10) /* C */, Bits(100, 100) /* E */, Bits(20, 10) /* D */};
  std::vector<KeyFrame*> kfs;
  for (std::size_t k = 0; k < descriptors.size(); ++k) {
    kfs.push_back(AddKeyFrame(AtCentre({0.1 * static_cast<double>(k), 0, 0}), Spec(1, {}, {}, descriptors[k])));
  }
  MapPoint* p = SharedPoint(kfs, 0);
  map_.UpdatePoint(p);
  EXPECT_EQ(features::DescriptorDistance(p->descriptor().ptr(), kfs[2]->keypoints().descriptor(0)), 0);
}

TEST_F(MapTest, PredictLevelFollowsTheScalePyramid) {
  KeyFrame* kf = AddKeyFrame(AtCentre({0, 0, 0}), Spec(2));
  MapPoint* p = map_.CreateMapPoint({0, 0, 2}, kf, 0);  // level 0 at 2 m
  const features::ScalePyramid& pyramid = sensor_->pyramid;
  EXPECT_FLOAT_EQ(p->max_distance(), 1.2F * 2.0F);
  EXPECT_EQ(p->PredictLevel(2.0 / std::pow(1.2, 0.5), pyramid), 1);
  EXPECT_EQ(p->PredictLevel(2.0 / std::pow(1.2, 2.5), pyramid), 3);
  EXPECT_EQ(p->PredictLevel(2.0 / std::pow(1.2, 6.5), pyramid), 7);
  // Nearer than the finest level can see, or farther than the range: clamped.
  EXPECT_EQ(p->PredictLevel(0.01, pyramid), 7);
  EXPECT_EQ(p->PredictLevel(3.0, pyramid), 0);
  EXPECT_EQ(p->PredictLevel(0.0, pyramid), 0);
  const features::ScalePyramid single = features::ScalePyramid::Make(1, 1.2);
  EXPECT_EQ(p->PredictLevel(0.5, single), 0);
}

TEST_F(MapTest, AMapStartedAfterwardsHasItsOwnKeyFramesPointsAndOrigin) {
  KeyFrame* a0 = AddKeyFrame(AtCentre({0, 0, 0}), Spec(10, {0, 1, 2}));
  KeyFrame* a1 = AddKeyFrame(AtCentre({0.1, 0, 0}), Spec(10, {0, 1, 2}));
  SharePoints(a0, a1, 0, 3);
  EXPECT_EQ(map_.active_map(), 0U);
  EXPECT_EQ(map_.StartNewMap(), 1U);
  EXPECT_EQ(map_.active_map(), 1U);
  EXPECT_EQ(map_.Maps(), std::vector<MapId>{0});  // the new map has no keyframe yet
  KeyFrame* b0 = AddKeyFrame(AtCentre({5, 0, 0}), Spec(10, {0, 1}));
  KeyFrame* b1 = AddKeyFrame(AtCentre({5.1, 0, 0}), Spec(10, {0, 1}));
  SharePoints(b0, b1, 0, 2);
  EXPECT_EQ(b0->map_id(), 1U);
  EXPECT_EQ(map_.Maps(), (std::vector<MapId>{0, 1}));
  EXPECT_EQ(map_.KeyFrames(0), (std::vector<KeyFrame*>{a0, a1}));
  EXPECT_EQ(map_.KeyFrames(1), (std::vector<KeyFrame*>{b0, b1}));
  EXPECT_EQ(map_.MapPoints(0).size(), 3U);
  EXPECT_EQ(map_.MapPoints(1).size(), 2U);
  EXPECT_EQ(map_.NumKeyFrames(1), 2U);
  // Each map's first keyframe anchors it and is never culled.
  EXPECT_TRUE(map_.IsOrigin(a0));
  EXPECT_TRUE(map_.IsOrigin(b0));
  EXPECT_FALSE(map_.IsOrigin(b1));
  map_.UpdateConnections(b0);
  map_.UpdateConnections(b1);
  EXPECT_EQ(b0->parent(), nullptr);
  map_.EraseKeyFrame(b0);
  EXPECT_FALSE(b0->bad());
  // Back in the first map, a keyframe joins it.
  map_.ActivateMap(0);
  EXPECT_EQ(AddKeyFrame(AtCentre({0.2, 0, 0}))->map_id(), 0U);
}

TEST_F(MapTest, MergingCarriesAMapIntoTheOthersWorldFrame) {
  KeyFrame* a0 = AddKeyFrame(AtCentre({0, 0, 0}), Spec(10, {0}));
  map_.StartNewMap();
  // The second map's world frame is the first's turned 90° about y and moved 1 m along x.
  const core::Pose T_a_b =
      testing::PoseFromAxisAngle(Eigen::Vector3d(0, std::numbers::pi / 2, 0), Eigen::Vector3d(1, 0, 0));
  KeyFrame* b0 = AddKeyFrame(AtCentre({0, 0, 0}), Spec(10, {0, 1}));
  KeyFrame* b1 = AddKeyFrame(AtCentre({0, 0, 0.5}), Spec(10, {0, 1}));
  MapPoint* p = SharedPoint({b0, b1}, 0, Eigen::Vector3d(0.2, 0.1, 2.0));
  const Eigen::Vector3d b1_centre = (T_a_b * b1->T_wc()).translation();
  map_.MergeMaps(1, 0, T_a_b);
  EXPECT_EQ(map_.Maps(), std::vector<MapId>{0});
  EXPECT_EQ(map_.active_map(), 0U);
  EXPECT_EQ(b0->map_id(), 0U);
  EXPECT_EQ(b1->map_id(), 0U);
  EXPECT_TRUE(map_.IsOrigin(a0));
  EXPECT_FALSE(map_.IsOrigin(b0));
  EXPECT_LT((b1->center() - b1_centre).norm(), 1e-12);
  EXPECT_LT((p->position() - T_a_b * Eigen::Vector3d(0.2, 0.1, 2.0)).norm(), 1e-12);
  EXPECT_EQ(map_.MapPoints(0).size(), 1U);  // the moved one
  // The point is still where both keyframes see it: in their cameras it has not moved.
  EXPECT_LT(((b1->T_cw() * p->position()) - Eigen::Vector3d(0.2, 0.1, 1.5)).norm(), 1e-12);
}

}  // namespace
}  // namespace hoidslam::slam::map_test
