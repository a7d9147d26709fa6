#include "hoidslam/pipeline/dynamic_mask.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/detect/file_detector.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/sequence_writer.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::pipeline::dynamic_mask_test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

core::Detection Det(const std::string& label, float x, float y, float w, float h) {
  return {.class_id = -1, .label = label, .score = 0.9F, .box = cv::Rect2f(x, y, w, h)};
}

hoid::Decision Dynamic() { return {.dynamic = true, .reason = hoid::Reason::kPerson}; }
hoid::Decision Static() { return {.dynamic = false, .reason = hoid::Reason::kNotPotentiallyDynamic}; }

// The pixels of `size` inside `rect` (whole pixels) set to 255.
cv::Mat Expected(cv::Size size, cv::Rect rect) {
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  mask(rect & cv::Rect(cv::Point(0, 0), size)).setTo(255);
  return mask;
}

bool SameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::countNonZero(a != b) == 0;
}

// The mask pixel a keypoint at `p` is looked up at: (floor(x), floor(y)), as stella_vslam and DynaSLAM do.
std::uint8_t At(const cv::Mat& mask, cv::Point2f p) {
  return mask.at<std::uint8_t>(static_cast<int>(std::floor(p.y)), static_cast<int>(std::floor(p.x)));
}

// Whether `p` lies within 0.5 px (inclusive) of the boundary of `box`.
bool NearBoxEdge(const cv::Rect2f& box, cv::Point2f p) {
  const float x1 = box.x + box.width;
  const float y1 = box.y + box.height;
  const bool near_outside = p.x >= box.x - 0.5F && p.x <= x1 + 0.5F && p.y >= box.y - 0.5F && p.y <= y1 + 0.5F;
  const bool deep_inside = p.x > box.x + 0.5F && p.x < x1 - 0.5F && p.y > box.y + 0.5F && p.y < y1 - 0.5F;
  return near_outside && !deep_inside;
}

// ---- the rasteriser ----------------------------------------------------------------------------------------------

TEST(PaintDynamicBoxes, MarksThePixelsOfDynamicBoxesOnly) {
  const std::vector<core::Detection> detections = {Det("person", 2, 1, 3, 2), Det("tv", 6, 4, 2, 2)};
  const cv::Mat mask = PaintDynamicBoxes(detections, std::vector{Dynamic(), Static()}, cv::Size(10, 8));
  ASSERT_EQ(mask.type(), CV_8UC1);
  EXPECT_TRUE(SameImage(mask, Expected(cv::Size(10, 8), cv::Rect(2, 1, 3, 2))));
}

TEST(PaintDynamicBoxes, NothingDynamicLeavesEveryPixelClear) {
  const std::vector<core::Detection> detections = {Det("tv", 1, 1, 5, 5)};
  EXPECT_EQ(cv::countNonZero(PaintDynamicBoxes(detections, std::vector{Static()}, cv::Size(8, 8))), 0);
  EXPECT_EQ(cv::countNonZero(PaintDynamicBoxes({}, {}, cv::Size(8, 8))), 0);
}

TEST(PaintDynamicBoxes, AFractionalEdgeTakesThePixelsWhoseCentreItReaches) {
  // Columns 2..4 have centres 2.5, 3.5, 4.5: a left edge at 2.5 takes column 2 (inside is x0 <= x), one at 2.6
  // does not; a right edge at 5.5 stops before column 5 (x < x1), one at 5.6 takes it.
  const auto columns = [](float x0, float x1) {
    const cv::Mat mask = PaintDynamicBoxes(std::vector{Det("person", x0, 0, x1 - x0, 1)}, std::vector{Dynamic()},
                                           cv::Size(10, 1));
    std::string row;
    for (int c = 0; c < mask.cols; ++c) row += mask.at<std::uint8_t>(0, c) != 0 ? '#' : '.';
    return row;
  };
  EXPECT_EQ(columns(2.5F, 5.5F), "..###.....");
  EXPECT_EQ(columns(2.4F, 5.5F), "..###.....");
  EXPECT_EQ(columns(2.6F, 5.5F), "...##.....");
  EXPECT_EQ(columns(2.5F, 5.6F), "..####....");
  EXPECT_EQ(columns(2.6F, 2.9F), "..........");  // narrower than a pixel and over no centre: nothing
}

TEST(PaintDynamicBoxes, ClipsBoxesAtTheImageBorder) {
  const cv::Size size(8, 6);
  const auto paint = [&](const core::Detection& d) { return PaintDynamicBoxes(std::vector{d}, std::vector{Dynamic()}, size); };
  EXPECT_TRUE(SameImage(paint(Det("person", -3, -2, 6, 5)), Expected(size, cv::Rect(0, 0, 3, 3))));
  EXPECT_TRUE(SameImage(paint(Det("person", 6, 4, 100, 100)), Expected(size, cv::Rect(6, 4, 2, 2))));
  EXPECT_TRUE(SameImage(paint(Det("person", -1e9F, -1e9F, 3e9F, 3e9F)), Expected(size, cv::Rect(0, 0, 8, 6))));
  EXPECT_EQ(cv::countNonZero(paint(Det("person", 20, 20, 5, 5))), 0);     // wholly outside
  EXPECT_EQ(cv::countNonZero(paint(Det("person", -9, 1, 5, 3))), 0);      // wholly left of the image
  EXPECT_EQ(cv::countNonZero(paint(Det("person", std::numeric_limits<float>::quiet_NaN(), 1, 5, 3))), 0);     // run drops nothing for it either
}

TEST(PaintDynamicBoxes, RejectsDecisionsThatDoNotMatchTheDetections) {
  EXPECT_THROW(PaintDynamicBoxes(std::vector{Det("person", 0, 0, 1, 1)}, {}, cv::Size(4, 4)), std::invalid_argument);
}

// The convention of dynamic_mask.h: a keypoint is dropped by run exactly when its pixel (floor(x), floor(y)) is
// marked, except within 0.5 px of a fractional box edge; with whole-pixel edges, everywhere.
TEST(PaintDynamicBoxes, AgreesWithRunsKeypointTestExceptWithinHalfAPixelOfAnEdge) {
  const cv::Size size(64, 48);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coordinate(-10.0F, 70.0F);
  std::uniform_real_distribution<float> extent(0.0F, 30.0F);
  std::bernoulli_distribution coin(0.5);
  for (const bool whole_pixels : {true, false}) {
    SCOPED_TRACE(whole_pixels ? "whole-pixel edges" : "fractional edges");
    std::vector<core::Detection> detections;
    std::vector<hoid::Decision> decisions;
    for (int i = 0; i < 20; ++i) {
      cv::Rect2f box(coordinate(rng), coordinate(rng), extent(rng), extent(rng));
      if (whole_pixels) box = cv::Rect2f(std::round(box.x), std::round(box.y), std::round(box.width), std::round(box.height));
      detections.push_back({.label = "person", .box = box});
      decisions.push_back(coin(rng) ? Dynamic() : Static());
    }
    const cv::Mat mask = PaintDynamicBoxes(detections, decisions, size);
    // Keypoints on whole pixels (the pyramid's first level), on half pixels and anywhere.
    std::vector<cv::Point2f> points;
    std::uniform_real_distribution<float> u(0.0F, 64.0F), v(0.0F, 48.0F);
    for (int i = 0; i < 20000; ++i) {
      const cv::Point2f p(u(rng), v(rng));
      points.push_back(i % 3 == 0 ? cv::Point2f(std::floor(p.x), std::floor(p.y))
                       : i % 3 == 1 ? cv::Point2f(std::floor(p.x) + 0.5F, std::floor(p.y) + 0.5F)
                                    : p);
    }
    std::vector<std::uint8_t> keep;
    hoid::MarkKeypointsToKeep(points, detections, decisions, keep);
    std::size_t dropped = 0, differ = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      dropped += keep[i] == 0 ? 1 : 0;
      if ((keep[i] == 0) == (At(mask, points[i]) != 0)) continue;
      ++differ;
      bool near_edge = false;
      for (std::size_t d = 0; d < detections.size(); ++d) {
        near_edge |= decisions[d].dynamic && NearBoxEdge(detections[d].box, points[i]);
      }
      EXPECT_TRUE(near_edge) << "keypoint (" << points[i].x << ", " << points[i].y << ") is far from every edge";
    }
    EXPECT_GT(dropped, 1000U);  // the boxes cover a good part of the image
    if (whole_pixels) {
      EXPECT_EQ(differ, 0U);
    }
  }
}

TEST(DilateMask, GrowsARegionOnEverySideAndStopsAtTheBorder) {
  const cv::Size size(12, 10);
  cv::Mat mask = Expected(size, cv::Rect(4, 3, 2, 2));
  DilateMask(mask, 0);
  EXPECT_TRUE(SameImage(mask, Expected(size, cv::Rect(4, 3, 2, 2))));
  DilateMask(mask, 2);
  EXPECT_TRUE(SameImage(mask, Expected(size, cv::Rect(2, 1, 6, 6))));
  DilateMask(mask, 3);  // reaches the top and left borders
  EXPECT_TRUE(SameImage(mask, Expected(size, cv::Rect(0, 0, 11, 10))));
  EXPECT_THROW(DilateMask(mask, -1), std::invalid_argument);
}

TEST(EncodeMask, WritesEachToolsValues) {
  const cv::Mat marked = Expected(cv::Size(4, 1), cv::Rect(1, 0, 2, 1));
  const auto row = [&](MaskFormat format) {
    const cv::Mat encoded = EncodeMask(marked, format);
    EXPECT_EQ(encoded.type(), CV_8UC1);
    return std::vector<int>{encoded.at<std::uint8_t>(0, 0), encoded.at<std::uint8_t>(0, 1),
                            encoded.at<std::uint8_t>(0, 2), encoded.at<std::uint8_t>(0, 3)};
  };
  EXPECT_EQ(row(MaskFormat::kHoidslam), (std::vector<int>{0, 255, 255, 0}));
  EXPECT_EQ(row(MaskFormat::kStella), (std::vector<int>{255, 0, 0, 255}));  // 0: stella extracts nothing there
  EXPECT_EQ(row(MaskFormat::kDynaslam), (std::vector<int>{0, 1, 1, 0}));    // 1: Mask R-CNN's foreground
}

TEST(ParseMaskFormat, NamesTheParameterAndTheChoices) {
  EXPECT_EQ(ParseMaskFormat("stella"), MaskFormat::kStella);
  EXPECT_EQ(ToString(MaskFormat::kDynaslam), "dynaslam");
  try {
    ParseMaskFormat("orbslam3", "--format");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--format"));
    EXPECT_THAT(e.what(), HasSubstr("hoidslam, stella or dynaslam"));
  }
}

TEST(MaskExportOptions, NamesANegativeDilation) {
  MaskExportOptions options;
  options.dilate = -2;
  try {
    options.Check();
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--dilate"));
  }
}

// ---- the export ------------------------------------------------------------------------------------------------

// `n` frames of 32×24 colour (`extension`) and depth images in <dir>/rgb and <dir>/depth, played at 10 fps.
io::RgbdSequence SmallSequence(const testing::TempDir& dir, int n, const std::string& extension = ".png") {
  fs::create_directories(dir / "seq" / "rgb");
  fs::create_directories(dir / "seq" / "depth");
  for (int i = 0; i < n; ++i) {
    const std::string name = fmt::format("{:.6f}", 100.0 + i);
    cv::imwrite((dir / "seq" / "rgb" / (name + extension)).string(), cv::Mat(24, 32, CV_8UC3, cv::Scalar(90, 90, 90)));
    cv::imwrite((dir / "seq" / "depth" / (name + ".png")).string(), cv::Mat(24, 32, CV_16UC1, cv::Scalar(5000)));
  }
  return io::RgbdSequence::OpenImageFolders(dir / "seq" / "rgb", dir / "seq" / "depth", 10.0);
}

// A person box that moves one pixel right per frame; it fails on the frames listed.
class ScriptedDetector final : public detect::Detector {
 public:
  explicit ScriptedDetector(std::vector<std::size_t> failing = {}) : failing_(std::move(failing)) {}
  std::vector<core::Detection> Detect(double /*timestamp*/, const cv::Mat& /*bgr*/) override {
    const std::size_t call = calls_++;
    if (std::find(failing_.begin(), failing_.end(), call) != failing_.end()) {
      throw core::InputError("no detections for this frame");
    }
    return {Det("person", 4.0F + static_cast<float>(call), 2, 8, 12), Det("tv", 20, 2, 6, 6)};
  }
  std::string Name() const override { return "scripted"; }

 private:
  std::vector<std::size_t> failing_;
  std::size_t calls_ = 0;
};

// Masks of mode hoid2d in `format`, written to `out`.
MaskExportOptions MasksTo(const fs::path& out, MaskFormat format = MaskFormat::kHoidslam) {
  MaskExportOptions options;
  options.exclusion.hoid.mode = core::FilterMode::kHoid2d;
  options.format = format;
  options.out = out;
  return options;
}

cv::Mat ReadMask(const fs::path& path) { return cv::imread(path.string(), cv::IMREAD_UNCHANGED); }

TEST(ExportMasks, WritesOneMaskPerFrameNamedLikeItsColourImageAndAList) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = SmallSequence(dir, 3);
  ScriptedDetector detector;
  const MaskExportSummary summary = ExportMasks(sequence, detector, MasksTo(dir / "masks", MaskFormat::kStella));
  EXPECT_EQ(summary.frames, 3U);
  EXPECT_EQ(summary.detector_failures, 0U);
  EXPECT_NEAR(summary.mean_masked_share, 8.0 * 12.0 / (32.0 * 24.0), 1e-9);  // the person; the tv is static

  for (int i = 0; i < 3; ++i) {
    const cv::Mat mask = ReadMask(dir / "masks" / fmt::format("{:.6f}.png", 100.0 + i));
    ASSERT_EQ(mask.type(), CV_8UC1) << i;
    // stella: 0 on the person's pixels, 255 everywhere else.
    cv::Mat expected(24, 32, CV_8UC1, cv::Scalar(255));
    expected(cv::Rect(4 + i, 2, 8, 12)).setTo(0);
    EXPECT_TRUE(SameImage(mask, expected)) << i;
  }
  EXPECT_EQ(testing::ReadText(dir / "masks" / "masks.txt"),
            "# hoidslam masks of seq: filter hoid2d, format stella (0 dynamic, 255 static), dilated 0 px\n"
            "# timestamp filename\n"
            "0.000000 100.000000.png\n"
            "0.100000 101.000000.png\n"
            "0.200000 102.000000.png\n");
}

TEST(ExportMasks, AFailedFrameReusesThePreviousDetectionsAsRunDoes) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = SmallSequence(dir, 3);
  ScriptedDetector detector({1});
  MaskExportOptions options = MasksTo(dir / "masks");
  options.dilate = 1;
  const MaskExportSummary summary = ExportMasks(sequence, detector, options);
  EXPECT_EQ(summary.detector_failures, 1U);
  // Frame 1 has frame 0's box; every box grown by a pixel on each side.
  EXPECT_TRUE(SameImage(ReadMask(dir / "masks" / "101.000000.png"), Expected(cv::Size(32, 24), cv::Rect(3, 1, 10, 14))));
  EXPECT_TRUE(SameImage(ReadMask(dir / "masks" / "102.000000.png"), Expected(cv::Size(32, 24), cv::Rect(5, 1, 10, 14))));
}

TEST(ExportMasks, StopsWhenAskedAndLeavesNoFolder) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = SmallSequence(dir, 5);
  ScriptedDetector detector;
  MaskExportOptions options = MasksTo(dir / "masks");
  int polls = 0;
  options.stop_requested = [&polls] { return ++polls > 2; };
  EXPECT_THROW(ExportMasks(sequence, detector, options), core::Interrupted);
  EXPECT_EQ(polls, 3);
  EXPECT_FALSE(fs::exists(dir / "masks"));
}

TEST(ExportMasks, DynaslamFormatNeedsPngColourImages) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = SmallSequence(dir, 2, ".jpg");
  ScriptedDetector detector;
  try {
    ExportMasks(sequence, detector, MasksTo(dir / "masks", MaskFormat::kDynaslam));
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("100.000000.jpg"));
  }
  EXPECT_FALSE(fs::exists(dir / "masks"));
  // The other formats name the mask <stem>.png whatever the colour image is.
  ExportMasks(sequence, detector, MasksTo(dir / "masks", MaskFormat::kStella));
  EXPECT_TRUE(fs::exists(dir / "masks" / "100.000000.png"));
}

TEST(ExportMasks, OracleNeedsTheGroundTruthMasks) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = SmallSequence(dir, 2);
  detect::NoDetector detector;
  MaskExportOptions options = MasksTo(dir / "masks");
  options.exclusion.oracle = true;
  try {
    ExportMasks(sequence, detector, options);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mask"));
  }
  EXPECT_FALSE(fs::exists(dir / "masks"));
}

// ---- agreement with `hoidslam run` on a synthetic sequence --------------------------------------------------------

struct Agreement {
  std::size_t keypoints = 0;
  std::size_t dropped = 0;  // by run's exclusion
  std::size_t differ = 0;   // dropped by run but clear in the mask, or the other way round
};

// Extracts every frame's ORB keypoints as `hoidslam run` does, marks them with run's own KeypointExclusion and
// compares each verdict with the exported mask at (floor(x), floor(y)). A keypoint may differ only where
// `near_edge` says it lies within 0.5 px of an edge.
using NearEdge = std::function<bool(const core::RgbdFrame&, std::span<const core::Detection>,
                                    std::span<const hoid::Decision>, cv::Point2f)>;
void CompareWithRun(const io::RgbdSequence& sequence, const MaskExportOptions& options, const NearEdge& near_edge,
                    Agreement& agreement) {
  RunOptions run = RunOptions::FromSettings(io::Settings{});
  run.system.deterministic = true;
  slam::System system(run.system);
  KeypointExclusion exclusion(options.exclusion, sequence.root());
  detect::FileDetector detector(sequence.root() / "detections.jsonl");
  const MaskValues values = ValuesOf(options.format);
  std::vector<std::uint8_t> keep;
  hoid::JudgedBoxes boxes;
  const std::vector<hoid::Decision>& decisions = boxes.decisions;
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const core::RgbdFrame frame = sequence.LoadFrame(i);
    const std::vector<cv::KeyPoint> keypoints = system.Extract(frame.rgb).keypoints;
    const std::vector<core::Detection> detections = detector.Detect(frame.timestamp, frame.rgb);
    exclusion.Mark(frame, detections, keypoints, cv::Mat(), keep, boxes);
    const cv::Mat mask = ReadMask(options.out / (sequence.entry(i).rgb_path.stem().string() + ".png"));
    ASSERT_EQ(mask.type(), CV_8UC1) << i;
    ASSERT_EQ(mask.size(), frame.rgb.size()) << i;
    ASSERT_EQ(cv::countNonZero((mask != values.dynamic) & (mask != values.clear)), 0) << i;
    for (std::size_t k = 0; k < keypoints.size(); ++k) {
      const cv::Point2f p = keypoints[k].pt;
      const bool dropped = keep[k] == 0;
      agreement.dropped += dropped ? 1 : 0;
      if (dropped != (At(mask, p) == values.dynamic)) {
        ++agreement.differ;
        EXPECT_TRUE(near_edge(frame, detections, decisions, p))
            << "frame " << i << ": keypoint (" << p.x << ", " << p.y << ") " << (dropped ? "dropped" : "kept")
            << " by run, far from an edge";
      }
    }
    agreement.keypoints += keypoints.size();
  }
}

TEST(ExportMasks, AgreesWithRunsExclusionKeypointByKeypoint) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(tum_dir, "data/tum");
  const testing::TempDir dir;
  // Every 4th frame of walking_xyz (people are in view from about the 25th), with jittered boxes so that their
  // edges fall at fractions of a pixel.
  synth::Scenario scenario = synth::LoadScenario("walking_xyz");
  scenario.max_frames = 40 * 4;
  scenario.detector_noise.box_jitter = 0.02;
  synth::SynthOptions synth_options;
  synth_options.out = dir / "walking_xyz";
  synth_options.tum_dir = tum_dir;
  synth_options.frame_step = 4;
  synth::WriteSequence(scenario, synth_options);
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(synth_options.out);

  {
    SCOPED_TRACE("hoid2d");
    detect::FileDetector detector(synth_options.out / "detections.jsonl");
    const MaskExportOptions options = MasksTo(dir / "hoid2d", MaskFormat::kDynaslam);
    ExportMasks(sequence, detector, options);
    Agreement agreement;
    CompareWithRun(sequence, options,
                   [](const core::RgbdFrame&, std::span<const core::Detection> detections,
                      std::span<const hoid::Decision> decisions, cv::Point2f p) {
                     for (std::size_t d = 0; d < detections.size(); ++d) {
                       if (decisions[d].dynamic && NearBoxEdge(detections[d].box, p)) return true;
                     }
                     return false;
                   },
                   agreement);
    EXPECT_GT(agreement.dropped, 1000U);
    EXPECT_LT(static_cast<double>(agreement.differ), 0.002 * static_cast<double>(agreement.keypoints));
  }
  {
    SCOPED_TRACE("oracle");
    detect::NoDetector detector;
    MaskExportOptions options = MasksTo(dir / "oracle", MaskFormat::kStella);
    options.exclusion.oracle = true;
    ExportMasks(sequence, detector, options);
    Agreement agreement;
    // Run reads the ground truth at (round(x), round(y)), the tools at (floor(x), floor(y)): they can only
    // differ where the ground truth changes between those two pixels, i.e. within 0.5 px of a region's edge.
    CompareWithRun(sequence, options,
                   [&sequence](const core::RgbdFrame& frame, std::span<const core::Detection>,
                               std::span<const hoid::Decision>, cv::Point2f p) {
                     const cv::Mat truth = ReadMask(sequence.root() / "mask" / fs::path(frame.rgb_path).filename());
                     const auto round = [](float v) { return static_cast<int>(std::lround(v)); };
                     return At(truth, p) != truth.at<std::uint8_t>(round(p.y), round(p.x));
                   },
                   agreement);
    EXPECT_GT(agreement.dropped, 200U);  // moving pixels are fewer than the boxes around them
    EXPECT_LT(static_cast<double>(agreement.differ), 0.002 * static_cast<double>(agreement.keypoints));
  }
}

}  // namespace
}  // namespace hoidslam::pipeline::dynamic_mask_test
