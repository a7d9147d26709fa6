#include "hoidslam/synth/textures.h"

#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/test_scenarios.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::synth::textures_test {
namespace {

TextureOptions Options(int size, std::uint64_t seed = 1) {
  TextureOptions options;
  options.size = size;
  options.seed = seed;
  return options;
}

std::string Message(const TextureOptions& options) {
  try {
    const TextureSet textures(options);
  } catch (const core::InputError& error) {
    return error.what();
  }
  return "";
}

TEST(Textures, EveryRoleHasItsVariantsAndMipmaps) {
  const TextureSet& textures = fixtures::DefaultTextures();
  const TextureOptions defaults;
  int expected = 0;
  for (int r = 0; r < kTextureRoleCount; ++r) {
    const auto role = static_cast<TextureRole>(r);
    EXPECT_EQ(ParseTextureRole(ToString(role), "texture"), role);
    const int count = textures.VariantCount(role);
    EXPECT_TRUE(count == 1 || count == defaults.variants) << ToString(role);
    expected += count;
    // Variants wrap around in both directions.
    EXPECT_EQ(textures.Index(role, count), textures.Index(role, 0));
    EXPECT_EQ(textures.Index(role, -1), textures.Index(role, count - 1));
  }
  EXPECT_EQ(textures.VariantCount(TextureRole::kShirt), defaults.variants);
  EXPECT_EQ(textures.VariantCount(TextureRole::kWall), 1);
  ASSERT_EQ(textures.size(), expected);
  for (int i = 0; i < textures.size(); ++i) {
    const std::vector<cv::Mat>& levels = textures.Levels(i);
    ASSERT_EQ(levels.size(), 7U);  // 256, 128, ..., 4
    for (std::size_t level = 0; level < levels.size(); ++level) {
      EXPECT_EQ(levels[level].type(), CV_8UC3);
      EXPECT_EQ(levels[level].cols, 256 >> level);
      EXPECT_EQ(levels[level].rows, 256 >> level);
    }
  }
}

// ORB needs corners: every texture but skin (smooth on purpose) has many strong ones, and real contrast.
TEST(Textures, ProceduralTexturesAreRichInCorners) {
  const TextureSet& textures = fixtures::DefaultTextures();
  for (int r = 0; r < kTextureRoleCount; ++r) {
    const auto role = static_cast<TextureRole>(r);
    for (int variant = 0; variant < textures.VariantCount(role); ++variant) {
      cv::Mat grey;
      cv::cvtColor(textures.Image(textures.Index(role, variant)), grey, cv::COLOR_BGR2GRAY);
      cv::Scalar mean;
      cv::Scalar std;
      cv::meanStdDev(grey, mean, std);
      std::vector<cv::Point2f> corners;
      cv::goodFeaturesToTrack(grey, corners, 500, 0.02, 4.0);
      const std::string name = std::string(ToString(role)) + " " + std::to_string(variant);
      if (role == TextureRole::kSkin) continue;
      EXPECT_GT(std[0], 6.0) << name;
      EXPECT_GE(corners.size(), 30U) << name;
    }
  }
}

TEST(Textures, SameSeedSameImagesOtherSeedOtherImages) {
  const TextureSet a(Options(64, 7));
  const TextureSet b(Options(64, 7));
  const TextureSet c(Options(64, 8));
  ASSERT_EQ(a.size(), c.size());
  int differing = 0;
  for (int i = 0; i < a.size(); ++i) {
    EXPECT_EQ(cv::norm(a.Image(i), b.Image(i), cv::NORM_INF), 0.0) << i;
    differing += cv::norm(a.Image(i), c.Image(i), cv::NORM_INF) > 0.0 ? 1 : 0;
  }
  EXPECT_EQ(differing, a.size());
}

TEST(Textures, PhotosReplaceWallDeskAndPosters) {
  testing::TempDir dir;
  cv::Mat red(100, 200, CV_8UC3, cv::Scalar(0, 0, 255));  // not square: centre-cropped
  red(cv::Rect(0, 0, 50, 100)).setTo(cv::Scalar(255, 0, 0));
  ASSERT_TRUE(cv::imwrite((dir / "b_red.png").string(), red));
  ASSERT_TRUE(cv::imwrite((dir / "a_green.jpg").string(), cv::Mat(64, 64, CV_8UC3, cv::Scalar(0, 255, 0))));
  { std::ofstream(dir / "notes.txt") << "not an image\n"; }
  TextureOptions options = Options(32);
  options.photo_folder = dir.path();
  const TextureSet textures(options);
  ASSERT_EQ(textures.VariantCount(TextureRole::kPoster), 2);
  const auto mean_of = [&](TextureRole role, int variant) { return cv::mean(textures.Image(textures.Index(role, variant))); };
  EXPECT_GT(mean_of(TextureRole::kWall, 0)[1], 240.0);    // a_green.jpg, first by name
  EXPECT_GT(mean_of(TextureRole::kDesk, 0)[2], 240.0);    // b_red.png, its blue strip cropped away
  EXPECT_LT(mean_of(TextureRole::kDesk, 0)[0], 10.0);
  EXPECT_GT(mean_of(TextureRole::kPoster, 0)[1], 240.0);
  EXPECT_GT(mean_of(TextureRole::kPoster, 1)[2], 240.0);
  // Everything else stays procedural.
  EXPECT_EQ(cv::norm(textures.Image(textures.Index(TextureRole::kShirt, 1)),
                     TextureSet(Options(32)).Image(TextureSet(Options(32)).Index(TextureRole::kShirt, 1)), cv::NORM_INF),
            0.0);
}

TEST(Textures, SharedPhotoFolderLoads) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(folder, "data/textures");
  TextureOptions options = Options(128);
  options.photo_folder = folder;
  const TextureSet textures(options);
  EXPECT_EQ(textures.VariantCount(TextureRole::kPoster), 12);
}

TEST(Textures, BadInputNamesTheFolderFileOrParameter) {
  testing::TempDir dir;
  TextureOptions options = Options(32);
  options.photo_folder = dir / "absent";
  EXPECT_NE(Message(options).find("absent"), std::string::npos);
  options.photo_folder = dir.path();
  EXPECT_NE(Message(options).find("no .jpg"), std::string::npos);
  { std::ofstream(dir / "broken.jpg") << "not a jpeg"; }
  EXPECT_NE(Message(options).find("broken.jpg"), std::string::npos);

  EXPECT_NE(Message(Options(100)).find("textures.size"), std::string::npos);
  TextureOptions no_variants = Options(32);
  no_variants.variants = 0;
  EXPECT_NE(Message(no_variants).find("textures.variants"), std::string::npos);
  try {
    ParseTextureRole("marble", "office.desk.texture");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("office.desk.texture"), std::string::npos);
  }
}

}  // namespace
}  // namespace hoidslam::synth::textures_test
