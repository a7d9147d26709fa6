#include "hoidslam/io/detections_file.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"

namespace hoidslam::io {

using core::InputError;
using nlohmann::json;

namespace {

constexpr const char* kFormatName = "hoidslam-detections";
constexpr int kFormatVersion = 1;

// Reads one line's JSON, naming the file, line and key in every error.
class LineParser {
 public:
  LineParser(const std::filesystem::path& path, std::size_t line) : path_(path), line_(line) {}

  [[noreturn]] void Fail(const std::string& what) const { throw InputError::AtLine(path_, line_, what); }

  const json& Member(const json& object, const char* key, const std::string& where) const {
    const auto it = object.find(key);
    if (it == object.end()) Fail(fmt::format("missing key '{}{}'", where, key));
    return *it;
  }

  double Number(const json& value, const std::string& key) const {
    if (!value.is_number()) Fail(fmt::format("'{}' must be a number, got {}", key, value.dump()));
    const double number = value.get<double>();
    if (!std::isfinite(number)) Fail(fmt::format("'{}' must be finite", key));
    return number;
  }

  // Box coordinates are stored as float: a number beyond float's range would become infinite.
  float BoxNumber(const json& value, const std::string& key) const {
    const double number = Number(value, key);
    if (std::abs(number) > std::numeric_limits<float>::max()) Fail(fmt::format("'{}' is out of range", key));
    return static_cast<float>(number);
  }

  // An integer in [lo, hi]. nlohmann::json would wrap a larger one into int silently (2^32 + 1 reads as 1).
  int Integer(const json& value, const std::string& key, int lo, int hi) const {
    bool in_range = false;
    if (value.is_number_unsigned()) {  // may exceed int64's range
      const auto v = value.get<std::uint64_t>();
      in_range = (lo <= 0 || v >= static_cast<std::uint64_t>(lo)) && v <= static_cast<std::uint64_t>(hi);
    } else if (value.is_number_integer()) {
      const auto v = value.get<std::int64_t>();
      in_range = v >= lo && v <= hi;
    }
    if (!in_range) Fail(fmt::format("'{}' must be an integer in [{}, {}], got {}", key, lo, hi, value.dump()));
    return value.get<int>();
  }

  core::Detection Detection(const json& object, std::size_t index) const {
    const std::string where = fmt::format("detections[{}].", index);
    if (!object.is_object()) Fail(fmt::format("'detections[{}]' must be an object", index));
    core::Detection detection;
    const json& label = Member(object, "label", where);
    if (!label.is_string() || label.get<std::string>().empty()) {
      Fail(fmt::format("'{}label' must be a non-empty string", where));
    }
    detection.label = label.get<std::string>();
    if (const auto it = object.find("class_id"); it != object.end()) {
      detection.class_id = Integer(*it, where + "class_id", -1, std::numeric_limits<int>::max());
    }
    detection.score = static_cast<float>(Number(Member(object, "score", where), where + "score"));
    if (detection.score < 0.0F || detection.score > 1.0F) {
      Fail(fmt::format("'{}score' must be in [0, 1], got {}", where, detection.score));
    }
    const json& box = Member(object, "box", where);
    if (!box.is_array() || box.size() != 4) Fail(fmt::format("'{}box' must be [x, y, width, height]", where));
    const float x = BoxNumber(box[0], where + "box[0]");
    const float y = BoxNumber(box[1], where + "box[1]");
    const float width = BoxNumber(box[2], where + "box[2]");
    const float height = BoxNumber(box[3], where + "box[3]");
    if (width < 0.0F || height < 0.0F) Fail(fmt::format("'{}box' has a negative width or height", where));
    detection.box = cv::Rect2f(x, y, width, height);
    return detection;
  }

  DetectionsFileHeader Header(const json& object) const {
    if (object.at("format") != kFormatName) Fail(fmt::format("'format' must be \"{}\"", kFormatName));
    const json& version = Member(object, "version", "");
    if (!version.is_number_integer() || version != kFormatVersion) {
      Fail(fmt::format("unsupported version {} (this hoidslam reads version {})", version.dump(), kFormatVersion));
    }
    DetectionsFileHeader header;
    if (const auto it = object.find("sequence"); it != object.end() && it->is_string()) header.sequence = *it;
    if (const auto it = object.find("detector"); it != object.end() && it->is_string()) header.detector = *it;
    if (const auto it = object.find("image_size"); it != object.end()) {
      if (!it->is_array() || it->size() != 2) Fail("'image_size' must be [width, height]");
      header.image_width = Integer((*it)[0], "image_size[0]", 0, std::numeric_limits<int>::max());
      header.image_height = Integer((*it)[1], "image_size[1]", 0, std::numeric_limits<int>::max());
    }
    return header;
  }

  FrameDetections Frame(const json& object) const {
    FrameDetections frame;
    frame.timestamp = Number(Member(object, "timestamp", ""), "timestamp");
    const json& detections = Member(object, "detections", "");
    if (!detections.is_array()) Fail("'detections' must be an array");
    frame.detections.reserve(detections.size());
    for (std::size_t i = 0; i < detections.size(); ++i) frame.detections.push_back(Detection(detections[i], i));
    return frame;
  }

 private:
  const std::filesystem::path& path_;
  std::size_t line_;
};

}  // namespace

DetectionsFile DetectionsFile::Read(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError::InFile(path, "no such file");
  std::ifstream in(path);
  if (!in) throw InputError::InFile(path, "cannot open for reading");

  DetectionsFile file;
  file.path_ = path;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    const LineParser parser(path, line);
    json object;
    try {
      object = json::parse(text);
    } catch (const json::exception& e) {  // parse_error, or out_of_range for a number such as 1e400
      parser.Fail(fmt::format("not valid JSON ({})", e.what()));
    }
    if (!object.is_object()) parser.Fail("each line must be a JSON object");
    if (object.contains("format")) {
      if (file.header_ || !file.frames_.empty()) parser.Fail("the header line must be the first line");
      file.header_ = parser.Header(object);
      continue;
    }
    file.frames_.push_back(parser.Frame(object));
  }
  std::stable_sort(file.frames_.begin(), file.frames_.end(),
                   [](const FrameDetections& a, const FrameDetections& b) { return a.timestamp < b.timestamp; });
  for (std::size_t i = 1; i < file.frames_.size(); ++i) {
    if (file.frames_[i].timestamp - file.frames_[i - 1].timestamp < kTimestampMatchTolerance) {
      throw InputError::InFile(path, fmt::format("timestamp {:.6f} appears on more than one line",
                                                 file.frames_[i].timestamp));
    }
  }
  return file;
}

const FrameDetections* DetectionsFile::Find(double timestamp) const {
  auto it = std::lower_bound(frames_.begin(), frames_.end(), timestamp - kTimestampMatchTolerance,
                             [](const FrameDetections& frame, double t) { return frame.timestamp < t; });
  if (it == frames_.end()) return nullptr;
  // Frames are at least the tolerance apart, so at most two lie within it: the nearer.
  if (const auto next = std::next(it);
      next != frames_.end() && std::abs(next->timestamp - timestamp) < std::abs(it->timestamp - timestamp)) {
    it = next;
  }
  if (std::abs(it->timestamp - timestamp) >= kTimestampMatchTolerance) return nullptr;
  return &*it;
}

void DetectionsFile::CheckCovers(const std::vector<double>& timestamps, const std::string& sequence_name) const {
  if (header_ && !header_->sequence.empty() && !sequence_name.empty() && header_->sequence != sequence_name) {
    throw InputError::InFile(path_, fmt::format("was written for sequence '{}', not '{}'", header_->sequence,
                                                sequence_name));
  }
  std::size_t missing = 0;
  double first_missing = 0.0;
  for (const double timestamp : timestamps) {
    if (Find(timestamp) != nullptr) continue;
    if (missing++ == 0) first_missing = timestamp;
  }
  if (missing > 0) {
    throw InputError::InFile(
        path_, fmt::format("has no line for {} of the {} frames of '{}' (first: timestamp {:.6f}); is it for "
                           "another sequence, or was it cut short?",
                           missing, timestamps.size(), sequence_name, first_missing));
  }
}

DetectionsFileWriter::DetectionsFileWriter(const std::filesystem::path& path, const DetectionsFileHeader& header)
    : file_(path) {
  json line = {{"format", kFormatName}, {"version", kFormatVersion}, {"sequence", header.sequence},
               {"detector", header.detector}};
  if (header.image_width > 0 && header.image_height > 0) {
    line["image_size"] = {header.image_width, header.image_height};
  }
  file_.stream() << line.dump() << '\n';
}

void DetectionsFileWriter::Write(const FrameDetections& frame) {
  // Timestamps keep microseconds exactly (TUM's precision); boxes and scores need no more than 0.01 px / 1e-4.
  std::string line = fmt::format("{{\"timestamp\":{:.6f},\"detections\":[", frame.timestamp);
  for (std::size_t i = 0; i < frame.detections.size(); ++i) {
    const core::Detection& d = frame.detections[i];
    line += fmt::format("{}{{\"label\":{},\"class_id\":{},\"score\":{:.4f},\"box\":[{:.2f},{:.2f},{:.2f},{:.2f}]}}",
                        i == 0 ? "" : ",", json(d.label).dump(), d.class_id, d.score, d.box.x, d.box.y,
                        d.box.width, d.box.height);
  }
  line += "]}\n";
  file_.stream() << line;
}

}  // namespace hoidslam::io
