#include "hoidslam/pipeline/dynamic_mask.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/progress.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/files.h"
#include "hoidslam/pipeline/run.h"

namespace hoidslam::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr core::EnumNames<MaskFormat, 3> kFormatNames = {{
    {MaskFormat::kHoidslam, "hoidslam"},
    {MaskFormat::kStella, "stella"},
    {MaskFormat::kDynaslam, "dynaslam"},
}};

// The pixels i of a row (or column) of `n` whose centre i + 0.5 lies in [lo, hi): from ceil(lo - 0.5) up to,
// not including, ceil(hi - 0.5), clipped to [0, n). In double, so that far-off edges cannot overflow an int.
std::pair<int, int> CentresInside(float lo, float hi, int n) {
  if (std::isnan(lo) || std::isnan(hi)) return {0, 0};
  const auto clip = [n](double v) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(n))); };
  return {clip(std::ceil(static_cast<double>(lo) - 0.5)), clip(std::ceil(static_cast<double>(hi) - 0.5))};
}

// DynaSLAM reads <mask folder>/<the colour image's file name>, so a mask named <stem>.png is found only when
// the colour image is a .png itself; anything else would silently send DynaSLAM back to its own network.
void CheckDynaslamNames(const io::RgbdSequence& sequence, std::size_t frames) {
  for (std::size_t i = 0; i < frames; ++i) {
    const fs::path& rgb = sequence.entry(i).rgb_path;
    if (rgb.extension() != ".png") {
      throw core::InputError::InFile(rgb, "is not a .png: DynaSLAM looks a mask up by its colour image's file "
                                          "name, so --format dynaslam needs .png colour images");
    }
  }
}

}  // namespace

std::string_view ToString(MaskFormat format) { return core::EnumName(kFormatNames, format); }

MaskFormat ParseMaskFormat(std::string_view text, const std::string& parameter) {
  return core::ParseEnumName(kFormatNames, text, parameter, "mask format");
}

MaskValues ValuesOf(MaskFormat format) {
  switch (format) {
    case MaskFormat::kHoidslam: return {.dynamic = 255, .clear = 0};
    case MaskFormat::kStella: return {.dynamic = 0, .clear = 255};
    case MaskFormat::kDynaslam: return {.dynamic = 1, .clear = 0};
  }
  throw std::invalid_argument("ValuesOf: unknown mask format");
}

cv::Mat PaintDynamicBoxes(std::span<const core::Detection> detections, std::span<const hoid::Decision> decisions,
                          cv::Size size) {
  if (decisions.size() != detections.size()) {
    throw std::invalid_argument(fmt::format("PaintDynamicBoxes: {} decisions for {} detections", decisions.size(),
                                            detections.size()));
  }
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  for (std::size_t d = 0; d < detections.size(); ++d) {
    if (!decisions[d].dynamic) continue;
    const cv::Rect2f& box = detections[d].box;
    // The same float edges as hoid::MarkKeypointsToKeep compares keypoints with.
    const auto [c0, c1] = CentresInside(box.x, box.x + box.width, size.width);
    const auto [r0, r1] = CentresInside(box.y, box.y + box.height, size.height);
    if (c0 < c1 && r0 < r1) mask(cv::Range(r0, r1), cv::Range(c0, c1)).setTo(255);
  }
  return mask;
}

void DilateMask(cv::Mat& mask, int pixels) {
  if (pixels < 0) throw std::invalid_argument(fmt::format("DilateMask: {} pixels", pixels));
  if (pixels == 0) return;
  const cv::Mat square = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * pixels + 1, 2 * pixels + 1));
  cv::dilate(mask, mask, square);
}

cv::Mat EncodeMask(const cv::Mat& marked, MaskFormat format) {
  const MaskValues values = ValuesOf(format);
  cv::Mat encoded(marked.size(), CV_8UC1, cv::Scalar(values.clear));
  encoded.setTo(values.dynamic, marked);
  return encoded;
}

void MaskExportOptions::Check() const {
  exclusion.hoid.Check();
  if (dilate < 0) throw core::InputError::ForParameter("--dilate", fmt::format("must be >= 0, got {}", dilate));
}

MaskExportSummary ExportMasks(const io::RgbdSequence& sequence, detect::Detector& detector,
                              const MaskExportOptions& options) {
  options.Check();
  // Run's own exclusion: the same checks (an oracle needs mask/), and the same verdicts on the detections.
  KeypointExclusion exclusion(options.exclusion, sequence.root(), options.camera);
  const std::size_t total = FramesToPlay(options.max_frames, sequence.size());
  if (options.format == MaskFormat::kDynaslam) CheckDynaslamNames(sequence, total);

  io::AtomicFolder folder(options.out, options.force, "--out", "use --force to replace it");
  io::AtomicFile list(folder.temporary() / "masks.txt");
  const MaskValues values = ValuesOf(options.format);
  list.stream() << fmt::format("# hoidslam masks of {}: filter {}, format {} ({} dynamic, {} static), dilated {} px\n"
                               "# timestamp filename\n",
                               sequence.name(), options.exclusion.ModeName(), ToString(options.format),
                               values.dynamic, values.clear, options.dilate);
  spdlog::info("{}: {} frames, filter {}, detector {}, format {}", sequence.name(), total,
               options.exclusion.ModeName(), detector.Name(), ToString(options.format));

  MaskExportSummary summary;
  double masked_share_sum = 0.0;
  core::ProgressReporter progress("masks", total);
  std::vector<core::Detection> detections;  // kept across frames: a failed frame reuses the last ones (run also moves them by their keypoints; masks has none)
  hoid::JudgedBoxes boxes;
  std::vector<std::uint8_t> no_keypoints;
  for (std::size_t index = 0; index < total; ++index) {
    if (options.stop_requested && options.stop_requested()) throw core::Interrupted();
    const core::RgbdFrame frame = sequence.LoadFrame(index);
    cv::Mat marked;
    if (options.exclusion.oracle) {
      cv::compare(exclusion.MovingMask(frame), 0, marked, cv::CMP_NE);  // run drops on any non-zero value
    } else {
      if (options.exclusion.NeedsDetections() && DetectOrKeepPrevious(detector, frame, index, detections)) {
        ++summary.detector_failures;
      }
      // Run's exclusion on no keypoints: only its verdicts on the detections are wanted here.
      exclusion.Mark(frame, detections, {}, cv::Mat(), no_keypoints, boxes);
      marked = exclusion.PaintDropped(frame, boxes);
    }
    DilateMask(marked, options.dilate);
    masked_share_sum += static_cast<double>(cv::countNonZero(marked)) / static_cast<double>(marked.total());

    const io::SequenceEntry& entry = sequence.entry(index);
    const std::string name = entry.rgb_path.stem().string() + ".png";
    io::WriteImageAtomically(folder.temporary() / name, EncodeMask(marked, options.format));
    list.stream() << fmt::format("{:.6f} {}\n", entry.rgb_timestamp, name);
    ++summary.frames;
    progress.Update(index + 1);
  }
  list.Commit();
  folder.Commit();
  summary.mean_masked_share = summary.frames == 0 ? 0.0 : masked_share_sum / static_cast<double>(summary.frames);
  return summary;
}

}  // namespace hoidslam::pipeline
