#include "hoidslam/detect/file_detector.h"

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::detect {

FileDetector::FileDetector(const std::filesystem::path& path) : file_(io::DetectionsFile::Read(path)) {}

std::vector<core::Detection> FileDetector::Detect(double timestamp, const cv::Mat& bgr) {
  const io::FrameDetections* frame = file_.Find(timestamp);
  if (frame == nullptr) {
    throw core::InputError::InFile(
        file_.path(), fmt::format("no detections for the frame at timestamp {:.6f} (is it a file for another "
                                  "sequence?)",
                                  timestamp));
  }
  if (const auto& header = file_.header(); header && header->image_width > 0 && !bgr.empty() &&
                                           (header->image_width != bgr.cols || header->image_height != bgr.rows)) {
    throw core::InputError::InFile(
        file_.path(), fmt::format("boxes are for {}×{} images but the frame at timestamp {:.6f} is {}×{}",
                                  header->image_width, header->image_height, timestamp, bgr.cols, bgr.rows));
  }
  return frame->detections;
}

std::string FileDetector::Name() const {
  if (file_.header() && !file_.header()->detector.empty()) return file_.header()->detector;
  return file_.path().filename().string();
}

}  // namespace hoidslam::detect
