#pragma once
// Replays a detections file (docs/detections-file.md): detections computed offline, looked up by timestamp.

#include <filesystem>
#include <string>
#include <vector>

#include "hoidslam/detect/detector.h"
#include "hoidslam/io/detections_file.h"

namespace hoidslam::detect {

class FileDetector final : public Detector {
 public:
  // Reads the whole file; throws InputError naming the file and line when it is malformed.
  explicit FileDetector(const std::filesystem::path& path);

  // The file's detections for the frame at `timestamp` (within io::kTimestampMatchTolerance). Throws InputError
  // naming the file when it has no line for that frame (a file written for another sequence) or when its header
  // gives an image size other than that of `bgr` (an empty `bgr` skips that check).
  std::vector<core::Detection> Detect(double timestamp, const cv::Mat& bgr) override;

  // The detector named in the file's header, else the file name.
  std::string Name() const override;
  std::filesystem::path Source() const override { return file_.path(); }

  // Checks up front that the file has a line for each of `timestamps`, the frames of `sequence_name`, so that a
  // wrong file fails before a long run rather than in the middle of it. Throws InputError naming the file.
  void CheckCovers(const std::vector<double>& timestamps, const std::string& sequence_name) const {
    file_.CheckCovers(timestamps, sequence_name);
  }

  const io::DetectionsFile& file() const { return file_; }

 private:
  io::DetectionsFile file_;
};

}  // namespace hoidslam::detect
