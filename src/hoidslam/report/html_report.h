#pragma once
// Reports as single HTML files that open anywhere, offline, and print: inline CSS, inline SVG charts
// (svg_plot.h), pictures as base64 data: URIs. Nothing is fetched from a network.
//
// The run report shows one folder written by `hoidslam run` (docs/slam.md, "Outputs"): its counts, the
// trajectory seen from above against ground truth, the ATE over time, the features per frame, the time per stage,
// how well the exclusion matched the moving pixels (or that the sequence has no ground-truth masks to score it
// against), the main map in 3D (the viewer's own page inlined, docs/viewer.md) and the annotated snapshots (when the
// run saved any). The bench report is a page of sections that `hoidslam bench` fills with tables and charts.

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/eval/evaluation.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/report/svg_plot.h"
#include "hoidslam/report/table.h"

namespace hoidslam::report {

// ---- What a run folder holds ---------------------------------------------------------------------------------

// A detection whose features were dropped, as frames.jsonl lists it.
struct DynamicDetection {
  std::string label;
  double score = 0.0;
  std::array<double, 4> box{};  // x, y, width, height (pixels)
  std::string reason;           // the filter's reason (docs/hoid.md): person, interaction, depth_confirmed, ...
  int person = -1;              // the person it interacts with (index into the frame's detections); -1: none
  std::optional<double> interaction;  // area(object ∩ person) / area(object) with that person
};

// Keypoints counted against the ground-truth moving-pixel mask.
struct ExclusionCounts {
  std::size_t moving_kept = 0;
  std::size_t moving_dropped = 0;
  std::size_t static_kept = 0;
  std::size_t static_dropped = 0;
};

// One line of frames.jsonl.
struct FrameRecord {
  std::size_t frame = 0;
  double timestamp = 0.0;
  std::string state;   // ok, lost, not_initialized
  std::string method;  // how the pose was first estimated: motion_model, reference_keyframe, ...
  bool keyframe = false;
  std::size_t extracted = 0;
  std::size_t dropped = 0;  // by the filter
  std::size_t kept = 0;     // handed to tracking (with the static keypoint budget, from the second extraction)
  std::size_t matched = 0;
  std::size_t inliers = 0;
  std::vector<DynamicDetection> dynamic;
  std::optional<ExclusionCounts> exclusion;  // when the run compared against the moving masks
  std::string detector_error;                // empty unless the detector failed on this frame
  std::optional<double> detection_age_ms;    // how much older than the frame its detections were
  std::size_t dropped_before = 0;            // a paced run's frames dropped just before this one
};

// summary.json's exclusion_quality: the run's keypoints against the ground-truth moving masks.
struct ExclusionQuality {
  double leaked = 0.0;  // fraction of the keypoints on moving pixels that were kept
  double wasted = 0.0;  // fraction of the keypoints on static pixels that were dropped
  ExclusionCounts counts;
};

struct StageTime {
  std::string stage;  // load, extract, detect, filter, track
  double median_ms = 0.0;
};

// An annotated frame the run saved as snapshots/<6-digit frame index>.jpg.
struct Snapshot {
  std::size_t frame = 0;
  std::filesystem::path path;
  std::string jpeg;  // the file's bytes
};

// The estimate against ground truth, associated and aligned exactly as `hoidslam eval` does.
struct GroundTruthComparison {
  eval::Evaluation evaluation;                    // ATE (per pair too) and RPE
  std::vector<Eigen::Vector3d> groundtruth;       // ground-truth positions over the run's time span
  std::vector<Eigen::Vector3d> aligned_estimate;  // every estimated position, in the ground truth's frame
};

// The main map as the run wrote it, for the 3D view.
struct RunMap {
  std::vector<io::ColoredPoint> points;  // map.ply, in file order (a point's id on the page is its place there)
  core::Trajectory keyframes;            // keyframes.txt: each keyframe's pose, camera to world
};

// The most triangles of a dense map the report shows: 16 base64 characters a triangle and 20 a vertex make
// 100,000 triangles (about 50,000 vertices) some 2.6 MB of page.
inline constexpr std::size_t kReportDenseTriangles = 100'000;

struct RunReport {
  std::filesystem::path folder;
  // From summary.json.
  std::string sequence;
  std::string filter;
  std::string detector;
  std::size_t frames = 0;
  std::size_t tracked = 0;
  std::size_t lost = 0;
  std::size_t before_initialization = 0;
  std::size_t keyframes = 0;
  std::size_t map_points = 0;
  std::size_t keypoints_extracted = 0;
  std::size_t keypoints_dropped = 0;
  bool interrupted = false;
  std::vector<StageTime> median_ms;           // the stages present, in pipeline order
  std::optional<double> median_tracking_ms;   // extraction + filter + tracking, the budgeted figure
  std::optional<ExclusionQuality> exclusion_quality;  // none when the sequence has no ground-truth moving masks
  core::CameraIntrinsics camera;  // the run's settings (provenance.settings.values), else the TUM fr3 defaults

  std::vector<FrameRecord> frame_log;  // frames.jsonl, in file order
  core::Trajectory estimate;           // trajectory.txt
  std::vector<Snapshot> snapshots;     // by frame; empty without snapshots/
  std::optional<RunMap> map;           // none when the folder has no map.ply or no keyframes.txt
  std::string no_map;                  // then: which file is missing
  // The dense map (mesh.ply) made small enough to show, at most kReportDenseTriangles; none without one. Not read by
  // LoadRunReport: making it small takes Open3D (dense::ReadMeshForDisplay), which this module does not link.
  std::optional<io::TriangleMesh> dense_mesh;
  std::optional<GroundTruthComparison> comparison;  // when ground truth was given and fits the estimate
  std::string not_compared;  // why there is no comparison although ground truth was given (too few matches)
};

// Reads a folder written by `hoidslam run` and, when `groundtruth` is not empty, compares its trajectory with that
// TUM file (default eval::EvaluationOptions, as `hoidslam run` evaluates). Throws InputError naming the file for
// a missing folder, summary.json, frames.jsonl or trajectory.txt, a malformed line, a snapshot that is not a
// JPEG, a map.ply or keyframes.txt that cannot be read, or an unreadable ground-truth file; ground truth that does
// not overlap the estimate is not an error but a note in the report (not_compared).
RunReport LoadRunReport(const std::filesystem::path& run_folder, const std::filesystem::path& groundtruth);

// The ground-truth file summary.json says the run was evaluated against (`evaluation.groundtruth.path`, as the
// run wrote it, possibly relative to where it ran); empty when the run was not evaluated. Throws InputError when
// summary.json is missing or malformed.
std::filesystem::path RecordedGroundTruth(const std::filesystem::path& run_folder);

// RecordedGroundTruth when that file is still there; else empty, with a warning that the run's ground truth is gone
// and that `option` gives one (the run recorded the path as it was given, possibly relative to another folder).
std::filesystem::path RecordedGroundTruthIfPresent(const std::filesystem::path& run_folder, std::string_view option);

// The viewer's page as one script and one stylesheet, for a report to inline (docs/viewer.md, "The same page in a
// report").
struct ViewerBundle {
  std::string script;   // viewer.js
  std::string style;    // viewer.css
  std::string missing;  // why there is no page to inline, when there is none (script and style are then empty)
};

// viewer.js and viewer.css of `web_dir` (core::WebDir(): the build's or the installed page). Never throws: files
// that are not there, or that would end their inline element early (`</script`, `</style`), give `missing`.
ViewerBundle LoadViewerBundle(const std::filesystem::path& web_dir);

// The whole page; the Map section inlines `viewer` with the run's map, or says why it cannot.
std::string RenderRunHtml(const RunReport& report, const ViewerBundle& viewer);

// LoadRunReport, RenderRunHtml with the page of core::WebDir(), and the page written to `out_html` complete or not
// at all. `shown_folder`: the folder the page names, when it is read from a staging folder that will be renamed to
// it (empty: `run_folder`); `dense_mesh`: the run's dense map made small (RunReport::dense_mesh).
void WriteRunReport(const std::filesystem::path& run_folder, const std::filesystem::path& groundtruth,
                    const std::filesystem::path& out_html, const std::filesystem::path& shown_folder = {},
                    std::optional<io::TriangleMesh> dense_mesh = std::nullopt);

// ---- Building blocks of the bench report ---------------------------------------------------------------------

struct BenchReportSection {
  std::string heading;
  std::string text;  // plain text; blank lines separate paragraphs
  std::vector<Table> tables;
  std::vector<std::string> svg_figures;  // SVG elements, e.g. from the functions below or svg_plot.h
  std::string html;                      // markup after the figures, e.g. from SnapshotGallery
};

// A page with `title`, the intro lines as a list, then each section: heading, text, tables, figures.
std::string RenderBenchHtml(const std::string& title, const std::vector<std::string>& intro_lines,
                            const std::vector<BenchReportSection>& sections);

// The aligned trajectories of several runs of one sequence over its ground truth, seen from above. Each run is
// named in the legend by `labels[i]`, or by its filter mode when `labels` is empty; a run without a comparison
// (not evaluated, or nothing tracked) appears in the legend only. Throws std::invalid_argument when the runs were
// compared against different ground-truth files or `labels` has the wrong length.
std::string TrajectoryOverlaySvg(std::span<const RunReport> runs, std::span<const std::string> labels = {});

// The position error over time of several runs of one sequence, one line each (named as in TrajectoryOverlaySvg);
// runs without a comparison are left out.
std::string AteOverTimeSvg(std::span<const RunReport> runs, std::span<const std::string> labels = {});

// `count` of the run's annotated snapshots, spread evenly over those it saved, with their captions; empty when
// it saved none.
std::string SnapshotGallery(const RunReport& report, std::size_t count);

// ATE RMSE per sequence (groups) and mode (bars): ate_m[s][m] in metres, NaN for a missing or failed run (drawn as
// a ×). The value axis is logarithmic when the values span more than a factor of 20, as they do when an
// unfiltered run fails by decimetres beside filtered ones at millimetres.
std::string AteBarChartSvg(const std::vector<std::string>& sequences, const std::vector<std::string>& modes,
                           const std::vector<std::vector<double>>& ate_m);

// ---- Pieces -------------------------------------------------------------------------------------------------

// A whole page that opens offline: `title` in the tab, the reports' shared style, `body` (markup) in <main>.
std::string HtmlPage(std::string_view title, std::string_view body);

// RFC 4648 base64 with padding.
std::string Base64Encode(std::string_view bytes);

// A report::Table as an HTML table (title as caption, note under it); cells that are numbers align right.
std::string TableHtml(const Table& table);

}  // namespace hoidslam::report
