#include "hoidslam/synth/preview.h"

#include <fmt/format.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/detections_file.h"
#include "hoidslam/io/files.h"
#include "hoidslam/io/rgbd_sequence.h"

namespace hoidslam::synth {
namespace {

cv::Scalar LabelColour(const std::string& label) {
  if (label == "person") return {60, 60, 255};
  if (label == "chair") return {255, 160, 40};
  if (label == "tv") return {255, 255, 60};
  return {60, 230, 60};
}

cv::Mat Tile(const cv::Mat& rgb, const cv::Mat& depth, const cv::Mat& mask,
             const std::vector<core::Detection>& detections, const PreviewOptions& options) {
  cv::Mat depth8;
  depth.convertTo(depth8, CV_8U, 255.0 / (options.max_depth * 5000.0));
  cv::Mat depth_colour;
  cv::applyColorMap(depth8, depth_colour, cv::COLORMAP_TURBO);
  depth_colour.setTo(cv::Scalar::all(0), depth == 0);

  cv::Mat boxes = rgb.clone();
  for (const core::Detection& d : detections) {
    const cv::Scalar colour = LabelColour(d.label);
    cv::rectangle(boxes, cv::Rect(d.box), colour, 2);
    cv::putText(boxes, d.label, {static_cast<int>(d.box.x) + 2, std::max(12, static_cast<int>(d.box.y) - 4)},
                cv::FONT_HERSHEY_SIMPLEX, 0.6, colour, 2);
  }
  cv::Mat moving = rgb * 0.35;
  moving.setTo(cv::Scalar(40, 40, 255), mask > 0);

  cv::Mat top;
  cv::Mat bottom;
  cv::Mat tile;
  cv::hconcat(rgb, depth_colour, top);
  cv::hconcat(boxes, moving, bottom);
  cv::vconcat(top, bottom, tile);
  cv::resize(tile, tile, {}, options.scale, options.scale, cv::INTER_AREA);
  // A thin white frame keeps tiles apart.
  cv::copyMakeBorder(tile, tile, 2, 2, 2, 2, cv::BORDER_CONSTANT, cv::Scalar::all(255));
  return tile;
}

}  // namespace

void PreviewOptions::Check() const {
  if (!(scale > 0.0 && scale <= 1.0)) throw core::InputError::ForParameter("preview.scale", "must be in (0, 1]");
  if (!(max_depth > 0.0)) throw core::InputError::ForParameter("preview.max_depth", "must be > 0");
}

cv::Mat SequencePreview(const std::filesystem::path& sequence, const PreviewOptions& options) {
  options.Check();
  const io::RgbdSequence frames = io::RgbdSequence::OpenTum(sequence);
  const io::DetectionsFile detections = io::DetectionsFile::Read(sequence / "detections.jsonl");
  std::vector<std::size_t> chosen = options.frames;
  if (chosen.empty()) {
    for (std::size_t k = 1; k <= 3; ++k) chosen.push_back(frames.size() * k / 4);
  }
  std::vector<cv::Mat> tiles;
  for (const std::size_t index : chosen) {
    if (index >= frames.size()) {
      throw core::InputError::ForParameter("preview.frames", fmt::format("frame {} is beyond the {} frames of {}",
                                                                         index, frames.size(), sequence.string()));
    }
    const io::SequenceEntry& entry = frames.entry(index);
    const std::filesystem::path mask_path = sequence / "mask" / entry.rgb_path.filename();
    const io::FrameDetections* found = detections.Find(entry.rgb_timestamp);
    tiles.push_back(Tile(io::ReadImage(entry.rgb_path, cv::IMREAD_COLOR, "colour"),
                         io::ReadImage(entry.depth_path, cv::IMREAD_UNCHANGED, "depth"),
                         io::ReadImage(mask_path, cv::IMREAD_GRAYSCALE, "mask"),
                         found != nullptr ? found->detections : std::vector<core::Detection>{}, options));
  }
  cv::Mat strip;
  cv::hconcat(tiles, strip);
  return strip;
}

void WritePreviewPng(const std::filesystem::path& path, const cv::Mat& preview) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", preview, bytes, {cv::IMWRITE_PNG_COMPRESSION, 9})) {
    throw core::InputError::InFile(path, "cannot encode the preview");
  }
  io::AtomicFile file(path);
  file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  file.Commit();
}

}  // namespace hoidslam::synth
