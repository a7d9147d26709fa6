#include "hoidslam/report/html_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "hoidslam/core/error.h"
#include "hoidslam/core/shipped_dir.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/report/page_json.h"

namespace hoidslam::report {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using core::InputError;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- Reading ---------------------------------------------------------------------------------------------------

// Typed members of the JSON objects of one file (and line), every error naming the file, line and member.
class JsonFields {
 public:
  JsonFields(const fs::path& file, std::size_t line) : file_(file), line_(line) {}

  [[noreturn]] void Fail(const std::string& what) const {
    if (line_ == 0) throw InputError::InFile(file_, what);
    throw InputError::AtLine(file_, line_, what);
  }

  const json& Member(const json& object, const std::string& key) const {
    const auto it = object.find(key);
    if (it == object.end()) Fail(fmt::format("'{}' is missing", key));
    return *it;
  }

  const json& Object(const json& object, const std::string& key) const {
    const json& member = Member(object, key);
    if (!member.is_object()) Fail(fmt::format("'{}' must be an object, not {}", key, member.type_name()));
    return member;
  }

  template <typename T>
  T Get(const json& object, const std::string& key) const {
    const json& member = Member(object, key);
    try {
      return member.get<T>();
    } catch (const json::exception&) {
      Fail(fmt::format("'{}' has the wrong type ({})", key, member.type_name()));
    }
  }

 private:
  const fs::path& file_;
  std::size_t line_;
};

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError::InFile(path, "cannot open for reading");
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError::InFile(path, "cannot read");
  return bytes;
}

void RequireFolder(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw InputError::InFile(folder, "no such folder");
}

// `path` exists as a regular file; the message says it belongs in a run folder.
void RequireRunFile(const fs::path& path) {
  if (!fs::is_regular_file(path)) {
    throw InputError::InFile(path, "not found; is the folder an output folder of `hoidslam run`?");
  }
}

json ReadJsonObject(const fs::path& path) {
  RequireRunFile(path);
  json object;
  try {
    object = json::parse(ReadBytes(path));
  } catch (const json::parse_error& e) {
    throw InputError::InFile(path, fmt::format("not valid JSON ({})", e.what()));
  }
  if (!object.is_object()) throw InputError::InFile(path, "must hold a JSON object");
  return object;
}

ExclusionCounts ReadExclusionCounts(const JsonFields& fields, const json& object) {
  return {fields.Get<std::size_t>(object, "moving_kept"), fields.Get<std::size_t>(object, "moving_dropped"),
          fields.Get<std::size_t>(object, "static_kept"), fields.Get<std::size_t>(object, "static_dropped")};
}

// The camera the run used, from the settings summary.json records (provenance.settings.values, as
// io::SettingsToJson writes them); keys not recorded keep the defaults, the TUM fr3 camera.
core::CameraIntrinsics RecordedCamera(const JsonFields& fields, const json& summary) {
  core::CameraIntrinsics camera;
  const json* values = &summary;
  for (const char* key : {"provenance", "settings", "values"}) {
    if (!values->contains(key)) return camera;
    values = &fields.Object(*values, key);
  }
  for (const auto& [key, value] : {std::pair{"Camera.fx", &camera.fx}, std::pair{"Camera.fy", &camera.fy},
                                   std::pair{"Camera.cx", &camera.cx}, std::pair{"Camera.cy", &camera.cy}}) {
    if (values->contains(key)) *value = fields.Get<double>(*values, key);
  }
  for (const auto& [key, value] :
       {std::pair{"Camera.width", &camera.width}, std::pair{"Camera.height", &camera.height}}) {
    if (values->contains(key)) *value = fields.Get<int>(*values, key);
  }
  return camera;
}

void ReadSummary(const fs::path& path, RunReport& report) {
  const json summary = ReadJsonObject(path);
  const JsonFields fields(path, 0);
  report.sequence = fields.Get<std::string>(summary, "sequence");
  report.filter = fields.Get<std::string>(summary, "filter");
  report.detector = fields.Get<std::string>(summary, "detector");
  report.frames = fields.Get<std::size_t>(summary, "frames");
  report.tracked = fields.Get<std::size_t>(summary, "tracked");
  report.lost = fields.Get<std::size_t>(summary, "lost");
  report.before_initialization = fields.Get<std::size_t>(summary, "before_initialization");
  report.keyframes = fields.Get<std::size_t>(summary, "keyframes");
  report.map_points = fields.Get<std::size_t>(summary, "map_points");
  report.keypoints_extracted = fields.Get<std::size_t>(summary, "keypoints_extracted");
  report.keypoints_dropped = fields.Get<std::size_t>(summary, "keypoints_dropped");
  report.interrupted = fields.Get<bool>(summary, "interrupted");
  const json& median = fields.Object(summary, "median_ms");
  for (const char* stage : {"load", "extract", "detect", "filter", "track"}) {
    if (median.contains(stage)) report.median_ms.push_back({stage, fields.Get<double>(median, stage)});
  }
  if (median.contains("tracking_total")) report.median_tracking_ms = fields.Get<double>(median, "tracking_total");
  // null (or absent) on a sequence without ground-truth moving masks, such as every real recording.
  if (summary.contains("exclusion_quality") && !summary.at("exclusion_quality").is_null()) {
    const json& quality = fields.Object(summary, "exclusion_quality");
    report.exclusion_quality = ExclusionQuality{fields.Get<double>(quality, "leaked"),
                                                fields.Get<double>(quality, "wasted"),
                                                ReadExclusionCounts(fields, quality)};
  }
  report.camera = RecordedCamera(fields, summary);
}

// map.ply and keyframes.txt into report.map, or into report.no_map the one that is missing.
void ReadRunMap(const fs::path& folder, RunReport& report) {
  for (const char* file : {"map.ply", "keyframes.txt"}) {
    if (!fs::exists(folder / file)) {
      report.no_map = fmt::format("the run folder has no {}", file);
      return;
    }
  }
  report.map = RunMap{io::ReadPly(folder / "map.ply"), io::ReadTumTrajectory(folder / "keyframes.txt")};
}

DynamicDetection ReadDynamic(const JsonFields& fields, const json& object) {
  if (!object.is_object()) fields.Fail("each entry of 'dynamic' must be an object");
  DynamicDetection d;
  d.label = fields.Get<std::string>(object, "label");
  d.score = fields.Get<double>(object, "score");
  d.box = fields.Get<std::array<double, 4>>(object, "box");
  d.reason = fields.Get<std::string>(object, "reason");
  if (object.contains("person")) d.person = fields.Get<int>(object, "person");
  if (object.contains("interaction")) d.interaction = fields.Get<double>(object, "interaction");
  return d;
}

std::vector<FrameRecord> ReadFrameLog(const fs::path& path) {
  RequireRunFile(path);
  std::ifstream in(path);
  if (!in) throw InputError::InFile(path, "cannot open for reading");
  std::vector<FrameRecord> records;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    const JsonFields fields(path, line);
    json object;
    try {
      object = json::parse(text);
    } catch (const json::parse_error& e) {
      fields.Fail(fmt::format("not valid JSON ({})", e.what()));
    }
    if (!object.is_object()) fields.Fail("each line must be a JSON object");
    FrameRecord r;
    r.frame = fields.Get<std::size_t>(object, "frame");
    r.timestamp = fields.Get<double>(object, "timestamp");
    r.state = fields.Get<std::string>(object, "state");
    r.method = fields.Get<std::string>(object, "method");
    r.keyframe = fields.Get<bool>(object, "keyframe");
    const json& features = fields.Object(object, "features");
    r.extracted = fields.Get<std::size_t>(features, "extracted");
    r.dropped = fields.Get<std::size_t>(features, "dropped");
  // Logs written before the second extraction have no "kept": tracking had what the filter left.
  r.kept = features.contains("kept") ? fields.Get<std::size_t>(features, "kept") : r.extracted - std::min(r.dropped, r.extracted);
    r.matched = fields.Get<std::size_t>(features, "matched");
    r.inliers = fields.Get<std::size_t>(features, "inliers");
    const json& dynamic = fields.Member(object, "dynamic");
    if (!dynamic.is_array()) fields.Fail("'dynamic' must be an array");
    for (const json& d : dynamic) r.dynamic.push_back(ReadDynamic(fields, d));
    if (object.contains("exclusion")) r.exclusion = ReadExclusionCounts(fields, fields.Object(object, "exclusion"));
    if (object.contains("detector_error")) r.detector_error = fields.Get<std::string>(object, "detector_error");
    if (object.contains("detections")) {
      r.detection_age_ms = fields.Get<double>(fields.Object(object, "detections"), "age_ms");
    }
    if (object.contains("dropped_before")) r.dropped_before = fields.Get<std::size_t>(object, "dropped_before");
    records.push_back(std::move(r));
  }
  return records;
}

// snapshots/<frame>.jpg, the frame index written with at least 6 digits; other files there are not ours.
std::vector<Snapshot> ReadSnapshots(const fs::path& folder) {
  std::vector<Snapshot> snapshots;
  if (!fs::is_directory(folder)) return snapshots;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string stem = entry.path().stem().string();
    const bool named_by_frame = stem.size() >= 6 && std::all_of(stem.begin(), stem.end(), [](unsigned char c) {
      return std::isdigit(c) != 0;
    });
    if (!entry.is_regular_file() || entry.path().extension() != ".jpg" || !named_by_frame) continue;
    Snapshot snapshot{std::stoul(stem), entry.path(), ReadBytes(entry.path())};
    if (!snapshot.jpeg.starts_with("\xFF\xD8\xFF")) throw InputError::InFile(entry.path(), "is not a JPEG image");
    snapshots.push_back(std::move(snapshot));
  }
  std::sort(snapshots.begin(), snapshots.end(), [](const Snapshot& a, const Snapshot& b) { return a.frame < b.frame; });
  return snapshots;
}

// The estimate against ground truth by eval's own association and alignment; fills report.comparison or, when the
// two do not fit together (too few matching stamps), report.not_compared.
void Compare(const fs::path& groundtruth, const fs::path& estimate_file, RunReport& report) {
  const core::Trajectory groundtruth_poses = io::ReadTumTrajectory(groundtruth);  // a bad file is an error
  GroundTruthComparison comparison;
  try {
    comparison.evaluation = eval::EvaluateTrajectoryFiles(groundtruth, estimate_file, {});
  } catch (const InputError& e) {
    report.not_compared = e.what();
    spdlog::warn("not compared with ground truth: {}", e.what());
    return;
  }
  // Ground truth usually covers more than the frames run (--frames, a cut recording): only the run's time span.
  const double margin = comparison.evaluation.options.ate.association.max_difference;
  double first = -std::numeric_limits<double>::infinity();
  double last = std::numeric_limits<double>::infinity();
  if (!report.frame_log.empty()) {
    first = report.frame_log.front().timestamp - margin;
    last = report.frame_log.back().timestamp + margin;
  }
  for (const core::StampedPose& pose : groundtruth_poses) {
    if (pose.timestamp >= first && pose.timestamp <= last) comparison.groundtruth.push_back(pose.T_wc.translation());
  }
  for (const core::StampedPose& pose : report.estimate) {
    comparison.aligned_estimate.push_back(comparison.evaluation.ate.alignment.Apply(pose.T_wc.translation()));
  }
  report.comparison = std::move(comparison);
}

// ---- Writing -----------------------------------------------------------------------------------------------------

constexpr std::string_view kStyle = R"(
:root { --ink: #222; --muted: #666; --rule: #e3e5e8; --accent: #8797ab; }
* { box-sizing: border-box; }
body { margin: 0; background: #f4f5f7; color: var(--ink);
       font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, Helvetica, Arial, sans-serif; }
body > main { max-width: 1100px; margin: 0 auto; padding: 28px 30px 40px; background: #fff; min-height: 100vh; }
h1 { font-size: 26px; margin: 0 0 2px; }
h2 { font-size: 19px; margin: 32px 0 10px; padding-bottom: 4px; border-bottom: 1px solid var(--rule); }
.sub { color: var(--muted); margin: 0; }
.sub b { color: var(--ink); }
.cards { display: grid; grid-template-columns: repeat(auto-fill, minmax(150px, 1fr)); gap: 10px; margin: 18px 0 6px; }
.card { border: 1px solid var(--rule); border-left: 4px solid var(--accent); border-radius: 6px; padding: 8px 12px; }
.card .k { color: var(--muted); font-size: 12px; text-transform: uppercase; letter-spacing: .04em; }
.card .v { font-size: 20px; font-weight: 600; font-variant-numeric: tabular-nums; }
.card .d { color: var(--muted); font-size: 12px; }
.note { background: #fff6e0; border: 1px solid #f0d9a0; border-radius: 6px; padding: 8px 12px; margin: 12px 0; }
.row { display: flex; flex-wrap: wrap; gap: 20px; align-items: flex-start; }
.row > * { flex: 1 1 480px; min-width: 0; }
figure { margin: 10px 0; }
figure svg { display: block; max-width: 100%; height: auto; }
figcaption { color: var(--muted); font-size: 13px; margin-top: 4px; }
table { border-collapse: collapse; margin: 10px 0; font-size: 14px; font-variant-numeric: tabular-nums; }
caption { text-align: left; font-weight: 600; padding-bottom: 4px; }
th, td { padding: 4px 12px 4px 0; border-bottom: 1px solid var(--rule); text-align: left; vertical-align: top; }
th { border-bottom: 2px solid #ccc; }
td.num { text-align: right; }
p.table-note { color: var(--muted); font-size: 13px; margin: -4px 0 12px; font-style: italic; }
.snapshots { display: grid; grid-template-columns: repeat(auto-fill, minmax(330px, 1fr)); gap: 18px; }
.snapshots figure { margin: 0; }
.snapshots img { display: block; width: 100%; height: auto; border-radius: 4px; border: 1px solid var(--rule); }
.snapshots figcaption { color: var(--ink); }
.snapshots ul { margin: 4px 0 0; padding-left: 18px; }
/* The map section's viewer page, made to fill a window, fills a box; it has a <main> of its own (body > main). */
#hoidslam-viewer { height: 640px; border-radius: 6px; overflow: hidden; }
footer { color: var(--muted); font-size: 12px; margin-top: 36px; border-top: 1px solid var(--rule); padding-top: 8px; }
@media print {
  body { background: #fff; }
  body > main { max-width: none; padding: 0; min-height: 0; }
  h2 { break-after: avoid; }
  figure, table, .card, .note { break-inside: avoid; }
}
)";

bool IsNumber(const std::string& text) {
  if (text.empty()) return false;
  char* end = nullptr;
  std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

std::string Percent(std::size_t part, std::size_t whole) {
  return whole == 0 ? std::string("–") : fmt::format("{:.1f} %", 100.0 * part / whole);
}

std::string Card(std::string_view key, std::string_view value, std::string_view detail = "") {
  return fmt::format(R"(<div class="card"><div class="k">{}</div><div class="v">{}</div><div class="d">{}</div></div>)",
                     EscapeXml(key), EscapeXml(value), EscapeXml(detail));
}

std::string Figure(const std::string& svg, std::string_view caption = "") {
  if (caption.empty()) return fmt::format("<figure>{}</figure>\n", svg);
  return fmt::format("<figure>{}<figcaption>{}</figcaption></figure>\n", svg, EscapeXml(caption));
}

std::string Note(std::string_view text) { return fmt::format("<p class=\"note\">{}</p>\n", EscapeXml(text)); }

// "per 1 s", "per 10 frames": the step RPE compares over.
std::string RpeStep(const eval::RpeOptions& options) {
  return fmt::format("per {} {}", options.delta, options.delta_unit == eval::DeltaUnit::kSeconds ? "s" : "frames");
}

// Seconds since the first frame, the time axis of every chart of a run.
double StartTime(const RunReport& report) {
  if (!report.frame_log.empty()) return report.frame_log.front().timestamp;
  return report.estimate.empty() ? 0.0 : report.estimate.front().timestamp;
}

Path3d GroundTruthPath(const GroundTruthComparison& comparison) {
  return {"ground truth", comparison.groundtruth, std::string(kGroundTruthColour), 6.0};
}

std::string Header(const RunReport& report) {
  std::string html = fmt::format("<h1>{}</h1>\n<p class=\"sub\">filter <b>{}</b> · detector <b>{}</b> · {}</p>\n",
                                 EscapeXml(report.sequence), EscapeXml(report.filter), EscapeXml(report.detector),
                                 EscapeXml(report.folder.string()));
  html += "<div class=\"cards\">\n";
  html += Card("frames", std::to_string(report.frames));
  html += Card("tracked", std::to_string(report.tracked), Percent(report.tracked, report.frames));
  html += Card("lost", std::to_string(report.lost),
               report.before_initialization > 0
                   ? fmt::format("{} more before initialisation", report.before_initialization)
                   : "");
  html += Card("keyframes", std::to_string(report.keyframes));
  html += Card("map points", std::to_string(report.map_points));
  html += Card("keypoints dropped", Percent(report.keypoints_dropped, report.keypoints_extracted),
               fmt::format("{} of {}", report.keypoints_dropped, report.keypoints_extracted));
  if (report.comparison) {
    const eval::Evaluation& e = report.comparison->evaluation;
    // An ATE says nothing without the frames it was measured on: a lost frame has no error to count.
    html += Card("ATE RMSE", FormatSignificant(e.ate.error.rmse, 3) + " m",
                 fmt::format("on {} of {} frames tracked; max {} m", e.ate.error.count, report.frames,
                             FormatSignificant(e.ate.error.max, 3)));
    html += Card("RPE translation", FormatSignificant(e.rpe.translation.rmse, 3) + " m",
                 "RMSE " + RpeStep(e.options.rpe));
    html += Card("RPE rotation", FormatSignificant(e.rpe.rotation_deg.rmse, 3) + " °",
                 "RMSE " + RpeStep(e.options.rpe));
  }
  if (report.median_tracking_ms) {
    html += Card("tracking time", FormatSignificant(*report.median_tracking_ms, 3) + " ms",
                 "median per frame, detector excluded");
  }
  html += "</div>\n";
  if (report.interrupted) html += Note("The run was interrupted: it holds the frames done before it stopped.");
  if (!report.not_compared.empty()) html += Note("Not compared with ground truth: " + report.not_compared);
  if (!report.comparison && report.not_compared.empty()) {
    html += Note("No ground truth given: the trajectory is shown as estimated, without errors.");
  }
  return html;
}

Table ErrorTable(const eval::Evaluation& evaluation) {
  Table table;
  table.title = "Error against ground truth";
  table.note = fmt::format("ground truth {}; ATE after {} alignment, as TUM's evaluate_ate.py",
                           evaluation.groundtruth_path.string(),
                           evaluation.options.ate.estimate_scale ? "Sim(3)" : "rigid");
  table.header = {"", "rmse", "mean", "median", "max", "pairs"};
  const auto row = [](std::string name, const eval::ErrorStatistics& s) {
    return std::vector<std::string>{std::move(name),        FormatSignificant(s.rmse, 3), FormatSignificant(s.mean, 3),
                                    FormatSignificant(s.median, 3), FormatSignificant(s.max, 3),
                                    std::to_string(s.count)};
  };
  const std::string step = RpeStep(evaluation.options.rpe);
  table.rows = {row("ATE (m)", evaluation.ate.error),
                row("RPE translation (m " + step + ")", evaluation.rpe.translation),
                row("RPE rotation (° " + step + ")", evaluation.rpe.rotation_deg)};
  return table;
}

// The position error of every matched pose over time (seconds from the run's first frame). Frames without a pose
// break the line, so a loss of tracking shows as a gap. Requires report.comparison.
LineSeries AteErrorSeries(const RunReport& report, std::string name, std::string colour) {
  const double t0 = StartTime(report);
  std::vector<std::pair<double, double>> points;
  std::vector<double> evaluated;
  for (const eval::AtePair& pair : report.comparison->evaluation.ate.pairs) {
    points.emplace_back(pair.estimate_timestamp - t0, pair.error);
    evaluated.push_back(pair.estimate_timestamp);
  }
  std::sort(evaluated.begin(), evaluated.end());
  // A gap in the line wherever a frame has no pose: lost, or tracked provisionally and withdrawn.
  for (const FrameRecord& frame : report.frame_log) {
    const auto near = std::lower_bound(evaluated.begin(), evaluated.end(), frame.timestamp - 1e-4);
    if (near == evaluated.end() || *near > frame.timestamp + 1e-4) points.emplace_back(frame.timestamp - t0, kNaN);
  }
  std::stable_sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  LineSeries errors{.name = std::move(name), .colour = std::move(colour)};
  for (const auto& [t, e] : points) {
    errors.x.push_back(t);
    errors.y.push_back(e);
  }
  return errors;
}

std::string TrajectorySection(const RunReport& report) {
  ChartOptions trajectory_options{.title = "Trajectory seen from above", .width = 520, .height = 470};
  std::vector<Path3d> paths;
  if (report.comparison) {
    paths.push_back(GroundTruthPath(*report.comparison));
    paths.push_back({"estimate, aligned", report.comparison->aligned_estimate, std::string(PaletteColour(0))});
  } else {
    std::vector<Eigen::Vector3d> positions;
    for (const core::StampedPose& pose : report.estimate) positions.push_back(pose.T_wc.translation());
    paths.push_back({"estimate", positions, std::string(PaletteColour(0))});
  }
  std::string html = "<section>\n<h2>Trajectory</h2>\n<div class=\"row\">\n";
  html += Figure(PathPlot(paths, trajectory_options),
                 report.comparison
                     ? "The estimate aligned onto the ground truth as for ATE; a dot marks the start."
                     : "Camera positions as estimated (frame of the first camera); a dot marks the start.");
  if (report.comparison) {
    const LineSeries errors = AteErrorSeries(report, "", std::string(PaletteColour(1)));
    const ChartOptions error_options{.title = "ATE over time", .x_label = "time (s)",
                                     .y_label = "position error (m)", .width = 520, .height = 470};
    html += Figure(LineChart(std::span(&errors, 1), error_options),
                   "Distance between each aligned estimated position and the ground truth at the same time.");
  }
  html += "</div>\n";
  if (report.comparison) html += TableHtml(ErrorTable(report.comparison->evaluation));
  return html + "</section>\n";
}

std::string FeaturesSection(const RunReport& report) {
  const double t0 = StartTime(report);
  std::vector<LineSeries> series = {{.name = "extracted"},
                                    {.name = "dropped by the filter"},
                                    {.name = "tracked"},
                                    {.name = "inliers"}};
  for (const FrameRecord& frame : report.frame_log) {
    const double t = frame.timestamp - t0;
    const std::size_t counts[] = {frame.extracted, frame.dropped, frame.kept, frame.inliers};
    for (std::size_t i = 0; i < series.size(); ++i) {
      series[i].x.push_back(t);
      series[i].y.push_back(static_cast<double>(counts[i]));
    }
  }
  const ChartOptions options{.title = "Keypoints per frame", .x_label = "time (s)", .y_label = "keypoints",
                             .width = 1040, .height = 320};
  return "<section>\n<h2>Features</h2>\n" +
         Figure(LineChart(series, options),
                "ORB keypoints extracted over the whole image, dropped by the filter before tracking, handed to "
                "tracking (with the static keypoint budget, a second extraction outside what is dynamic spends the "
                "budget again), and the inliers of the final pose.") +
         "</section>\n";
}

// Real-time runs: how old each frame's detections were, and the frames a paced run dropped. Empty for runs whose
// frames all waited for their own detections and dropped none.
std::string RealTimeSection(const RunReport& report) {
  std::size_t dropped = 0;
  bool late = false;
  for (const FrameRecord& frame : report.frame_log) {
    dropped += frame.dropped_before;
    late |= frame.detection_age_ms.value_or(0.0) > 0.0;
  }
  if (!late && dropped == 0) return "";
  const double t0 = StartTime(report);
  LineSeries age{.name = "age of the detections", .colour = std::string(PaletteColour(3))};
  for (const FrameRecord& frame : report.frame_log) {
    age.x.push_back(frame.timestamp - t0);
    age.y.push_back(frame.detection_age_ms.value_or(kNaN));
  }
  const ChartOptions options{.title = "Age of the detections per frame", .x_label = "time (s)", .y_label = "ms",
                             .width = 1040, .height = 260};
  return "<section>\n<h2>Real time</h2>\n" +
         Figure(LineChart(std::span(&age, 1), options),
                fmt::format("How much older than each frame (in the recording's time) the detections that judged it "
                            "were: the detector runs in its own thread and tracking does not wait for it. {} frame{} "
                            "dropped, arriving while the system was busy.",
                            dropped, dropped == 1 ? "" : "s")) +
         "</section>\n";
}

std::string TimingSection(const RunReport& report) {
  if (report.median_ms.empty()) return "";
  std::vector<std::string> stages;
  BarSeries bars{.name = "", .colour = std::string(PaletteColour(2))};
  Table table;
  table.header = {"stage", "median ms per frame"};
  for (const StageTime& stage : report.median_ms) {
    stages.push_back(stage.stage);
    bars.values.push_back(stage.median_ms);
    table.rows.push_back({stage.stage, FormatSignificant(stage.median_ms, 3)});
  }
  if (report.median_tracking_ms) {
    table.rows.push_back({"tracking (extract + filter + track)", FormatSignificant(*report.median_tracking_ms, 3)});
  }
  table.note = "load is reading and decoding the images; the tracking budget leaves out load and detect";
  const BarChartOptions options{.chart = {.title = "Median time per stage", .y_label = "ms per frame",
                                          .width = 520, .height = 300}};
  return "<section>\n<h2>Time per stage</h2>\n<div class=\"row\">\n" +
         Figure(BarChart(stages, std::span(&bars, 1), options)) + "<div>" + TableHtml(table) + "</div>\n</div>\n" +
         "</section>\n";
}

std::string ExclusionSection(const RunReport& report) {
  const bool per_frame = std::any_of(report.frame_log.begin(), report.frame_log.end(),
                                     [](const FrameRecord& f) { return f.exclusion.has_value(); });
  std::string html = "<section>\n<h2>Exclusion against the moving pixels</h2>\n";
  if (!report.exclusion_quality && !per_frame) {
    // A real recording has no per-pixel truth of what moved: say so rather than leave the reader to wonder.
    return html + Note("Not scored: the sequence has no ground-truth masks of the moving pixels (a mask/ folder, as "
                       "hoidslam synth writes), so which keypoints lay on moving things is unknown.") +
           "</section>\n";
  }
  if (report.exclusion_quality) {
    const ExclusionQuality& q = *report.exclusion_quality;
    const ExclusionCounts& c = q.counts;
    Table table;
    table.title = "Keypoints on the ground-truth moving mask";
    table.header = {"keypoints", "all", "kept", "dropped", ""};
    table.rows = {
        {"on moving pixels", std::to_string(c.moving_kept + c.moving_dropped), std::to_string(c.moving_kept),
         std::to_string(c.moving_dropped), fmt::format("leaked: {:.1f} % kept", 100.0 * q.leaked)},
        {"on static pixels", std::to_string(c.static_kept + c.static_dropped), std::to_string(c.static_kept),
         std::to_string(c.static_dropped), fmt::format("wasted: {:.1f} % dropped", 100.0 * q.wasted)}};
    table.note = "leaked keypoints feed moving things to tracking; wasted ones are static structure thrown away";
    html += TableHtml(table);
  }
  if (per_frame) {
    const double t0 = StartTime(report);
    std::vector<LineSeries> series = {
        {.name = "moving keypoints kept (leaked)", .colour = std::string(PaletteColour(1))},
        {.name = "static keypoints dropped (wasted)", .colour = std::string(PaletteColour(4))}};
    for (const FrameRecord& frame : report.frame_log) {
      const double t = frame.timestamp - t0;
      series[0].x.push_back(t);
      series[1].x.push_back(t);
      series[0].y.push_back(frame.exclusion ? static_cast<double>(frame.exclusion->moving_kept) : kNaN);
      series[1].y.push_back(frame.exclusion ? static_cast<double>(frame.exclusion->static_dropped) : kNaN);
    }
    const ChartOptions options{.title = "Exclusion errors per frame", .x_label = "time (s)", .y_label = "keypoints",
                               .width = 1040, .height = 300};
    html += Figure(LineChart(series, options));
  }
  return html + "</section>\n";
}

// "tv 1.00: interaction with person #15 (100 % of its box)"
std::string DescribeDynamic(const DynamicDetection& d) {
  std::string text = fmt::format("{:.2f}: {}", d.score, d.reason);
  if (d.person >= 0) text += fmt::format(" with person #{}", d.person);
  if (d.interaction) text += fmt::format(" ({:.0f} % of its box)", 100.0 * *d.interaction);
  return text;
}

std::string SnapshotCaption(const Snapshot& snapshot, const FrameRecord* frame, double t0) {
  if (frame == nullptr) return fmt::format("<b>frame {}</b> (not in frames.jsonl)", snapshot.frame);
  std::string html = fmt::format("<b>frame {}</b> · {:.2f} s · {} ({}{})<br>{} keypoints, {} dropped, {} inliers",
                                 frame->frame, frame->timestamp - t0, EscapeXml(frame->state), EscapeXml(frame->method),
                                 frame->keyframe ? ", keyframe" : "", frame->extracted, frame->dropped, frame->inliers);
  if (frame->exclusion) {
    const ExclusionCounts& c = *frame->exclusion;
    html += fmt::format("<br>moving keypoints kept {} of {}, static dropped {} of {}", c.moving_kept,
                        c.moving_kept + c.moving_dropped, c.static_dropped, c.static_kept + c.static_dropped);
  }
  if (!frame->detector_error.empty()) html += "<br>detector failed: " + EscapeXml(frame->detector_error);
  if (!frame->dynamic.empty()) {
    html += "<ul>";
    for (const DynamicDetection& d : frame->dynamic) {
      html += fmt::format("<li><b>{}</b> {}</li>", EscapeXml(d.label), EscapeXml(DescribeDynamic(d)));
    }
    html += "</ul>";
  }
  return html;
}

// The page's embedded data (docs/viewer.md, "The same page in a report"): hello and the main map, whole, as map 0,
// and the dense map when there is one; no frame, so the page shows the map alone. Escaped for a <script> element.
std::string ViewerData(const RunReport& report) {
  const RunMap& map = *report.map;
  PointsJson points;
  for (std::size_t i = 0; i < map.points.size(); ++i) points.Add(i, 0, map.points[i].position, map.points[i].bgr);
  json keyframes = json::array();
  for (std::size_t i = 0; i < map.keyframes.size(); ++i) {
    keyframes.push_back(KeyframeJson(i, 0, map.keyframes[i].T_wc));
  }
  json data = {
      {"hello", HelloJson(report.sequence, report.frames, report.camera, false)},
      {"map",
       {{"full", true},
        {"main_map", 0},
        {"maps", json::array({MapCountsJson(0, map.points.size(), map.keyframes.size())})},
        {"points", std::move(points).ToJson()},
        {"keyframes", std::move(keyframes)}}}};
  if (report.dense_mesh) data["dense"] = DenseMeshJson(*report.dense_mesh);
  std::string text = data.dump(-1, ' ', false, json::error_handler_t::replace);
  // '<' appears only inside JSON strings, where \u003c means the same: no "</script" or "<!--" can end the element
  // early or change how the browser reads it.
  for (std::size_t at = 0; (at = text.find('<', at)) != std::string::npos;) text.replace(at, 1, "\\u003c");
  return text;
}

std::string MapSection(const RunReport& report, const ViewerBundle& viewer) {
  std::string html = "<section>\n<h2>Map</h2>\n";
  const std::string& missing = report.map ? viewer.missing : report.no_map;
  if (!missing.empty()) return html + Note("No 3D view of the map: " + missing + ".") + "</section>\n";
  html += fmt::format(
      "<p class=\"sub\">The main map as the run wrote it: the {} points of map.ply in their own colours and the {} "
      "keyframes of keyframes.txt as cameras along their path. Drag to turn, right-drag to pan, scroll to zoom.</p>\n",
      report.map->points.size(), report.map->keyframes.size());
  if (report.dense_mesh) {
    html += fmt::format("<p class=\"sub\">The dense map of mesh.ply with it, made small enough to show: {} triangles "
                        "(at most {}). <b>dense map</b> shows or hides it.</p>\n",
                        report.dense_mesh->triangles.size(), kReportDenseTriangles);
  }
  return html + "<style>" + viewer.style + "</style>\n<div id=\"hoidslam-viewer\"></div>\n" +
         "<script id=\"hoidslam-data\" type=\"application/json\">" + ViewerData(report) + "</script>\n" +
         "<script>" + viewer.script + "</script>\n</section>\n";
}

std::string SnapshotsSection(const RunReport& report) {
  if (report.snapshots.empty()) return "";
  return "<section>\n<h2>Annotated frames</h2>\n<p class=\"sub\">Boxes coloured by the filter's decision with the "
         "interaction ratio; keypoints kept green, dropped red.</p>\n" +
         SnapshotGallery(report, report.snapshots.size()) + "</section>\n";
}

}  // namespace

std::string SnapshotGallery(const RunReport& report, std::size_t count) {
  if (report.snapshots.empty() || count == 0) return "";
  const double t0 = StartTime(report);
  std::string html = "<div class=\"snapshots\">\n";
  // `count` of them, spread evenly over the ones the run saved.
  for (std::size_t k = 0; k < std::min(count, report.snapshots.size()); ++k) {
    const Snapshot& snapshot = report.snapshots[(2 * k + 1) * report.snapshots.size() / (2 * count)];
    const auto frame = std::find_if(report.frame_log.begin(), report.frame_log.end(),
                                    [&](const FrameRecord& f) { return f.frame == snapshot.frame; });
    html += fmt::format("<figure><img src=\"data:image/jpeg;base64,{}\" alt=\"frame {}\"><figcaption>{}</figcaption>"
                        "</figure>\n",
                        Base64Encode(snapshot.jpeg), snapshot.frame,
                        SnapshotCaption(snapshot, frame == report.frame_log.end() ? nullptr : &*frame, t0));
  }
  return html + "</div>\n";
}

RunReport LoadRunReport(const fs::path& run_folder, const fs::path& groundtruth) {
  RequireFolder(run_folder);
  RunReport report;
  report.folder = run_folder;
  ReadSummary(run_folder / "summary.json", report);
  report.frame_log = ReadFrameLog(run_folder / "frames.jsonl");
  const fs::path trajectory = run_folder / "trajectory.txt";
  RequireRunFile(trajectory);
  report.estimate = io::ReadTumTrajectory(trajectory);
  report.snapshots = ReadSnapshots(run_folder / "snapshots");
  ReadRunMap(run_folder, report);
  if (!groundtruth.empty()) Compare(groundtruth, trajectory, report);
  return report;
}

fs::path RecordedGroundTruth(const fs::path& run_folder) {
  RequireFolder(run_folder);
  const fs::path path = run_folder / "summary.json";
  const json summary = ReadJsonObject(path);
  if (!summary.contains("evaluation")) return {};
  const JsonFields fields(path, 0);
  return fields.Get<std::string>(fields.Object(fields.Object(summary, "evaluation"), "groundtruth"), "path");
}

fs::path RecordedGroundTruthIfPresent(const fs::path& run_folder, std::string_view option) {
  fs::path groundtruth = RecordedGroundTruth(run_folder);
  if (!groundtruth.empty() && !fs::exists(groundtruth)) {
    spdlog::warn("{}: the ground truth the run {} was evaluated against is not there; no errors for it (give {})",
                 groundtruth.string(), run_folder.string(), option);
    groundtruth.clear();
  }
  return groundtruth;
}

ViewerBundle LoadViewerBundle(const fs::path& web_dir) {
  const auto none = [](std::string why) { return ViewerBundle{.script = "", .style = "", .missing = std::move(why)}; };
  ViewerBundle bundle;
  try {
    bundle.script = ReadBytes(web_dir / "viewer.js");
    bundle.style = ReadBytes(web_dir / "viewer.css");
  } catch (const InputError& e) {
    return none(fmt::format("the viewer's page is not there ({})", e.what()));
  }
  // An inline element ends at the first "</script" or "</style", whatever the case, even inside a string.
  const auto holds_end_tag = [](std::string text, std::string_view tag) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text.find(fmt::format("</{}", tag)) != std::string::npos;
  };
  for (const auto& [file, text, tag] : {std::tuple{"viewer.js", &bundle.script, "script"},
                                        std::tuple{"viewer.css", &bundle.style, "style"}}) {
    if (holds_end_tag(*text, tag)) {
      return none(fmt::format("{} holds \"</{}\" and cannot be inlined", (web_dir / file).string(), tag));
    }
  }
  return bundle;
}

std::string RenderRunHtml(const RunReport& report, const ViewerBundle& viewer) {
  std::string body = Header(report);
  body += TrajectorySection(report);
  body += MapSection(report, viewer);
  body += FeaturesSection(report);
  body += TimingSection(report);
  body += ExclusionSection(report);
  body += RealTimeSection(report);
  body += SnapshotsSection(report);
  body += fmt::format("<footer>Written by <code>hoidslam report</code> from {}.</footer>\n",
                      EscapeXml(report.folder.string()));
  return HtmlPage(fmt::format("{} · {} · hoidslam", report.sequence, report.filter), body);
}

void WriteRunReport(const fs::path& run_folder, const fs::path& groundtruth, const fs::path& out_html,
                    const fs::path& shown_folder, std::optional<io::TriangleMesh> dense_mesh) {
  RunReport report = LoadRunReport(run_folder, groundtruth);
  if (!shown_folder.empty()) report.folder = shown_folder;
  report.dense_mesh = std::move(dense_mesh);
  const ViewerBundle viewer = LoadViewerBundle(core::WebDir());
  if (!viewer.missing.empty()) spdlog::warn("the report has no 3D view of the map: {}", viewer.missing);
  const std::string html = RenderRunHtml(report, viewer);
  io::AtomicFile file(out_html);
  file.stream() << html;
  file.Commit();
}

std::string RenderBenchHtml(const std::string& title, const std::vector<std::string>& intro_lines,
                            const std::vector<BenchReportSection>& sections) {
  std::string body = fmt::format("<h1>{}</h1>\n", EscapeXml(title));
  if (!intro_lines.empty()) {
    body += "<ul class=\"sub\">\n";
    for (const std::string& line : intro_lines) body += fmt::format("<li>{}</li>\n", EscapeXml(line));
    body += "</ul>\n";
  }
  for (const BenchReportSection& section : sections) {
    body += fmt::format("<section>\n<h2>{}</h2>\n", EscapeXml(section.heading));
    std::size_t start = 0;
    while (start < section.text.size()) {
      const std::size_t end = std::min(section.text.find("\n\n", start), section.text.size());
      const std::string_view paragraph = std::string_view(section.text).substr(start, end - start);
      if (paragraph.find_first_not_of(" \n") != std::string_view::npos) {
        body += fmt::format("<p>{}</p>\n", EscapeXml(paragraph));
      }
      start = end + 2;
    }
    for (const Table& table : section.tables) body += TableHtml(table);
    if (!section.svg_figures.empty()) {
      body += "<div class=\"row\">\n";
      for (const std::string& svg : section.svg_figures) body += Figure(svg);
      body += "</div>\n";
    }
    body += section.html;
    body += "</section>\n";
  }
  body += "<footer>Written by <code>hoidslam bench</code>.</footer>\n";
  return HtmlPage(title, body);
}

std::string TrajectoryOverlaySvg(std::span<const RunReport> runs, std::span<const std::string> labels) {
  if (!labels.empty() && labels.size() != runs.size()) {
    throw std::invalid_argument(fmt::format("TrajectoryOverlaySvg: {} labels for {} runs", labels.size(), runs.size()));
  }
  const auto reference = std::find_if(runs.begin(), runs.end(), [](const RunReport& r) { return r.comparison; });
  std::vector<Path3d> paths;
  if (reference != runs.end()) paths.push_back(GroundTruthPath(*reference->comparison));
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunReport& run = runs[i];
    Path3d path{labels.empty() ? run.filter : labels[i], {}, std::string(PaletteColour(i))};
    if (run.comparison) {
      if (run.comparison->evaluation.groundtruth_path != reference->comparison->evaluation.groundtruth_path) {
        throw std::invalid_argument(fmt::format("TrajectoryOverlaySvg: runs compared with {} and with {}",
                                                reference->comparison->evaluation.groundtruth_path.string(),
                                                run.comparison->evaluation.groundtruth_path.string()));
      }
      path.points = run.comparison->aligned_estimate;
    } else {
      path.name += " (no aligned trajectory)";
    }
    paths.push_back(std::move(path));
  }
  const std::string sequence = runs.empty() ? std::string() : runs.front().sequence;
  return PathPlot(paths, {.title = fmt::format("{}: trajectories seen from above", sequence), .width = 640,
                          .height = 520});
}

std::string AteOverTimeSvg(std::span<const RunReport> runs, std::span<const std::string> labels) {
  if (!labels.empty() && labels.size() != runs.size()) {
    throw std::invalid_argument(fmt::format("AteOverTimeSvg: {} labels for {} runs", labels.size(), runs.size()));
  }
  std::vector<LineSeries> series;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!runs[i].comparison) continue;
    series.push_back(AteErrorSeries(runs[i], labels.empty() ? runs[i].filter : labels[i], std::string(PaletteColour(i))));
  }
  const std::string sequence = runs.empty() ? std::string() : runs.front().sequence;
  return LineChart(series, {.title = fmt::format("{}: ATE over time", sequence), .x_label = "time (s)",
                            .y_label = "position error (m)", .width = 640, .height = 520});
}

std::string AteBarChartSvg(const std::vector<std::string>& sequences, const std::vector<std::string>& modes,
                           const std::vector<std::vector<double>>& ate_m) {
  if (ate_m.size() != sequences.size()) {
    throw std::invalid_argument(fmt::format("AteBarChartSvg: {} rows of values for {} sequences", ate_m.size(),
                                            sequences.size()));
  }
  std::vector<BarSeries> series;
  for (std::size_t m = 0; m < modes.size(); ++m) series.push_back({.name = modes[m]});
  double smallest = std::numeric_limits<double>::infinity();
  double largest = 0.0;
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    if (ate_m[s].size() != modes.size()) {
      throw std::invalid_argument(fmt::format("AteBarChartSvg: sequence {} has {} values for {} modes", sequences[s],
                                              ate_m[s].size(), modes.size()));
    }
    for (std::size_t m = 0; m < modes.size(); ++m) {
      const double value = ate_m[s][m];
      series[m].values.push_back(value);
      if (std::isfinite(value) && value > 0.0) {
        smallest = std::min(smallest, value);
        largest = std::max(largest, value);
      }
    }
  }
  const bool log = largest > 20.0 * smallest;
  const int bars = static_cast<int>(sequences.size() * modes.size());
  const BarChartOptions options{.chart = {.title = "ATE RMSE per sequence and mode",
                                          .y_label = log ? "ATE RMSE (m, log scale)" : "ATE RMSE (m)",
                                          .width = std::clamp(160 + 18 * bars, 560, 1040),
                                          .height = 380,
                                          .log_y = log}};
  return BarChart(sequences, series, options);
}

std::string HtmlPage(std::string_view title, std::string_view body) {
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n"
      "<style>{}</style>\n</head>\n<body>\n<main>\n{}</main>\n</body>\n</html>\n",
      EscapeXml(title), kStyle, body);
}

std::string Base64Encode(std::string_view bytes) {
  constexpr std::string_view kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const auto group = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16 |
                       static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    for (const int shift : {18, 12, 6, 0}) out += kAlphabet[(group >> shift) & 0x3F];
  }
  // One or two bytes left: their sextets, then '=' for each missing byte.
  const std::size_t left = bytes.size() - i;
  if (left > 0) {
    std::uint32_t group = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
    if (left == 2) group |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    out += kAlphabet[(group >> 18) & 0x3F];
    out += kAlphabet[(group >> 12) & 0x3F];
    out += left == 2 ? kAlphabet[(group >> 6) & 0x3F] : '=';
    out += '=';
  }
  return out;
}

std::string TableHtml(const Table& table) {
  std::string html = "<table>";
  if (!table.title.empty()) html += fmt::format("<caption>{}</caption>", EscapeXml(table.title));
  html += "<thead><tr>";
  for (const std::string& cell : table.header) html += fmt::format("<th>{}</th>", EscapeXml(cell));
  html += "</tr></thead><tbody>\n";
  for (const auto& row : table.rows) {
    html += "<tr>";
    for (const std::string& cell : row) {
      html += fmt::format("<td{}>{}</td>", IsNumber(cell) ? " class=\"num\"" : "", EscapeXml(cell));
    }
    html += "</tr>\n";
  }
  html += "</tbody></table>\n";
  if (!table.note.empty()) html += fmt::format("<p class=\"table-note\">{}</p>\n", EscapeXml(table.note));
  return html;
}

}  // namespace hoidslam::report
