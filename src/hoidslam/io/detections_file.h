#pragma once
// The detections file: detections for a whole sequence, one JSON object per line (JSON Lines), so that any
// detector can be run offline and its output replayed. Schema: docs/detections-file.md.
//
//   {"format":"hoidslam-detections","version":1,"sequence":"...","detector":"...","image_size":[640,480]}
//   {"timestamp":1341846313.592026,"detections":[{"label":"person","class_id":0,"score":0.91,"box":[x,y,w,h]}]}
//
// The first line (the header) is optional for hand-written files. Every frame has a line, also frames with no
// detections, so a missing frame is told apart from an empty one.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hoidslam/core/detection.h"
#include "hoidslam/io/atomic_file.h"

namespace hoidslam::io {

struct FrameDetections {
  double timestamp = 0.0;  // the RGB image's timestamp, seconds
  std::vector<core::Detection> detections;
};

struct DetectionsFileHeader {
  std::string sequence;  // the sequence's folder name, to catch a file meant for another sequence
  std::string detector;  // what produced the file, e.g. "yolox_nano.onnx" or "synthetic ground truth"
  int image_width = 0;   // size of the images the boxes refer to; 0 when unknown
  int image_height = 0;
};

// Two timestamps name the same frame when they differ by less than this: a millisecond, so that a file whose
// timestamps were rounded to the millisecond (as many tools write them) still finds every frame, and no camera
// takes two frames that near.
inline constexpr double kTimestampMatchTolerance = 1e-3;

class DetectionsFile {
 public:
  // Throws InputError "<file>:<line>: ..." for malformed JSON, a missing or mistyped field, a negative box size
  // or a score outside [0, 1].
  static DetectionsFile Read(const std::filesystem::path& path);

  const std::filesystem::path& path() const { return path_; }
  const std::optional<DetectionsFileHeader>& header() const { return header_; }
  const std::vector<FrameDetections>& frames() const { return frames_; }  // sorted by timestamp

  // The frame within kTimestampMatchTolerance of `timestamp`, or nullptr.
  const FrameDetections* Find(double timestamp) const;

  // Throws InputError naming the file when it does not cover every one of `timestamps` (the frames of
  // `sequence_name`): a file for another sequence, or one cut short.
  void CheckCovers(const std::vector<double>& timestamps, const std::string& sequence_name) const;

 private:
  std::filesystem::path path_;
  std::optional<DetectionsFileHeader> header_;
  std::vector<FrameDetections> frames_;
};

// Writes a detections file line by line; the file appears at its path only on Commit().
class DetectionsFileWriter {
 public:
  DetectionsFileWriter(const std::filesystem::path& path, const DetectionsFileHeader& header);
  void Write(const FrameDetections& frame);
  void Commit() { file_.Commit(); }

 private:
  AtomicFile file_;
};

}  // namespace hoidslam::io
