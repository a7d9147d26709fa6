// Detections files: the bytes are a detections file (JSON Lines, docs/detections-file.md).

#include <cmath>

#include "fuzz/targets.h"
#include "hoidslam/io/detections_file.h"

namespace hoidslam::fuzz {

void FuzzDetections(Bytes input) {
  const std::filesystem::path path = ScratchDir() / "detections.jsonl";
  WriteBytes(path, input);
  const auto file = ParseOrReject([&] { return io::DetectionsFile::Read(path); }, path.string());
  if (!file) return;
  // The rules of docs/detections-file.md, on what was accepted.
  if (const auto& header = file->header()) {
    Require(header->image_width >= 0 && header->image_height >= 0, "a negative image size");
  }
  const std::vector<io::FrameDetections>& frames = file->frames();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    Require(std::isfinite(frames[i].timestamp), "a timestamp is not finite");
    Require(i == 0 || frames[i].timestamp - frames[i - 1].timestamp >= io::kTimestampMatchTolerance,
            "frames are not sorted, or two name the same timestamp");
    Require(file->Find(frames[i].timestamp) == &frames[i], "Find does not find a frame by its own timestamp");
    for (const core::Detection& d : frames[i].detections) {
      Require(!d.label.empty(), "an empty label");
      Require(d.score >= 0.0F && d.score <= 1.0F, "a score outside [0, 1]");
      Require(std::isfinite(d.box.x) && std::isfinite(d.box.y) && std::isfinite(d.box.width) &&
                  std::isfinite(d.box.height),
              "a box with a number that is not finite");
      Require(d.box.width >= 0.0F && d.box.height >= 0.0F, "a box with a negative size");
    }
  }
}

}  // namespace hoidslam::fuzz
