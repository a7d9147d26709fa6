#include "hoidslam/io/rgbd_sequence.h"

#include <cmath>
#include <map>
#include <string_view>
#include <system_error>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/io/files.h"
#include "hoidslam/io/text_lines.h"
#include "hoidslam/io/timestamp_association.h"
#include "hoidslam/io/trajectory_file.h"

namespace hoidslam::io {
namespace {

namespace fs = std::filesystem;
using core::InputError;

// Timestamp → image, as TUM's read_file_list builds it: a repeated timestamp keeps its last line.
using ImageList = std::map<double, fs::path>;

void CheckOptions(const SequenceOptions& options) {
  if (!(options.depth_factor > 0.0 && std::isfinite(options.depth_factor))) {
    throw InputError::ForParameter("DepthMapFactor", fmt::format("must be > 0, got {}", options.depth_factor));
  }
  if (!(options.max_time_difference > 0.0 && std::isfinite(options.max_time_difference))) {
    throw InputError::ForParameter("max_time_difference",
                                   fmt::format("must be > 0 seconds, got {}", options.max_time_difference));
  }
}

// `root / listed`, which must exist; the error names the list file, its line and the missing image.
fs::path ListedImage(const fs::path& root, std::string_view listed, const fs::path& list_file, std::size_t line) {
  // The operating system would read a path only up to a NUL byte, and so find an image the line does not name.
  if (listed.find('\0') != std::string_view::npos) {
    throw InputError::AtLine(list_file, line, "the image path contains a NUL byte");
  }
  fs::path image = root / fs::path(listed);
  // Without an error code, a name the system cannot look up (too long, say) would throw filesystem_error.
  std::error_code error;
  if (!fs::is_regular_file(image, error)) {
    const bool absent = !error || error == std::errc::no_such_file_or_directory || error == std::errc::not_a_directory;
    throw InputError::AtLine(
        list_file, line,
        absent ? fmt::format("listed image {} does not exist", image.string())
               : fmt::format("cannot look at listed image {}: {}", image.string(), error.message()));
  }
  return image;
}

// rgb.txt / depth.txt: `timestamp relative/path` lines.
ImageList ReadImageList(const fs::path& root, const fs::path& list_file) {
  ImageList images;
  ForEachDataLine(list_file, [&](std::size_t line, const std::vector<std::string_view>& fields) {
    if (fields.size() != 2) {
      throw InputError::AtLine(list_file, line,
                               fmt::format("expected 'timestamp path', found {} field(s)", fields.size()));
    }
    images[ParseDouble(fields[0], list_file, line)] = ListedImage(root, fields[1], list_file, line);
  });
  if (images.empty()) throw InputError::InFile(list_file, "lists no images");
  return images;
}

// RGB and depth images paired as TUM's associate.py pairs them, in RGB time order.
std::vector<SequenceEntry> Associate(const ImageList& rgb, const ImageList& depth, double max_difference) {
  const auto stamps = [](const ImageList& images) {
    std::vector<double> times;
    times.reserve(images.size());
    for (const auto& [time, unused] : images) times.push_back(time);
    return times;
  };
  const std::vector<double> rgb_times = stamps(rgb);
  const std::vector<double> depth_times = stamps(depth);
  std::vector<SequenceEntry> entries;
  for (const TimestampMatch& match :
       AssociateTimestamps(rgb_times, depth_times, max_difference, 0.0, "max_time_difference")) {
    const double t_rgb = rgb_times[match.first];
    const double t_depth = depth_times[match.second];
    entries.push_back({t_rgb, rgb.at(t_rgb), t_depth, depth.at(t_depth)});
  }
  return entries;
}

// An associations file, with every listed image checked.
std::vector<SequenceEntry> ReadAssociations(const fs::path& root, const fs::path& file) {
  std::vector<SequenceEntry> entries;
  for (const AssociationLine& line : ReadAssociationList(file)) {
    entries.push_back({line.rgb_timestamp, ListedImage(root, line.rgb, file, line.line), line.depth_timestamp,
                       ListedImage(root, line.depth, file, line.line)});
  }
  return entries;
}

// "3-channel 8-bit unsigned" and the like, for messages about what an image file held.
std::string DescribeType(const cv::Mat& image) {
  constexpr std::string_view kDepthNames[] = {"8-bit unsigned", "8-bit signed", "16-bit unsigned", "16-bit signed",
                                              "32-bit signed",  "32-bit float", "64-bit float",    "16-bit float"};
  return fmt::format("{}-channel {}", image.channels(), kDepthNames[image.depth()]);
}

}  // namespace

std::vector<AssociationLine> ReadAssociationList(const std::filesystem::path& file) {
  std::map<double, AssociationLine> by_rgb_time;
  ForEachDataLine(file, [&](std::size_t line, const std::vector<std::string_view>& fields) {
    if (fields.size() != 4) {
      throw InputError::AtLine(
          file, line, fmt::format("expected 't_rgb rgb_path t_depth depth_path', found {} field(s)", fields.size()));
    }
    const double t_rgb = ParseDouble(fields[0], file, line);
    by_rgb_time[t_rgb] = {t_rgb, std::string(fields[1]), ParseDouble(fields[2], file, line), std::string(fields[3]),
                          line};
  });
  if (by_rgb_time.empty()) throw InputError::InFile(file, "lists no RGB-D pairs");
  std::vector<AssociationLine> lines;
  lines.reserve(by_rgb_time.size());
  for (auto& [unused, line] : by_rgb_time) lines.push_back(std::move(line));
  return lines;
}

RgbdSequence RgbdSequence::OpenTum(const std::filesystem::path& root, const SequenceOptions& options) {
  CheckOptions(options);
  if (!fs::is_directory(root)) throw InputError::InFile(root, "sequence folder does not exist");

  RgbdSequence sequence;
  sequence.name_ = NormalFolder(root).filename().string();
  sequence.root_ = root;
  sequence.options_ = options;
  if (!options.associations.empty()) {
    sequence.entries_ = ReadAssociations(root, root / options.associations);
  } else {
    const fs::path rgb_list = root / "rgb.txt";
    const fs::path depth_list = root / "depth.txt";
    sequence.entries_ =
        Associate(ReadImageList(root, rgb_list), ReadImageList(root, depth_list), options.max_time_difference);
    if (sequence.entries_.empty()) {
      throw InputError::InFile(root, fmt::format("no image of {} is within {} s of an image of {}", rgb_list.string(),
                                                 options.max_time_difference, depth_list.string()));
    }
  }
  // Ground truth is optional and is matched to frames by time later, never by line.
  if (const fs::path groundtruth = root / "groundtruth.txt"; fs::exists(groundtruth)) {
    sequence.groundtruth_ = ReadTumTrajectory(groundtruth);
  }
  return sequence;
}

RgbdSequence RgbdSequence::OpenImageFolders(const std::filesystem::path& rgb_folder,
                                            const std::filesystem::path& depth_folder, double fps,
                                            const SequenceOptions& options) {
  CheckOptions(options);
  if (!(fps > 0.0 && std::isfinite(fps))) {
    throw InputError::ForParameter("fps", fmt::format("must be > 0, got {}", fps));
  }
  const std::vector<fs::path> rgb = ImagesIn(rgb_folder);
  const std::vector<fs::path> depth = ImagesIn(depth_folder);
  if (rgb.size() != depth.size() || rgb.empty()) {
    throw InputError(
        fmt::format("{} holds {} image(s) and {} holds {}: the folders must hold the same, non-zero "
                    "number of images",
                    rgb_folder.string(), rgb.size(), depth_folder.string(), depth.size()));
  }

  RgbdSequence sequence;
  // seq/rgb + seq/depth is called "seq"; folders with nothing in common are called after the colour folder.
  const fs::path rgb_parent = NormalFolder(rgb_folder).parent_path();
  sequence.root_ = rgb_parent == NormalFolder(depth_folder).parent_path() ? rgb_parent : NormalFolder(rgb_folder);
  sequence.name_ = sequence.root_.filename().string();
  sequence.options_ = options;
  sequence.entries_.reserve(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const double timestamp = static_cast<double>(i) / fps;
    sequence.entries_.push_back({timestamp, rgb[i], timestamp, depth[i]});
  }
  return sequence;
}

std::vector<double> RgbdSequence::Timestamps() const {
  std::vector<double> timestamps;
  timestamps.reserve(entries_.size());
  for (const SequenceEntry& entry : entries_) timestamps.push_back(entry.rgb_timestamp);
  return timestamps;
}

core::RgbdFrame RgbdSequence::LoadFrame(std::size_t index) const {
  const SequenceEntry& entry = entries_.at(index);
  core::RgbdFrame frame;
  frame.timestamp = entry.rgb_timestamp;
  frame.depth_delay = entry.depth_timestamp - entry.rgb_timestamp;
  frame.rgb_path = entry.rgb_path.string();
  frame.depth_path = entry.depth_path.string();
  frame.rgb = ReadImage(entry.rgb_path, cv::IMREAD_COLOR, "colour");

  const cv::Mat raw = ReadImage(entry.depth_path, cv::IMREAD_UNCHANGED, "depth");
  if (raw.type() != CV_16UC1) {
    throw InputError::InFile(
        entry.depth_path,
        fmt::format("depth image must be 1-channel 16-bit unsigned (a 16-bit PNG), found {}", DescribeType(raw)));
  }
  if (raw.size() != frame.rgb.size()) {
    throw InputError::InFile(entry.depth_path,
                             fmt::format("depth image is {}x{} but its colour image {} is {}x{}", raw.cols, raw.rows,
                                         entry.rgb_path.string(), frame.rgb.cols, frame.rgb.rows));
  }
  // 0 (no measurement) stays 0.
  raw.convertTo(frame.depth, CV_32F, 1.0 / options_.depth_factor);
  return frame;
}

}  // namespace hoidslam::io
