#include "hoidslam/io/rgbd_sequence.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::io {
namespace {

using ::hoidslam::testing::WriteText;

namespace fs = std::filesystem;
using core::InputError;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr int kWidth = 8;
constexpr int kHeight = 6;


void WriteColour(const fs::path& path) {
  ASSERT_TRUE(cv::imwrite(path.string(), cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar(10, 20, 30))));
}

void WriteDepth(const fs::path& path, const cv::Mat& depth) { ASSERT_TRUE(cv::imwrite(path.string(), depth)); }

void WriteDepth(const fs::path& path, std::uint16_t value = 5000) {
  WriteDepth(path, cv::Mat(kHeight, kWidth, CV_16UC1, cv::Scalar(value)));
}

// (rgb time, depth time) of every entry.
std::vector<std::pair<double, double>> Pairs(const RgbdSequence& sequence) {
  std::vector<std::pair<double, double>> pairs;
  for (const SequenceEntry& entry : sequence.entries()) pairs.emplace_back(entry.rgb_timestamp, entry.depth_timestamp);
  return pairs;
}

// A TUM-layout folder in a scratch directory: rgb/ and depth/ with tiny images, list files written on request.
class TumFolder : public ::testing::Test {
 protected:
  void SetUp() override { MakeLayout(scratch_ / "rgbd_dataset_freiburg3_synthetic"); }

  void MakeLayout(const fs::path& root) {
    root_ = root;
    fs::create_directories(root_ / "rgb");
    fs::create_directories(root_ / "depth");
  }

  // Writes rgb/<t>.png and returns its list line.
  std::string Colour(double t) {
    const std::string relative = fmt::format("rgb/{:.6f}.png", t);
    WriteColour(root_ / relative);
    return fmt::format("{:.6f} {}\n", t, relative);
  }
  std::string Depth(double t) {
    const std::string relative = fmt::format("depth/{:.6f}.png", t);
    WriteDepth(root_ / relative);
    return fmt::format("{:.6f} {}\n", t, relative);
  }
  void Lists(const std::string& rgb, const std::string& depth) {
    WriteText(root_ / "rgb.txt", "# color images\n" + rgb);
    WriteText(root_ / "depth.txt", "# depth maps\n" + depth);
  }

  testing::TempDir scratch_;
  fs::path root_;
};

TEST_F(TumFolder, AssociatesPairsCloserThanTheToleranceOnly) {
  Lists(Colour(1.0) + Colour(2.0) + Colour(3.0), Depth(1.01) + Depth(2.03) + Depth(3.019));
  const RgbdSequence sequence = RgbdSequence::OpenTum(root_);
  EXPECT_THAT(Pairs(sequence), ElementsAre(std::pair{1.0, 1.01}, std::pair{3.0, 3.019}));
  EXPECT_EQ(sequence.name(), "rgbd_dataset_freiburg3_synthetic");
  EXPECT_EQ(sequence.entry(1).rgb_path, root_ / "rgb/3.000000.png");
  EXPECT_EQ(sequence.entry(1).depth_path, root_ / "depth/3.019000.png");
  EXPECT_THAT(sequence.Timestamps(), ElementsAre(1.0, 3.0));
  EXPECT_TRUE(sequence.groundtruth().empty());
}

TEST_F(TumFolder, ToleranceIsAnOption) {
  Lists(Colour(1.0) + Colour(2.0), Depth(1.01) + Depth(2.03));
  SequenceOptions options;
  options.max_time_difference = 0.05;
  EXPECT_EQ(RgbdSequence::OpenTum(root_, options).size(), 2u);
}

TEST_F(TumFolder, AssociationIsGreedyClosestFirstAndUsesEachImageOnce) {
  // 1.010–1.008 (2 ms) beats 1.000–1.008 (8 ms), so 1.000 stays unpaired; 5.000 takes the closer of two depths.
  Lists(Colour(1.0) + Colour(1.01) + Colour(5.0), Depth(1.008) + Depth(4.995) + Depth(5.001));
  const RgbdSequence sequence = RgbdSequence::OpenTum(root_);
  EXPECT_THAT(Pairs(sequence), ElementsAre(std::pair{1.01, 1.008}, std::pair{5.0, 5.001}));
}

TEST_F(TumFolder, ToleratesCommentsBlankLinesSeparatorsAndRepeatedTimestamps) {
  Colour(1.0);
  Colour(2.0);
  Colour(3.0);
  WriteColour(root_ / "rgb/replacement.png");
  WriteText(root_ / "rgb.txt",
            "# color images\n\n   # indented comment\n1.000000\trgb/1.000000.png\n"
            "2.000000,rgb/2.000000.png\r\n3.000000    rgb/3.000000.png\n   \n3.000000 rgb/replacement.png\n");
  WriteText(root_ / "depth.txt", Depth(1.0) + Depth(2.0) + Depth(3.0));
  const RgbdSequence sequence = RgbdSequence::OpenTum(root_);
  ASSERT_EQ(sequence.size(), 3u);
  EXPECT_EQ(sequence.entry(2).rgb_path, root_ / "rgb/replacement.png");  // the last line of a repeated time wins
}

TEST_F(TumFolder, ReadsGroundTruthThatStartsAfterTheFirstFrameAndHasGaps) {
  Lists(Colour(1.0) + Colour(1.1) + Colour(1.2), Depth(1.0) + Depth(1.1) + Depth(1.2));
  WriteText(root_ / "groundtruth.txt",
            "# timestamp tx ty tz qx qy qz qw\n1.05 0 0 0 0 0 0 1\n1.06 0.1 0 0 0 0 0 1\n1.19 0.2 0 0 0 0 0 1\n");
  const RgbdSequence sequence = RgbdSequence::OpenTum(root_);
  EXPECT_EQ(sequence.size(), 3u);
  ASSERT_EQ(sequence.groundtruth().size(), 3u);
  EXPECT_DOUBLE_EQ(sequence.groundtruth().front().timestamp, 1.05);
  EXPECT_DOUBLE_EQ(sequence.groundtruth().back().T_wc.translation().x(), 0.2);
}

TEST_F(TumFolder, ReadsAnAssociationsFileInsteadOfTheLists) {
  Colour(1.0);
  Colour(2.0);
  Depth(1.5);
  Depth(2.5);
  WriteText(root_ / "assoc.txt",
            "# t_rgb rgb t_depth depth\n2.0 rgb/2.000000.png 2.5 depth/2.500000.png\n"
            "1.0 rgb/1.000000.png 1.5 depth/1.500000.png\n");
  SequenceOptions options;
  options.associations = "assoc.txt";  // no rgb.txt or depth.txt needed
  const RgbdSequence sequence = RgbdSequence::OpenTum(root_, options);
  EXPECT_THAT(Pairs(sequence), ElementsAre(std::pair{1.0, 1.5}, std::pair{2.0, 2.5}));
  EXPECT_EQ(sequence.entry(0).depth_path, root_ / "depth/1.500000.png");
}

TEST_F(TumFolder, LoadsColourAndDepthInMetres) {
  Lists(Colour(1.0), "");
  cv::Mat depth(kHeight, kWidth, CV_16UC1, cv::Scalar(5000));
  depth.at<std::uint16_t>(0, 0) = 0;
  depth.at<std::uint16_t>(1, 2) = 12345;
  WriteDepth(root_ / "depth/1.png", depth);
  WriteText(root_ / "depth.txt", "1.001 depth/1.png\n");

  const core::RgbdFrame frame = RgbdSequence::OpenTum(root_).LoadFrame(0);
  EXPECT_DOUBLE_EQ(frame.timestamp, 1.0);
  EXPECT_NEAR(frame.depth_delay, 0.001, 1e-12) << "the depth image's stamp less the colour's";
  EXPECT_EQ(frame.rgb.type(), CV_8UC3);
  EXPECT_EQ(frame.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  ASSERT_EQ(frame.depth.type(), CV_32FC1);
  EXPECT_EQ(frame.depth.size(), cv::Size(kWidth, kHeight));
  EXPECT_EQ(frame.depth.at<float>(0, 0), 0.0f);
  EXPECT_FLOAT_EQ(frame.depth.at<float>(0, 1), 1.0f);
  EXPECT_FLOAT_EQ(frame.depth.at<float>(1, 2), 2.469f);
  EXPECT_EQ(frame.depth_path, (root_ / "depth/1.png").string());

  SequenceOptions fr2;
  fr2.depth_factor = 5208.0;
  EXPECT_FLOAT_EQ(RgbdSequence::OpenTum(root_, fr2).LoadFrame(0).depth.at<float>(0, 1), 5000.0f / 5208.0f);
}

TEST_F(TumFolder, RejectsAMissingFolderOrListFile) {
  EXPECT_THAT([&] { RgbdSequence::OpenTum(scratch_ / "nowhere"); },
              ThrowsMessage<InputError>(HasSubstr((scratch_ / "nowhere").string())));
  WriteText(root_ / "depth.txt", Depth(1.0));
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); }, ThrowsMessage<InputError>(HasSubstr("rgb.txt")));
  fs::remove(root_ / "depth.txt");
  WriteText(root_ / "rgb.txt", Colour(1.0));
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); }, ThrowsMessage<InputError>(HasSubstr("depth.txt")));
  SequenceOptions options;
  options.associations = "missing_associations.txt";
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_, options); },
              ThrowsMessage<InputError>(HasSubstr("missing_associations.txt")));
}

TEST_F(TumFolder, NamesFileAndLineOfAnUnparseableLine) {
  Lists(Colour(1.0) + "1.5x rgb/1.000000.png\n", Depth(1.0));  // the comment is line 1
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("rgb.txt:3"), HasSubstr("1.5x"))));
  Lists(Colour(1.0), Depth(1.0) + "2.0\n");
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); }, ThrowsMessage<InputError>(HasSubstr("depth.txt:3")));
  WriteText(root_ / "assoc.txt", "1.0 rgb/1.000000.png 1.0\n");
  SequenceOptions options;
  options.associations = "assoc.txt";
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_, options); }, ThrowsMessage<InputError>(HasSubstr("assoc.txt:1")));
}

TEST_F(TumFolder, NamesListFileLineAndImageOfAMissingImage) {
  Lists(Colour(1.0), Depth(1.0) + "2.0 depth/2.000000.png\n");
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("depth.txt:3"), HasSubstr("depth/2.000000.png"))));
  WriteText(root_ / "assoc.txt",
            "1.0 rgb/1.000000.png 1.0 depth/1.000000.png\n1.1 rgb/gone.png 1.1 depth/1.000000.png\n");
  SequenceOptions options;
  options.associations = "assoc.txt";
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_, options); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("assoc.txt:2"), HasSubstr("rgb/gone.png"))));
}

TEST_F(TumFolder, RejectsImagePathsTheSystemCannotLookUpOrWouldCut) {
  Lists(Colour(1.0) + "1.1 rgb/" + std::string(300, 'x') + ".png\n", Depth(1.0));
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("rgb.txt:3: cannot look at listed image"),
                                              HasSubstr("File name too long"))));
  // The system would read "rgb/1.000000.png", which exists, and ignore the rest.
  using namespace std::string_literals;  // "..."s keeps the NUL byte
  Lists(Colour(1.0) + "1.1 rgb/1.000000.png\0.jpg\n"s, Depth(1.0));
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); },
              ThrowsMessage<InputError>(HasSubstr("rgb.txt:3: the image path contains a NUL byte")));
}

TEST_F(TumFolder, RejectsListsWithNothingToPair) {
  Lists(Colour(1.0), Depth(1.5));
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("rgb.txt"), HasSubstr("depth.txt"))));
  Lists("", Depth(1.5));
  EXPECT_THAT([&] { RgbdSequence::OpenTum(root_); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("rgb.txt"), HasSubstr("no images"))));
}

TEST_F(TumFolder, RejectsANonPositiveDepthFactor) {
  Lists(Colour(1.0), Depth(1.0));
  for (double factor : {0.0, -5000.0}) {
    SequenceOptions options;
    options.depth_factor = factor;
    EXPECT_THAT([&] { RgbdSequence::OpenTum(root_, options); },
                ThrowsMessage<InputError>(HasSubstr("parameter DepthMapFactor")));
  }
}

// The depth file of frame 0, replaced by `write` after the sequence was opened; LoadFrame must name it.
class BadDepth : public TumFolder {
 protected:
  void SetUp() override {
    TumFolder::SetUp();
    Lists(Colour(1.0), Depth(1.0));
    depth_ = root_ / "depth/1.000000.png";
  }
  void ExpectLoadFrameNamesDepthFile(const std::string& what) {
    const RgbdSequence sequence = RgbdSequence::OpenTum(root_);
    EXPECT_THAT([&] { sequence.LoadFrame(0); },
                ThrowsMessage<InputError>(AllOf(HasSubstr(depth_.string()), HasSubstr(what))));
  }
  fs::path depth_;
};

TEST_F(BadDepth, EightBitDepthIsRejected) {
  WriteDepth(depth_, cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(50)));
  ExpectLoadFrameNamesDepthFile("1-channel 8-bit");
}

TEST_F(BadDepth, ThreeChannelDepthIsRejected) {
  WriteDepth(depth_, cv::Mat(kHeight, kWidth, CV_16UC3, cv::Scalar(1, 2, 3)));
  ExpectLoadFrameNamesDepthFile("3-channel 16-bit");
}

TEST_F(BadDepth, GarbageBytesAreRejected) {
  WriteText(depth_, "\x89PNG definitely not an image \x01\x02\x03");
  ExpectLoadFrameNamesDepthFile("cannot decode");
}

TEST_F(BadDepth, TruncatedPngIsRejected) {
  cv::Mat noise(120, 160, CV_16UC1);
  cv::randu(noise, 0, 65535);  // incompressible, so half the file cuts into the image data
  std::vector<uchar> png;
  ASSERT_TRUE(cv::imencode(".png", noise, png));
  WriteText(depth_, std::string(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() / 2)));
  ExpectLoadFrameNamesDepthFile("cannot decode");
}

TEST_F(BadDepth, MissingFileIsRejected) {
  const RgbdSequence sequence = RgbdSequence::OpenTum(root_);
  fs::remove(depth_);
  EXPECT_THAT([&] { sequence.LoadFrame(0); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(depth_.string()), HasSubstr("does not exist"))));
}

TEST_F(BadDepth, SizeDifferentFromTheColourImageIsRejected) {
  WriteDepth(depth_, cv::Mat(kHeight + 1, kWidth, CV_16UC1, cv::Scalar(1)));
  ExpectLoadFrameNamesDepthFile("8x7");
}

// Bonn RGB-D Dynamic folders (rgbd_bonn_<name>) have the TUM layout and nothing TUM-specific is assumed.
TEST_F(TumFolder, OpensABonnStyleFolder) {
  MakeLayout(scratch_ / "rgbd_bonn_crowd2");
  Lists(Colour(1548266469.07481) + Colour(1548266469.10848), Depth(1548266469.07505) + Depth(1548266469.10873));
  WriteText(root_ / "groundtruth.txt", "1548266469.0 1 2 3 0 0 0 1\n");
  const RgbdSequence sequence = RgbdSequence::OpenTum(root_.string() + "/");
  EXPECT_EQ(sequence.name(), "rgbd_bonn_crowd2");
  ASSERT_EQ(sequence.size(), 2u);
  EXPECT_EQ(sequence.groundtruth().size(), 1u);
  EXPECT_EQ(sequence.LoadFrame(1).depth.type(), CV_32FC1);
}

TEST(ImageFolders, PairsImagesInFileNameOrderAtTheGivenRate) {
  testing::TempDir scratch;
  fs::create_directories(scratch / "walk/colour");
  fs::create_directories(scratch / "walk/depth");
  for (const char* name : {"002.png", "000.png", "001.png"}) {
    WriteColour(scratch / "walk/colour" / name);
    WriteDepth(scratch / "walk/depth" / name);
  }
  WriteText(scratch / "walk/colour/notes.txt", "not an image");
  const RgbdSequence sequence = RgbdSequence::OpenImageFolders(scratch / "walk/colour", scratch / "walk/depth", 10.0);
  EXPECT_EQ(sequence.name(), "walk");
  ASSERT_EQ(sequence.size(), 3u);
  EXPECT_THAT(sequence.Timestamps(), ElementsAre(0.0, 0.1, 0.2));
  EXPECT_EQ(sequence.entry(1).rgb_path.filename(), "001.png");
  EXPECT_EQ(sequence.entry(2).depth_path.filename(), "002.png");
  EXPECT_FLOAT_EQ(sequence.LoadFrame(2).depth.at<float>(0, 0), 1.0f);
}

TEST(ImageFolders, RejectsUnequalCountsNamingBothFolders) {
  testing::TempDir scratch;
  fs::create_directories(scratch / "rgb");
  fs::create_directories(scratch / "depth");
  WriteColour(scratch / "rgb/a.png");
  WriteColour(scratch / "rgb/b.jpg");
  WriteDepth(scratch / "depth/a.png");
  EXPECT_THAT([&] { RgbdSequence::OpenImageFolders(scratch / "rgb", scratch / "depth", 30.0); },
              ThrowsMessage<InputError>(AllOf(HasSubstr((scratch / "rgb").string() + " holds 2"),
                                              HasSubstr((scratch / "depth").string() + " holds 1"))));
  EXPECT_THAT([&] { RgbdSequence::OpenImageFolders(scratch / "rgb", scratch / "nowhere", 30.0); },
              ThrowsMessage<InputError>(HasSubstr("nowhere")));
  EXPECT_THAT([&] { RgbdSequence::OpenImageFolders(scratch / "rgb", scratch / "depth", 0.0); },
              ThrowsMessage<InputError>(HasSubstr("parameter fps")));
}

TEST(RealTum, LoadsTheWalkingXyzPair) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(dir, "data/tum/fr3_walking_xyz_pair");
  const RgbdSequence sequence = RgbdSequence::OpenTum(dir);
  ASSERT_EQ(sequence.size(), 2u);
  EXPECT_EQ(sequence.name(), "fr3_walking_xyz_pair");
  EXPECT_FALSE(sequence.groundtruth().empty());
  // Ground truth starts after the first image: matching must go by time, which the timestamps allow.
  EXPECT_GT(sequence.groundtruth().front().timestamp, sequence.entry(0).rgb_timestamp);
  EXPECT_LT(sequence.groundtruth().front().timestamp - sequence.entry(0).rgb_timestamp, 0.1);

  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const core::RgbdFrame frame = sequence.LoadFrame(i);
    EXPECT_EQ(frame.rgb.type(), CV_8UC3);
    EXPECT_EQ(frame.rgb.size(), cv::Size(640, 480));
    ASSERT_EQ(frame.depth.type(), CV_32FC1);
    std::vector<float> valid;
    for (auto it = frame.depth.begin<float>(); it != frame.depth.end<float>(); ++it) {
      if (*it > 0.0f) valid.push_back(*it);
    }
    ASSERT_GT(valid.size(), frame.depth.total() / 4);  // the second frame has depth on 44% of its pixels
    std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
    EXPECT_GT(valid[valid.size() / 2], 0.5f);
    EXPECT_LT(valid[valid.size() / 2], 6.0f);
  }

  // The shipped associations file gives the same pairs as associating rgb.txt with depth.txt.
  SequenceOptions options;
  options.associations = "associations.txt";
  const RgbdSequence associated = RgbdSequence::OpenTum(dir, options);
  ASSERT_EQ(associated.size(), sequence.size());
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    EXPECT_EQ(associated.entry(i).rgb_path, sequence.entry(i).rgb_path);
    EXPECT_EQ(associated.entry(i).depth_path, sequence.entry(i).depth_path);
  }
}

// Associating the images of each real fr3 sequence's timing reproduces the association list TUM's tool made.
TEST(RealTum, AssociationReproducesTheShippedListsOfWholeSequences) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(folder, "data/tum/associations");
  std::size_t sequences = 0;
  for (const fs::directory_entry& file : fs::directory_iterator(folder)) {
    SCOPED_TRACE(file.path());
    testing::TempDir root;
    WriteText(root / "image.png", "");  // never decoded: association only needs listed files to exist
    std::ifstream in(file.path());
    std::string rgb_list, depth_list, t_rgb, rgb, t_depth, depth;
    std::vector<std::pair<double, double>> expected;
    while (in >> t_rgb >> rgb >> t_depth >> depth) {
      rgb_list += t_rgb + " image.png\n";
      depth_list += t_depth + " image.png\n";
      expected.emplace_back(std::stod(t_rgb), std::stod(t_depth));
    }
    WriteText(root / "rgb.txt", rgb_list);
    WriteText(root / "depth.txt", depth_list);
    ASSERT_GT(expected.size(), 600u);
    EXPECT_EQ(Pairs(RgbdSequence::OpenTum(root.path())), expected);
    ++sequences;
  }
  EXPECT_EQ(sequences, 8u);
}

}  // namespace
}  // namespace hoidslam::io
