#include "hoidslam/slam/data/keyframe_database.h"

#include <memory>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/features/orb_extractor.h"
#include "hoidslam/slam/data/map.h"

// A namespace of this file's own, for the unity build (scripts/sanitize.sh).
namespace hoidslam::slam::keyframe_database_test {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;
using ::testing::UnorderedElementsAre;

constexpr int kKeypoints = 40;

// A bag of words of equal weights.
bow::ImageWords Words(const std::vector<bow::WordId>& ids) {
  bow::ImageWords words;
  for (const bow::WordId id : ids) words.bow.push_back({id, 1.0 / static_cast<double>(ids.size())});
  return words;
}

class KeyFrameDatabaseTest : public ::testing::Test {
 protected:
  // A keyframe with the given words, entered into the map's database.
  KeyFrame* Add(const std::vector<bow::WordId>& ids) {
    std::vector<cv::KeyPoint> keypoints;
    for (int i = 0; i < kKeypoints; ++i) keypoints.emplace_back(20.0F + 10.0F * static_cast<float>(i), 100.0F, 31.0F);
    auto set = std::make_shared<const KeypointSet>(sensor_, std::move(keypoints), cv::Mat::zeros(kKeypoints, 32, CV_8UC1),
                                                   cv::Mat::zeros(480, 640, CV_32FC1), cv::Mat());
    KeyFrame* keyframe = map_.CreateKeyFrame(map_.NumKeyFrames(), 0.0, std::move(set), core::Pose::Identity());
    map_.IndexKeyFrame(keyframe, Words(ids));
    return keyframe;
  }

  // Makes `later` see the points of `earlier` (all its keypoints): covisible, with `earlier` as its parent.
  void Connect(KeyFrame* earlier, KeyFrame* later) {
    for (int i = 0; i < kKeypoints; ++i) {
      MapPoint* p = map_.CreateMapPoint(Eigen::Vector3d(0.1 * i, 0.0, 2.0), earlier, i);
      map_.AddObservation(p, later, i);
    }
    map_.UpdateConnections(later);
  }

  std::vector<KeyFrame*> Candidates(const std::vector<bow::WordId>& ids) const {
    return map_.database().RelocalizationCandidates(Words(ids).bow, 10);
  }

  std::shared_ptr<const Sensor> sensor_ =
      Sensor::Make(core::CameraIntrinsics{}, 40.0, 3.0, features::ScalePyramid::Make(8, 1.2));
  Map map_;
};

TEST_F(KeyFrameDatabaseTest, FindsThePlaceThatSharesMostWordsAnywhereInTheMap) {
  KeyFrame* office = Add({10, 11, 12, 13});
  KeyFrame* kitchen = Add({1, 2, 3, 4});
  KeyFrame* corridor = Add({1, 2, 20, 21});  // two words alike: fewer than 80 % of the kitchen's four
  Add({30, 31});
  EXPECT_THAT(Candidates({1, 2, 3, 4}), ElementsAre(kitchen));
  EXPECT_THAT(Candidates({10, 11, 12, 99}), ElementsAre(office));
  EXPECT_THAT(Candidates({1, 2, 20, 21, 5}), ElementsAre(corridor));
  EXPECT_THAT(Candidates({50, 51}), IsEmpty());
}

TEST_F(KeyFrameDatabaseTest, AGroupOfCovisibleKeyframesOutweighsOneAloneAndGivesItsBest) {
  // Two keyframes of one place, seeing the same points, each a little like the frame; and one lone keyframe
  // a little more like it than either.
  KeyFrame* place_a = Add({1, 2, 3, 4, 5, 7, 8});
  KeyFrame* place_b = Add({1, 2, 3, 4, 5, 9, 10, 11});
  Connect(place_a, place_b);
  Add({1, 2, 3, 4, 5, 6});
  // Against the frame's five words: the lone keyframe scores 5/6, place_a 5/7 and place_b 5/8, credited together
  // 1.34, so the lone one (less than 75 % of that) is not tried, and the place is tried at its best keyframe.
  EXPECT_THAT(Candidates({1, 2, 3, 4, 5}), ElementsAre(place_a));
}

TEST_F(KeyFrameDatabaseTest, ACulledKeyframeIsNoLongerFound) {
  KeyFrame* first = Add({40, 41, 42});
  KeyFrame* culled = Add({1, 2, 3, 4});
  Connect(first, culled);
  ASSERT_THAT(Candidates({1, 2, 3, 4}), ElementsAre(culled));
  map_.EraseKeyFrame(culled);
  EXPECT_THAT(Candidates({1, 2, 3, 4}), IsEmpty());
  EXPECT_THAT(Candidates({40, 41, 42}), ElementsAre(first));
}

TEST_F(KeyFrameDatabaseTest, EachMapIsSearchedOnItsOwnOrAllTogether) {
  KeyFrame* first_map = Add({1, 2, 3, 4});
  Add({40, 41});
  map_.StartNewMap();
  KeyFrame* second_map = Add({1, 2, 3, 4, 5});
  Connect(second_map, Add({1, 2, 6, 7}));
  // Relocalisation in one map, or in all of them.
  EXPECT_THAT(map_.database().RelocalizationCandidates(Words({1, 2, 3, 4}).bow, 10, 0), ElementsAre(first_map));
  EXPECT_THAT(map_.database().RelocalizationCandidates(Words({1, 2, 3, 4}).bow, 10, 1), ElementsAre(second_map));
  EXPECT_THAT(Candidates({1, 2, 3, 4}), UnorderedElementsAre(first_map, second_map));
  KeyFrame* probe = Add({1, 2, 3, 4, 8});
  // A loop stays in the keyframe's map; a merge looks only in the others.
  EXPECT_THAT(map_.database().LoopCandidates(*probe, 0.0), ElementsAre(second_map));
  EXPECT_THAT(map_.database().MergeCandidates(*probe, 0.0), ElementsAre(first_map));
}

}  // namespace
}  // namespace hoidslam::slam::keyframe_database_test
