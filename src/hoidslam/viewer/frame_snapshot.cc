#include "hoidslam/viewer/frame_snapshot.h"

#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/hoid/explain.h"
#include "hoidslam/report/html_report.h"
#include "hoidslam/report/page_json.h"

namespace hoidslam::viewer {
namespace {

using report::PoseJson;
using report::Rounded;

std::string JpegDataUrl(const cv::Mat& image, double scale, int quality) {
  if (image.empty()) return {};
  cv::Mat shown = image;
  if (scale != 1.0) cv::resize(image, shown, cv::Size(), scale, scale, cv::INTER_AREA);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", shown, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality});
  return "data:image/jpeg;base64," +
         report::Base64Encode(std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size()));
}

std::string Text(const nlohmann::json& entry, const char* key) {
  const auto it = entry.find(key);
  return it != entry.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::size_t Count(const nlohmann::json& entry, const char* key) {
  const auto features = entry.find("features");
  if (features == entry.end()) return 0;
  const auto it = features->find(key);
  return it != features->end() && it->is_number_integer() ? it->get<std::size_t>() : 0;
}

}  // namespace

FrameSnapshot SnapshotOf(std::size_t index, const core::RgbdFrame& frame, const pipeline::FrameOutcome& outcome) {
  FrameSnapshot snapshot;
  snapshot.index = index;
  snapshot.timestamp = frame.timestamp;
  snapshot.image = frame.rgb;
  snapshot.keypoints.reserve(2 * outcome.features.keypoints.size());
  for (const cv::KeyPoint& k : outcome.features.keypoints) {
    snapshot.keypoints.push_back(k.pt.x);
    snapshot.keypoints.push_back(k.pt.y);
  }
  snapshot.keep = outcome.keep;
  snapshot.detections = outcome.boxes.detections;
  snapshot.decisions = outcome.boxes.decisions;
  if (outcome.result.T_cw) snapshot.T_wc = outcome.result.T_cw->inverse();
  snapshot.entry = outcome.entry;
  return snapshot;
}

std::string FrameEventJson(const FrameSnapshot& snapshot, double fps, double image_scale, int jpeg_quality) {
  const nlohmann::json& entry = snapshot.entry;
  nlohmann::json json = {{"index", snapshot.index},
                         {"timestamp", snapshot.timestamp},
                         {"state", Text(entry, "state")},
                         {"method", Text(entry, "method")},
                         {"failure", Text(entry, "failure")},
                         {"rejection", Text(entry, "rejection")},
                         {"map", entry.value("map", 0)},
                         {"keyframe", entry.value("keyframe", false)},
                         {"matched", Count(entry, "matched")},
                         {"inliers", Count(entry, "inliers")},
                         {"T_wc", snapshot.T_wc ? PoseJson(*snapshot.T_wc) : nlohmann::json()},
                         {"image", JpegDataUrl(snapshot.image, image_scale, jpeg_quality)},
                         {"width", snapshot.image.cols},
                         {"height", snapshot.image.rows},
                         {"keep", snapshot.keep},
                         {"kept", Count(entry, "kept")},
                         {"dropped", Count(entry, "dropped")},
                         {"fps", Rounded(fps, 10.0)}};
  nlohmann::json& keypoints = json["keypoints"] = nlohmann::json::array();
  for (const float v : snapshot.keypoints) keypoints.push_back(Rounded(v, 10.0));
  nlohmann::json& boxes = json["boxes"] = nlohmann::json::array();
  for (std::size_t i = 0; i < snapshot.detections.size(); ++i) {
    const core::Detection& d = snapshot.detections[i];
    boxes.push_back({{"box", {Rounded(d.box.x, 10.0), Rounded(d.box.y, 10.0), Rounded(d.box.width, 10.0),
                              Rounded(d.box.height, 10.0)}},
                     {"label", d.label},
                     {"score", Rounded(d.score, 100.0)},
                     {"dynamic", snapshot.decisions[i].dynamic},
                     {"caption", hoid::CaptionDecision(d, snapshot.decisions[i])},
                     {"reason", hoid::DescribeDecision(snapshot.detections, snapshot.decisions, i)}});
  }
  json["box_age"] = nullptr;
  if (const auto detections = entry.find("detections"); detections != entry.end()) {
    json["box_age"] = {{"frames", detections->value("age_frames", 0)}, {"ms", detections->value("age_ms", 0.0)}};
  }
  json["times"] = entry.contains("ms") ? entry["ms"] : nlohmann::json::object();
  return json.dump();
}

}  // namespace hoidslam::viewer
