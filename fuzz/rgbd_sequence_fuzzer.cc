// TUM / Bonn sequence folders: the list files (rgb.txt, depth.txt, groundtruth.txt) and the associations file.
// The folder holds a few empty image files (rgb/1.png ... depth/3.png) for the lists to name: opening a sequence
// checks that every listed image exists, and reads none.

#include <cmath>
#include <set>

#include "fuzz/targets.h"
#include "hoidslam/io/rgbd_sequence.h"

namespace hoidslam::fuzz {
namespace {

namespace fs = std::filesystem;

const fs::path& SequenceFolder() {
  static const fs::path root = [] {
    const fs::path folder = ScratchDir() / "sequence";
    for (const char* images : {"rgb", "depth"}) {
      fs::create_directories(folder / images);
      for (const char* name : {"1.png", "2.png", "3.png"}) WriteBytes(folder / images / name, {});
    }
    return folder;
  }();
  return root;
}

// What every opened sequence keeps: frames in strictly increasing RGB time, finite times, listed images that
// exist, and a valid ground truth.
void CheckSequence(const io::RgbdSequence& sequence) {
  Require(sequence.size() > 0, "a sequence without frames");
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const io::SequenceEntry& entry = sequence.entry(i);
    Require(std::isfinite(entry.rgb_timestamp) && std::isfinite(entry.depth_timestamp), "a time is not finite");
    Require(i == 0 || sequence.entry(i - 1).rgb_timestamp < entry.rgb_timestamp,
            "RGB times are not strictly increasing");
    for (const fs::path& image : {entry.rgb_path, entry.depth_path}) {
      Require(image.string().find('\0') == std::string::npos && fs::is_regular_file(image),
              "an entry names an image that does not exist");
    }
  }
  CheckTrajectory(sequence.groundtruth());
}

}  // namespace

void FuzzTumLists(Bytes input) {
  const fs::path& root = SequenceFolder();
  const std::vector<Bytes> files = SplitFiles(input, 3);
  const char* names[] = {"rgb.txt", "depth.txt", "groundtruth.txt"};
  for (std::size_t i = 0; i < 3; ++i) {
    WriteOrRemove(root / names[i], i < files.size() ? std::optional(files[i]) : std::nullopt);
  }
  const io::SequenceOptions options;
  const auto sequence = ParseOrReject([&] { return io::RgbdSequence::OpenTum(root, options); }, root.string());
  if (!sequence) return;
  CheckSequence(*sequence);
  // Paired as associate.py pairs: within the tolerance, each depth image at most once.
  std::set<double> depth_times;
  for (const io::SequenceEntry& entry : sequence->entries()) {
    Require(std::abs(entry.rgb_timestamp - entry.depth_timestamp) < options.max_time_difference,
            "a pair further apart than the tolerance");
    Require(depth_times.insert(entry.depth_timestamp).second, "a depth image paired twice");
  }
}

void FuzzAssociations(Bytes input) {
  const fs::path& root = SequenceFolder();
  io::SequenceOptions options;
  options.associations = "associations.txt";
  WriteBytes(root / options.associations, input);
  // No groundtruth.txt: that file is the tum_lists target's.
  fs::remove(root / "groundtruth.txt");
  if (const auto sequence =
          ParseOrReject([&] { return io::RgbdSequence::OpenTum(root, options); }, root.string())) {
    CheckSequence(*sequence);
  }
}

}  // namespace hoidslam::fuzz
