#pragma once
// A picture of what a synthetic sequence looks like: for each chosen frame a 2 x 2 tile of the colour image,
// the depth (colourised, black = no depth), the ground-truth boxes drawn on the colour image, and the
// moving-pixel mask over a darkened colour image. Tiles of several frames are placed side by side.

#include <cstddef>
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace hoidslam::synth {

struct PreviewOptions {
  std::vector<std::size_t> frames;  // frame indices; empty = 3 frames spread over the sequence
  double scale = 0.4;               // size of each image in the tile relative to the sequence's, in (0, 1]
  double max_depth = 5.0;           // metres mapped to the end of the colour map, > 0

  // Throws InputError naming the parameter ("preview.scale", ...).
  void Check() const;
};

// Reads a sequence written by WriteSequence (rgb, depth, mask, detections.jsonl) and draws the preview.
// Throws InputError naming the folder or file when something is missing or a frame index is out of range.
cv::Mat SequencePreview(const std::filesystem::path& sequence, const PreviewOptions& options);

// Writes a preview as a PNG compressed as much as PNG allows (previews end up in documentation), atomically.
void WritePreviewPng(const std::filesystem::path& path, const cv::Mat& preview);

}  // namespace hoidslam::synth
