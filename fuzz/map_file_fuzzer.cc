// Map files: the bytes are a map file (.hmap, slam/map_file.h), decoded as slam::LoadMap decodes a file's bytes;
// one made with the target's camera (the TUM fr3 defaults, 8 pyramid levels of 1.2) is then rebuilt into a map,
// its bags of words from a small vocabulary of the target's own. Each input is read twice: as it is, and with its
// last eight bytes made the checksum of the others, so that mutations reach the checks behind the checksum.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "fuzz/targets.h"
#include "hoidslam/features/orb_extractor.h"
#include "hoidslam/slam/data/map_file.h"
#include "support/small_vocabulary.h"

namespace hoidslam::fuzz {
namespace {

const std::shared_ptr<const slam::Sensor>& TargetSensor() {
  static const auto sensor =
      slam::Sensor::Make(core::CameraIntrinsics{}, 40.0, 3.0, features::ScalePyramid::Make(8, 1.2));
  return sensor;
}

// A vocabulary of k = 4, L = 2 of fixed descriptors (rows of repeated bytes), trained once.
const bow::Vocabulary& TargetVocabulary() {
  static const bow::Vocabulary vocabulary = [] {
    std::vector<cv::Mat> images;
    for (int image = 0; image < 4; ++image) {
      cv::Mat descriptors(16, bow::kDescriptorBytes, CV_8U);
      for (int row = 0; row < descriptors.rows; ++row) descriptors.row(row).setTo(cv::Scalar((image * 16 + row) * 4));
      images.push_back(descriptors);
    }
    return testing::TrainSmallVocabulary(images);
  }();
  return vocabulary;
}

void CheckMap(Bytes bytes) {
  const std::string source = "map.hmap";
  const auto content = ParseOrReject([&] { return slam::DecodeMap(bytes, source); }, source);
  if (!content) return;
  // Every byte of an accepted file is a field that is read, so writing it again gives the same bytes.
  const std::vector<std::uint8_t> written = slam::EncodeMap(*content);
  Require(std::equal(written.begin(), written.end(), bytes.begin(), bytes.end()), "saving does not give the file");
  if (!(content->camera == slam::MapFileCamera::Of(*TargetSensor()))) return;

  slam::Map map;
  slam::RebuildMap(*content, TargetSensor(), TargetVocabulary(), map);
  Require(map.NumKeyFrames() == content->keyframes.size(), "the map does not hold every keyframe");
  const std::vector<slam::MapPoint*> points = map.MapPoints();
  Require(points.size() == content->points.size(), "the map does not hold every point");
  for (std::size_t p = 0; p < points.size(); ++p) {
    Require(points[p]->observations().size() == content->points[p].observations.size(),
            "a point lost an observation");
  }
  for (const slam::KeyFrame* keyframe : map.KeyFrames()) {
    for (const auto& [other, weight] : keyframe->covisibles()) {
      Require(other != keyframe && weight > 0 && other->Weight(keyframe) == weight, "a covisibility edge is one-sided");
    }
  }
}

}  // namespace

void FuzzMapFile(Bytes input) {
  CheckMap(input);
  if (const auto checksummed = WithChecksum(input)) CheckMap(*checksummed);
}

}  // namespace hoidslam::fuzz
