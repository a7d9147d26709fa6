#include "hoidslam/slam/data/map_file.h"

#include <cstdint>
#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/features/orb_extractor.h"
#include "support/small_vocabulary.h"
#include "support/temp_dir.h"

// A namespace of this file's own, for the unity build (scripts/sanitize.sh).
namespace hoidslam::slam::map_file_test {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr int kKeypoints = 60;

std::shared_ptr<const Sensor> MakeSensor(double fx = 535.4) {
  core::CameraIntrinsics camera;
  camera.fx = fx;
  return Sensor::Make(camera, 40.0, 3.0, features::ScalePyramid::Make(8, 1.2));
}

// A small vocabulary of random descriptors; `seed` picks them, so two seeds give two vocabularies.
bow::Vocabulary MakeVocabulary(std::uint64_t seed) {
  cv::RNG rng(seed);
  std::vector<cv::Mat> images;
  for (int i = 0; i < 4; ++i) {
    cv::Mat descriptors(50, 32, CV_8UC1);
    rng.fill(descriptors, cv::RNG::UNIFORM, 0, 256);
    images.push_back(descriptors);
  }
  return testing::TrainSmallVocabulary(images);
}

// Keypoints on a lattice, every other one with depth, with random descriptors and colours.
std::shared_ptr<const KeypointSet> MakeKeypoints(const std::shared_ptr<const Sensor>& sensor, cv::RNG& rng) {
  std::vector<cv::KeyPoint> keypoints;
  std::vector<float> depth;
  std::vector<cv::Vec3b> colors;
  for (int i = 0; i < kKeypoints; ++i) {
    keypoints.emplace_back(20.0F + 10.0F * static_cast<float>(i % 50), 20.0F + 10.0F * static_cast<float>(i / 50),
                           31.0F, 45.0F, 0.5F, i % 3);
    depth.push_back(i % 2 == 0 ? 2.0F : 0.0F);
    colors.emplace_back(static_cast<std::uint8_t>(i), 100, static_cast<std::uint8_t>(rng.uniform(0, 256)));
  }
  cv::Mat descriptors(kKeypoints, 32, CV_8UC1);
  rng.fill(descriptors, cv::RNG::UNIFORM, 0, 256);
  return std::make_shared<const KeypointSet>(sensor, std::move(keypoints), descriptors, std::move(depth),
                                             std::move(colors));
}

core::Pose At(double x) {
  core::Pose pose = core::Pose::Identity();
  pose.translation() = Eigen::Vector3d(-x, 0.0, 0.0);
  pose.rotate(Eigen::AngleAxisd(0.05 * x, Eigen::Vector3d::UnitY()));
  return pose;
}

// Four keyframes seeing shared points, the third culled, a loop edge between the first and the last.
void BuildMap(Map& map, const std::shared_ptr<const Sensor>& sensor, const bow::Vocabulary& vocabulary) {
  std::unique_lock lock(map.mutex());
  cv::RNG rng(7);
  std::vector<KeyFrame*> keyframes;
  for (int k = 0; k < 4; ++k) {
    keyframes.push_back(map.CreateKeyFrame(static_cast<std::uint64_t>(10 * k), 0.5 * k, MakeKeypoints(sensor, rng),
                                           At(0.1 * k)));
  }
  for (int i = 0; i < 40; ++i) {
    MapPoint* point = map.CreateMapPoint(Eigen::Vector3d(0.05 * i, 0.01 * i, 2.0), keyframes[0], i);
    for (int k = 1; k < 4; ++k) {
      if ((i + k) % 4 != 0) map.AddObservation(point, keyframes[static_cast<std::size_t>(k)], i);
    }
    map.UpdatePoint(point);
  }
  for (KeyFrame* keyframe : keyframes) {
    map.UpdateConnections(keyframe);
    map.IndexKeyFrame(keyframe, vocabulary.Transform(keyframe->keypoints().descriptors()));
  }
  map.AddLoopEdge(keyframes[0], keyframes[3]);
  // A point whose first keyframe no longer sees it: it keeps that keyframe's colour.
  map.EraseObservation(keyframes[0]->map_point(4), keyframes[0]);
  map.EraseKeyFrame(keyframes[2]);
  // As local mapping would, before a map is saved: what loading recomputes is then the same.
  for (KeyFrame* keyframe : map.KeyFrames()) map.UpdateConnections(keyframe);
  for (MapPoint* point : map.MapPoints()) map.UpdatePoint(point);
}

std::vector<std::uint8_t> ReadBytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void WriteBytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
}

// Makes the last eight bytes the checksum of the others again, so a change reaches the checks behind it.
void Rechecksum(std::vector<std::uint8_t>& bytes) {
  const std::size_t content = bytes.size() - bow::kChecksumBytes;
  const std::uint64_t checksum = bow::Fnv1a64(std::span(bytes).first(content));
  for (std::size_t i = 0; i < bow::kChecksumBytes; ++i) bytes[content + i] = static_cast<std::uint8_t>(checksum >> (8 * i));
}

class MapFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    BuildMap(map_, sensor_, vocabulary_);
    std::shared_lock lock(map_.mutex());
    SaveMap(map_, 0, *sensor_, vocabulary_, path_);
  }

  // The error loading `path_` with this sensor and vocabulary gives (none: "").
  std::string LoadError(const std::shared_ptr<const Sensor>& sensor, const bow::Vocabulary& vocabulary) const {
    Map loaded;
    std::unique_lock lock(loaded.mutex());
    try {
      LoadMap(path_, sensor, vocabulary, loaded);
    } catch (const core::InputError& error) {
      return error.what();
    }
    return "";
  }
  std::string LoadError() const { return LoadError(sensor_, vocabulary_); }

  std::shared_ptr<const Sensor> sensor_ = MakeSensor();
  bow::Vocabulary vocabulary_ = MakeVocabulary(1);
  Map map_;
  testing::TempDir dir_;
  std::filesystem::path path_ = dir_ / "office.hmap";
};

TEST_F(MapFileTest, ALoadedMapHasTheSavedKeyframesPointsAndGraph) {
  Map loaded;
  std::unique_lock lock(loaded.mutex());
  LoadMap(path_, sensor_, vocabulary_, loaded);
  std::shared_lock original_lock(map_.mutex());

  const std::vector<KeyFrame*> before = map_.KeyFrames();
  const std::vector<KeyFrame*> after = loaded.KeyFrames();
  ASSERT_EQ(before.size(), 3U);  // the culled one is not saved
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t k = 0; k < before.size(); ++k) {
    const KeyFrame& b = *before[k];
    const KeyFrame& a = *after[k];
    EXPECT_EQ(a.id(), k);  // renumbered without gaps
    EXPECT_EQ(a.frame_id(), b.frame_id());
    EXPECT_EQ(a.timestamp(), b.timestamp());
    EXPECT_TRUE(a.T_cw().matrix() == b.T_cw().matrix());
    ASSERT_EQ(a.keypoints().size(), b.keypoints().size());
    for (int i = 0; i < a.keypoints().size(); ++i) {
      EXPECT_EQ(a.keypoints().depth(i), b.keypoints().depth(i));
      EXPECT_EQ(a.keypoints().color(i), b.keypoints().color(i));
      EXPECT_EQ(a.keypoints().level(i), b.keypoints().level(i));
    }
    EXPECT_EQ(cv::norm(a.keypoints().descriptors(), b.keypoints().descriptors(), cv::NORM_HAMMING), 0.0);
    EXPECT_EQ(a.parent() == nullptr, b.parent() == nullptr);
    if (a.parent() != nullptr) {
      EXPECT_EQ(a.parent()->frame_id(), b.parent()->frame_id());
    }
    EXPECT_EQ(a.loop_edges().size(), b.loop_edges().size());
    ASSERT_EQ(a.covisibles().size(), b.covisibles().size());
    for (std::size_t c = 0; c < a.covisibles().size(); ++c) {
      EXPECT_EQ(a.covisibles()[c].first->frame_id(), b.covisibles()[c].first->frame_id());
      EXPECT_EQ(a.covisibles()[c].second, b.covisibles()[c].second);
    }
    EXPECT_EQ(a.words().bow, b.words().bow);
  }

  const std::vector<MapPoint*> points_before = map_.MapPoints();
  const std::vector<MapPoint*> points_after = loaded.MapPoints();
  ASSERT_EQ(points_after.size(), points_before.size());
  for (std::size_t p = 0; p < points_before.size(); ++p) {
    const MapPoint& b = *points_before[p];
    const MapPoint& a = *points_after[p];
    EXPECT_EQ(a.position(), b.position());
    EXPECT_EQ(a.color(), b.color());
    EXPECT_EQ(a.num_observations(), b.num_observations());
    EXPECT_EQ(a.reference_keyframe()->frame_id(), b.reference_keyframe()->frame_id());
    EXPECT_EQ(a.normal(), b.normal());
    EXPECT_EQ(cv::norm(a.descriptor(), b.descriptor(), cv::NORM_HAMMING), 0.0);
    ASSERT_EQ(a.observations().size(), b.observations().size());
    for (std::size_t o = 0; o < a.observations().size(); ++o) {
      EXPECT_EQ(a.observations()[o].keyframe->frame_id(), b.observations()[o].keyframe->frame_id());
      EXPECT_EQ(a.observations()[o].index, b.observations()[o].index);
    }
  }

  // The ids continue after the loaded ones.
  KeyFrame* next = loaded.CreateKeyFrame(99, 9.0, after[0]->shared_keypoints(), At(0.0));
  EXPECT_EQ(next->id(), after.size());
  EXPECT_EQ(loaded.CreateMapPoint(Eigen::Vector3d(0, 0, 2), next, 50)->id(), points_after.size());
}

TEST_F(MapFileTest, ALoadedMapSavesToTheSameBytes) {
  Map loaded;
  std::unique_lock lock(loaded.mutex());
  LoadMap(path_, sensor_, vocabulary_, loaded);
  EXPECT_EQ(EncodeMap(ContentOf(loaded, 0, *sensor_, vocabulary_)), ReadBytes(path_));
}

TEST_F(MapFileTest, AMissingFileIsAnErrorNamingIt) {
  std::filesystem::remove(path_);
  EXPECT_THAT(LoadError(), HasSubstr(path_.string() + ": map file does not exist"));
}

TEST_F(MapFileTest, ATruncatedFileIsAnErrorNamingIt) {
  std::vector<std::uint8_t> bytes = ReadBytes(path_);
  bytes.resize(bytes.size() - 100);
  WriteBytes(path_, bytes);
  EXPECT_THAT(LoadError(), HasSubstr(path_.string() + ": truncated or corrupt"));
  bytes.resize(10);
  WriteBytes(path_, bytes);
  EXPECT_THAT(LoadError(), HasSubstr(path_.string() + ": truncated"));
}

TEST_F(MapFileTest, AFlippedByteFailsTheChecksum) {
  std::vector<std::uint8_t> bytes = ReadBytes(path_);
  bytes[bytes.size() / 2] ^= 0x10;
  WriteBytes(path_, bytes);
  EXPECT_THAT(LoadError(), HasSubstr(path_.string() + ": truncated or corrupt: the checksum"));
}

TEST_F(MapFileTest, AnotherFormatOrVersionIsRefused) {
  std::vector<std::uint8_t> bytes = ReadBytes(path_);
  bytes[8] = 2;  // the version
  WriteBytes(path_, bytes);
  EXPECT_THAT(LoadError(), HasSubstr(path_.string() + ": unsupported format version 2 (this hoidslam reads version 1)"));
  bytes[0] = 'X';
  WriteBytes(path_, bytes);
  EXPECT_THAT(LoadError(), HasSubstr(path_.string() + ": not a hoidslam map file"));
}

TEST_F(MapFileTest, AMapOfAnotherCameraOrVocabularyIsRefusedSayingWhatDiffers) {
  EXPECT_THAT(LoadError(MakeSensor(520.0), vocabulary_),
              HasSubstr(path_.string() + ": the map was made with another camera (640×480 px, fx 535.4 "));
  EXPECT_THAT(LoadError(sensor_, MakeVocabulary(2)),
              HasSubstr(path_.string() + ": the map was made with another vocabulary (" + vocabulary_.identity()));
  EXPECT_EQ(LoadError(), "");
}

TEST_F(MapFileTest, ContentThatIsNotAMapIsRefusedBehindAValidChecksum) {
  std::vector<std::uint8_t> bytes = ReadBytes(path_);
  // The last point's last observation: its keyframe index (8 bytes before the checksum's 8) beyond the three.
  bytes[bytes.size() - 16] = 7;
  Rechecksum(bytes);
  WriteBytes(path_, bytes);
  EXPECT_THAT(LoadError(), AllOf(HasSubstr(path_.string() + ": point "), HasSubstr(": keyframe 7 of 3")));
}

}  // namespace
}  // namespace hoidslam::slam::map_file_test
