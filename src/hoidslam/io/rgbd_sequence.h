#pragma once
// RGB-D sequences on disk: the TUM RGB-D layout (also used by Bonn RGB-D Dynamic) and plain image folders.
//
// TUM layout: <root>/rgb.txt, <root>/depth.txt (`timestamp relative/path.png` lines), optional
// associations file, optional groundtruth.txt, 16-bit depth PNGs scaled by a depth factor (5000 per metre).

#include <filesystem>
#include <string>
#include <vector>

#include "hoidslam/core/frame.h"
#include "hoidslam/core/pose.h"

namespace hoidslam::io {

struct SequenceOptions {
  double depth_factor = 5000.0;           // depth PNG units per metre (TUM, Bonn: 5000), > 0
  double max_time_difference = 0.02;      // seconds, RGB–depth association tolerance (TUM associate.py)
  std::filesystem::path associations;     // optional `t_rgb rgb/.. t_depth depth/..` file; relative to root
};

// One associated RGB-D pair.
struct SequenceEntry {
  double rgb_timestamp = 0.0;
  std::filesystem::path rgb_path;  // absolute or relative to the working directory, ready to open
  double depth_timestamp = 0.0;
  std::filesystem::path depth_path;
};

// One line of an associations file (`t_rgb rgb/x.png t_depth depth/y.png`), paths as written.
struct AssociationLine {
  double rgb_timestamp = 0.0;
  std::string rgb;
  double depth_timestamp = 0.0;
  std::string depth;
  std::size_t line = 0;  // in the file, from 1
};

// Reads an associations file: exactly 4 fields a line, '#' comments and blank lines skipped, a repeated RGB
// timestamp keeps its last line, sorted by RGB time. Throws InputError naming the file and line; an empty list
// is an error too.
std::vector<AssociationLine> ReadAssociationList(const std::filesystem::path& file);

class RgbdSequence {
 public:
  // Opens a TUM / Bonn sequence folder. Throws InputError naming the file and line on a missing folder or
  // list file, an unparseable line, or a listed image that does not exist.
  static RgbdSequence OpenTum(const std::filesystem::path& root, const SequenceOptions& options = {});

  // Opens two folders of images (sorted by file name, paired in order) played at a fixed rate.
  static RgbdSequence OpenImageFolders(const std::filesystem::path& rgb_folder,
                                       const std::filesystem::path& depth_folder, double fps,
                                       const SequenceOptions& options = {});

  const std::string& name() const { return name_; }  // folder name, e.g. rgbd_dataset_freiburg3_walking_xyz
  const std::filesystem::path& root() const { return root_; }
  std::size_t size() const { return entries_.size(); }
  const SequenceEntry& entry(std::size_t index) const { return entries_.at(index); }
  const std::vector<SequenceEntry>& entries() const { return entries_; }
  std::vector<double> Timestamps() const;  // RGB timestamps in order

  // Loads frame `index`: BGR colour and depth in metres. Throws InputError naming the file for an unreadable
  // image or a depth image that is not single-channel 16-bit.
  core::RgbdFrame LoadFrame(std::size_t index) const;

  // groundtruth.txt when present (TUM format), else empty.
  const core::Trajectory& groundtruth() const { return groundtruth_; }

 private:
  std::string name_;
  std::filesystem::path root_;
  SequenceOptions options_;
  std::vector<SequenceEntry> entries_;
  core::Trajectory groundtruth_;
};

}  // namespace hoidslam::io
