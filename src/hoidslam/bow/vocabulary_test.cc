#include "hoidslam/bow/vocabulary.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/bow/test_images.h"
#include "hoidslam/core/error.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::bow {
namespace {

using ::testing::HasSubstr;

// A small vocabulary (k = 8, L = 3: at most 512 words) of a few real photos, trained once for the suite.
class VocabularyOfPhotos : public ::testing::Test {
 protected:
  static constexpr const char* kPhotos[] = {"photos/bus.jpg",     "photos/zidane.jpg",   "photos/horses.jpg",
                                            "textures/graf1.png", "textures/board.jpg", "textures/building.jpg"};

  static VocabularyOptions Options() {
    VocabularyOptions options;
    options.branching = 8;
    options.levels = 3;
    return options;
  }

  static void SetUpTestSuite() {
    for (const char* photo : kPhotos) {
      images_.push_back(fixtures::ReadGray(testing::SharedPath(std::string("data/") + photo)));
      descriptors_.push_back(images_.back().empty() ? cv::Mat() : fixtures::OrbDescriptors(images_.back()));
    }
  }

  void SetUp() override {
    HOIDSLAM_SHARED_PATH_OR_SKIP(photos, "data/photos");
    for (const cv::Mat& image : images_) ASSERT_FALSE(image.empty());
    if (!vocabulary_) vocabulary_.emplace(Vocabulary::Train(descriptors_, Options()));
  }

  static inline std::vector<cv::Mat> images_;
  static inline std::vector<cv::Mat> descriptors_;
  static inline std::optional<Vocabulary> vocabulary_;
};

TEST_F(VocabularyOfPhotos, IsATreeOfAtMostKToTheLWords) {
  const Vocabulary& vocabulary = *vocabulary_;
  EXPECT_EQ(vocabulary.branching(), 8);
  EXPECT_EQ(vocabulary.levels(), 3);
  EXPECT_EQ(vocabulary.training_images(), std::size(kPhotos));
  EXPECT_EQ(vocabulary.training_descriptors(), 6000U);
  EXPECT_LE(vocabulary.node_count(), 1U + 8 + 64 + 512);
  // 6000 descriptors fill nearly all of the 512 leaves.
  EXPECT_LE(vocabulary.word_count(), 512U);
  EXPECT_GT(vocabulary.word_count(), 400U);
  std::size_t words = 0;
  for (std::size_t node = 0; node < vocabulary.node_count(); ++node) {
    const TreeNode& n = vocabulary.tree().nodes[node];
    EXPECT_LE(n.child_count, 8U);
    EXPECT_LE(vocabulary.Level(static_cast<NodeId>(node)), 3);
    if (node > 0 && n.child_count == 0) {
      ++words;
      EXPECT_GE(n.idf, 0.0);
      EXPECT_LE(n.idf, std::log(6.0) + 1e-12);
    }
  }
  EXPECT_EQ(words, vocabulary.word_count());
  EXPECT_EQ(vocabulary.tree().nodes[0].child_count, 8U);
}

TEST_F(VocabularyOfPhotos, AnImageScoresOneAgainstItselfAndMoreAgainstAShiftedBlurredCopyThanAnotherImage) {
  const Vocabulary& vocabulary = *vocabulary_;
  const BowVector bus = vocabulary.Transform(descriptors_[0]).bow;
  EXPECT_DOUBLE_EQ(Score(bus, bus), 1.0);

  cv::Mat shifted;
  cv::warpAffine(images_[0], shifted, cv::Matx23d(1, 0, 9, 0, 1, -6), images_[0].size(), cv::INTER_LINEAR,
                 cv::BORDER_REFLECT);
  cv::GaussianBlur(shifted, shifted, cv::Size(5, 5), 1.0);
  const double to_copy = Score(bus, vocabulary.Transform(fixtures::OrbDescriptors(shifted)).bow);
  for (std::size_t other = 1; other < descriptors_.size(); ++other) {
    const double to_other = Score(bus, vocabulary.Transform(descriptors_[other]).bow);
    EXPECT_GT(to_copy, to_other + 0.1) << kPhotos[other];
  }
}

TEST_F(VocabularyOfPhotos, BowVectorIsSortedPositiveAndSumsToOne) {
  const BowVector bow = vocabulary_->Transform(descriptors_[1]).bow;
  ASSERT_GT(bow.size(), 50U);
  double sum = 0.0;
  for (std::size_t i = 0; i < bow.size(); ++i) {
    if (i > 0) {
      EXPECT_LT(bow[i - 1].word, bow[i].word);
    }
    EXPECT_LT(bow[i].word, vocabulary_->word_count());
    EXPECT_GT(bow[i].weight, 0.0);
    sum += bow[i].weight;
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
}

TEST_F(VocabularyOfPhotos, DirectIndexPutsEveryKeypointUnderOneNodeOfTheAskedLevel) {
  const Vocabulary& vocabulary = *vocabulary_;
  const cv::Mat& descriptors = descriptors_[2];
  for (int levels_up = 0; levels_up <= vocabulary.levels(); ++levels_up) {
    const FeatureVector features = vocabulary.Transform(descriptors, levels_up).features;
    std::vector<int> keypoints;
    for (std::size_t i = 0; i < features.size(); ++i) {
      if (i > 0) {
        EXPECT_LT(features[i - 1].node, features[i].node);
      }
      const int level = vocabulary.Level(features[i].node);
      const bool is_word = vocabulary.tree().nodes[features[i].node].child_count == 0;
      // The node at the asked level, or a word above it.
      EXPECT_TRUE(level == vocabulary.levels() - levels_up || (is_word && level < vocabulary.levels() - levels_up))
          << "levels up " << levels_up << ", node " << features[i].node;
      EXPECT_TRUE(std::is_sorted(features[i].keypoints.begin(), features[i].keypoints.end()));
      keypoints.insert(keypoints.end(), features[i].keypoints.begin(), features[i].keypoints.end());
    }
    std::sort(keypoints.begin(), keypoints.end());
    std::vector<int> every(static_cast<std::size_t>(descriptors.rows));
    std::iota(every.begin(), every.end(), 0);
    EXPECT_EQ(keypoints, every) << "levels up " << levels_up;
  }
  const FeatureVector at_root = vocabulary.Transform(descriptors, vocabulary.levels()).features;
  ASSERT_EQ(at_root.size(), 1U);
  EXPECT_EQ(at_root[0].node, 0U);
}

TEST_F(VocabularyOfPhotos, TrainingIsDeterministicWhateverTheThreadCountAndTheSeedMatters) {
  VocabularyOptions options = Options();
  options.threads = 1;
  const std::vector<std::uint8_t> one_thread = Vocabulary::Train(descriptors_, options).Serialize();
  options.threads = 2;
  const std::vector<std::uint8_t> two_threads = Vocabulary::Train(descriptors_, options).Serialize();
  EXPECT_EQ(one_thread, two_threads);
  EXPECT_EQ(vocabulary_->Serialize(), one_thread);
  options.seed = 2;
  EXPECT_NE(Vocabulary::Train(descriptors_, options).Serialize(), one_thread);
}

TEST_F(VocabularyOfPhotos, SavedAndLoadedGivesTheSameTreeIdentityAndTransforms) {
  const testing::TempDir scratch;
  vocabulary_->Save(scratch / "photos.hbow");
  const Vocabulary loaded = Vocabulary::Load(scratch / "photos.hbow");
  EXPECT_EQ(loaded.tree(), vocabulary_->tree());
  EXPECT_EQ(loaded.identity(), vocabulary_->identity());
  EXPECT_EQ(loaded.identity().size(), 16U);
  for (const cv::Mat& descriptors : descriptors_) {
    EXPECT_EQ(loaded.Transform(descriptors), vocabulary_->Transform(descriptors));
  }
}

TEST_F(VocabularyOfPhotos, TransformOfNothingIsEmptyAndOfAnotherMatrixTypeThrows) {
  EXPECT_EQ(vocabulary_->Transform(cv::Mat()), ImageWords{});
  EXPECT_THROW(vocabulary_->Transform(cv::Mat(10, 32, CV_32F, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(vocabulary_->Transform(cv::Mat(10, 64, CV_8U, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(vocabulary_->Transform(descriptors_[0], -1), std::invalid_argument);
  // Further up than the root is the root.
  EXPECT_EQ(vocabulary_->Transform(descriptors_[0], 4), vocabulary_->Transform(descriptors_[0], 3));
}

// Noisy copies of far-apart prototypes: image i holds copies of prototype 0 and of prototype i + 1.
TEST(Vocabulary, IdfIsTheLogOfImagesOverImagesWithTheWord) {
  std::mt19937 rng(5);
  const auto random_row = [&rng](cv::Mat& row) {
    for (int byte = 0; byte < row.cols; ++byte) row.at<std::uint8_t>(0, byte) = static_cast<std::uint8_t>(rng());
  };
  cv::Mat prototypes(4, kDescriptorBytes, CV_8U);
  for (int p = 0; p < 4; ++p) {
    cv::Mat row = prototypes.row(p);
    random_row(row);
  }
  const auto noisy_copies = [&](int prototype, int count) {
    cv::Mat copies;
    for (int c = 0; c < count; ++c) {
      cv::Mat copy = prototypes.row(prototype).clone();
      copy.at<std::uint8_t>(0, static_cast<int>(rng() % kDescriptorBytes)) ^= 1U << (rng() % 8);
      copies.push_back(copy);
    }
    return copies;
  };
  std::vector<cv::Mat> images;
  for (int i = 0; i < 3; ++i) {
    cv::Mat image = noisy_copies(0, 20);
    image.push_back(noisy_copies(i + 1, 20));
    images.push_back(image);
  }
  VocabularyOptions options;
  options.branching = 4;
  options.levels = 1;
  const Vocabulary vocabulary = Vocabulary::Train(images, options);
  ASSERT_EQ(vocabulary.word_count(), 4U);
  std::vector<double> idf;
  for (WordId word = 0; word < 4; ++word) idf.push_back(vocabulary.idf(word));
  std::sort(idf.begin(), idf.end());
  EXPECT_DOUBLE_EQ(idf[0], 0.0);  // prototype 0's word is in every image
  for (int word = 1; word < 4; ++word) EXPECT_DOUBLE_EQ(idf[static_cast<std::size_t>(word)], std::log(3.0));
  // Prototype 0's word weighs nothing, so an image's bag holds its own prototype's word alone.
  const BowVector bow = vocabulary.Transform(images[1]).bow;
  ASSERT_EQ(bow.size(), 1U);
  EXPECT_DOUBLE_EQ(bow[0].weight, 1.0);
}

TEST(Vocabulary, TrainingWithoutDescriptorsOrWithBadOptionsSaysWhy) {
  try {
    Vocabulary::Train({cv::Mat(), cv::Mat()}, VocabularyOptions{});
    FAIL() << "trained on nothing";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the 2 images gave no descriptor"));
  }
  try {
    Vocabulary::Train({cv::Mat()}, VocabularyOptions{});
    FAIL() << "trained on nothing";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the 1 image gave no descriptor"));
  }
  const std::vector<cv::Mat> some{cv::Mat(3, kDescriptorBytes, CV_8U, cv::Scalar(7))};
  const auto error_of = [&some](VocabularyOptions options) {
    try {
      Vocabulary::Train(some, options);
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error_of({.branching = 1}), HasSubstr("parameter --branching"));
  EXPECT_THAT(error_of({.branching = 65}), HasSubstr("parameter --branching"));
  EXPECT_THAT(error_of({.levels = 0}), HasSubstr("parameter --levels"));
  EXPECT_THAT(error_of({.levels = 9}), HasSubstr("parameter --levels"));
  EXPECT_THAT(error_of({.max_iterations = 0}), HasSubstr("parameter --iterations"));
  EXPECT_THAT(error_of({.threads = -1}), HasSubstr("parameter --threads"));
  EXPECT_THROW(Vocabulary::Train({cv::Mat(3, 16, CV_8U, cv::Scalar(7))}, VocabularyOptions{}), std::invalid_argument);
}

TEST(Vocabulary, EqualDescriptorsMakeOneWordUnderTheRoot) {
  const Vocabulary vocabulary = Vocabulary::Train({cv::Mat(50, kDescriptorBytes, CV_8U, cv::Scalar(42))}, {});
  EXPECT_EQ(vocabulary.node_count(), 2U);
  EXPECT_EQ(vocabulary.word_count(), 1U);
  EXPECT_EQ(Vocabulary::Load(vocabulary.Serialize(), "one-word").tree(), vocabulary.tree());
}

// The vocabulary shipped in data/vocabulary, on real frames it was not trained on.
TEST(ShippedVocabulary, LoadsAndTellsFramesOfOneSceneFromOtherPhotos) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(frame_path, fixtures::kTumFrame);
  const Vocabulary vocabulary = Vocabulary::Load(std::filesystem::path(HOIDSLAM_VOCABULARY_DIR) / "orb-k10-l5.hbow");
  EXPECT_EQ(vocabulary.branching(), 10);
  EXPECT_EQ(vocabulary.levels(), 5);
  EXPECT_GT(vocabulary.word_count(), 20000U);
  EXPECT_LE(vocabulary.word_count(), 100000U);
  EXPECT_GE(vocabulary.training_images(), 100U);

  const BowVector frame = vocabulary.Transform(fixtures::OrbDescriptors(fixtures::ReadGray(frame_path))).bow;
  EXPECT_GT(frame.size(), 500U);  // 1000 keypoints spread over many words
  EXPECT_DOUBLE_EQ(Score(frame, frame), 1.0);
  const cv::Mat later = fixtures::ReadGray(testing::SharedPath(fixtures::kLaterTumFrame));
  const double to_later = Score(frame, vocabulary.Transform(fixtures::OrbDescriptors(later)).bow);
  for (const char* photo : {"photos/bus.jpg", "photos/zidane.jpg", "textures/home.jpg", "textures/board.jpg"}) {
    const cv::Mat other = fixtures::ReadGray(testing::SharedPath(std::string("data/") + photo));
    EXPECT_GT(to_later, Score(frame, vocabulary.Transform(fixtures::OrbDescriptors(other)).bow)) << photo;
  }
}

}  // namespace
}  // namespace hoidslam::bow
