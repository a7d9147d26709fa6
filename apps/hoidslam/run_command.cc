// `hoidslam run`: RGB-D SLAM over a sequence with the features of people and of the objects they handle
// dropped before tracking. Writes the trajectory, the keyframes, the sparse map and a per-frame log, and, when
// the sequence has ground truth, prints its ATE and RPE (docs/slam.md).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "command_line.h"
#include "commands.h"
#include "detector_options.h"
#include "sequence_options.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/interrupt.h"
#include "hoidslam/core/shipped_dir.h"
#include "hoidslam/dense/dense_mapper.h"
#include "hoidslam/dense/display_mesh.h"
#include "hoidslam/dense/occupancy.h"
#include "hoidslam/eval/dense_score.h"
#include "hoidslam/eval/evaluation.h"
#include "hoidslam/eval/loop_recall.h"
#include "hoidslam/eval/pose_check.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/pipeline/depth_units.h"
#include "hoidslam/pipeline/playback.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/pipeline/summary_json.h"
#include "hoidslam/report/html_report.h"
#include "hoidslam/slam/system.h"
#include "hoidslam/version.h"
#include "hoidslam/viewer/viewer.h"

namespace hoidslam::apps {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
  SequenceArgs sequence;
  std::string settings;
  std::vector<double> camera;  // --camera fx,fy,cx,cy[,k1,k2,p1,p2,k3]
  DetectorArgs detector;
  std::string filter;      // overrides HOID.mode
  std::optional<double> min_interaction_area;  // overrides HOID.minInteractionArea
  std::optional<double> depth_threshold;       // overrides HOID.depthThreshold
  std::string keypoint_budget{pipeline::ToString(pipeline::RunOptions{}.keypoint_budget)};
  std::string vocabulary = slam::ShippedVocabulary().string();
  std::size_t snapshots = pipeline::RunOptions{}.snapshots;
  std::string out;
  std::size_t frames = 0;
  bool deterministic = false;
  bool no_loop_closing = false;
  bool no_final_adjustment = false;
  double new_map_after = slam::TrackerOptions{}.new_map_after;
  bool no_map_merging = false;
  std::string save_map;
  std::string load_map;
  bool localization = false;
  bool realtime = false;
  bool pace = false;
  std::size_t preload_megabytes = pipeline::RealTimeOptions{}.preload_megabytes;
  double detector_latency_ms = 0.0;
  bool force = false;
  bool view = false;
  viewer::ViewerOptions view_options;
  bool view_keep = false;
  bool dense = false;
  dense::DenseOptions dense_options;
  std::string occupancy_band;
};

// --camera fx,fy,cx,cy[,k1,k2,p1,p2,k3] in place of the settings' camera, at the size of the sequence's images; the
// settings' baseline is kept (Camera.bf follows fx).
void SetCamera(const std::vector<double>& values, const cv::Size& image, io::Settings& settings) {
  if (values.size() != 4 && values.size() != 9) {
    throw core::InputError::ForParameter(
        "--camera", fmt::format("takes fx,fy,cx,cy or fx,fy,cx,cy,k1,k2,p1,p2,k3, got {} values", values.size()));
  }
  const double baseline = settings.bf / settings.camera.fx;
  core::CameraIntrinsics& camera = settings.camera;
  camera = {values[0], values[1], values[2], values[3]};
  if (values.size() == 9) {
    camera.k1 = values[4];
    camera.k2 = values[5];
    camera.p1 = values[6];
    camera.p2 = values[7];
    camera.k3 = values[8];
  }
  camera.width = image.width;
  camera.height = image.height;
  settings.bf = baseline * camera.fx;
  try {
    settings.Check();
  } catch (const core::InputError& e) {
    throw core::InputError::ForParameter("--camera", e.what());
  }
}

// The dense map against a synthetic sequence's exact geometry (eval/dense_score.h), in the ground truth's frame by
// the keyframes' poses: the scores, or nullopt when the sequence carries no geometry.
std::optional<eval::DenseScore> ScoreDenseMap(const io::RgbdSequence& sequence, const fs::path& run,
                                              const eval::Evaluation& evaluation, const core::CameraIntrinsics& camera,
                                              const eval::DenseScoreOptions& options) {
  if (!eval::DenseTruth::Exists(sequence.root())) return std::nullopt;
  const eval::DenseTruth truth = eval::DenseTruth::Load(sequence, camera, options.view_step);
  const dense::OccupiedCells cells = dense::ReadOccupiedCells(run / "occupancy.bt");
  const eval::Alignment alignment =
      eval::DenseScoreAlignment(sequence.groundtruth(), io::ReadTumTrajectory(run / "keyframes.txt"),
                                evaluation.options.ate.association, options);
  return eval::ScoreDenseMap(io::ReadPlyMesh(run / "mesh.ply"), &cells.centres, cells.resolution, alignment, truth,
                             options);
}

void RunRun(const RunArgs& args) {
  // One rule with bench and the API: --settings, else the shipped file the folder's name calls for, else defaults.
  const io::SettingsChoice choice =
      io::ChooseSettings(args.settings, SequenceFolder(args.sequence), core::ShippedDir() / "config");
  io::Settings settings = choice.settings;
  // --depth-factor may correct settings the run chose itself; a file given with it would be contradicted.
  const bool settings_given = choice.reason == io::SettingsChoice::Reason::kGiven;
  if (args.sequence.depth_factor && !settings_given) settings.depth_map_factor = *args.sequence.depth_factor;
  if (args.min_interaction_area) settings.hoid.min_interaction_area = *args.min_interaction_area;
  if (args.depth_threshold) settings.hoid.depth_threshold = *args.depth_threshold;

  const io::RgbdSequence sequence =
      OpenSequence(args.sequence, settings_given ? std::optional(settings.depth_map_factor) : std::nullopt,
                   settings.depth_map_factor);
  const core::RgbdFrame first = sequence.LoadFrame(0);
  if (!args.camera.empty()) SetCamera(args.camera, first.rgb.size(), settings);

  pipeline::RunOptions options = pipeline::RunOptions::FromSettings(settings);
  options.settings_source = choice.Describe();
  if (!args.filter.empty()) pipeline::SetFilterMode(args.filter, options.exclusion, "--filter");
  options.keypoint_budget = pipeline::ParseKeypointBudget(args.keypoint_budget, "--keypoint-budget");
  options.snapshots = args.snapshots;
  options.system.deterministic = args.deterministic;
  options.system.vocabulary = args.vocabulary;
  options.system.loop_closing.enabled = !args.no_loop_closing;
  options.system.final_adjustment.enabled = !args.no_final_adjustment;
  options.system.tracking.new_map_after = args.new_map_after;
  options.system.loop_closing.merge_maps = !args.no_map_merging;
  options.system.load_map = args.load_map;
  options.system.localization = args.localization;
  options.save_map = args.save_map;
  options.realtime.enabled = args.realtime;
  options.realtime.pace = args.pace;
  options.realtime.preload_megabytes = args.preload_megabytes;
  options.realtime.detector_latency_ms = args.detector_latency_ms;
  options.max_frames = args.frames;
  options.Check();
  // The map is written at the end of the run: a file that cannot be written is said now, not after the tracking.
  if (!options.save_map.empty()) io::CheckWritableFile(options.save_map, "--save-map");

  const std::unique_ptr<detect::Detector> detector =
      OpenDetector(args.detector, args.sequence, options.exclusion, sequence, args.dense);
  // The wrong camera's settings and depth in the wrong unit, said before the run (tracking checks the depth of the
  // first frame that has enough of it).
  pipeline::CheckImageSize(first, options);
  if (const std::optional<pipeline::DepthSpread> spread = pipeline::MeasureDepth(first.depth);
      spread && options.check_depth_units) {
    if (const std::string problem = pipeline::DepthUnitsProblem(*spread, options.depth_factor); !problem.empty()) {
      throw core::InputError::InFile(first.depth_path, problem);
    }
  }

  // Declared before the dense mapper, whose live preview shows its meshes on the viewer: the mapper (and the
  // preview's thread) ends first, then the viewer, then the playback it controls.
  pipeline::Playback playback;
  std::unique_ptr<viewer::Viewer> view;
  // The dense map's options are checked before the run: a volume too big for memory is said now.
  std::unique_ptr<dense::DenseMapper> dense_mapper;
  if (args.dense) {
    dense::DenseOptions dense_options = args.dense_options;
    if (!args.occupancy_band.empty()) dense::SetOccupancyBand(args.occupancy_band, dense_options.occupancy);
    dense_mapper = std::make_unique<dense::DenseMapper>(dense_options, options.system.camera);
  }

  // The viewer listens before the run starts: a port that is taken is said before any tracking.
  if (args.view) {
    const viewer::ViewerHello hello{sequence.name(), pipeline::FramesToPlay(options.max_frames, sequence.size()),
                                    options.system.camera};
    view = std::make_unique<viewer::Viewer>(args.view_options, hello, options.realtime.pace ? nullptr : &playback);
    spdlog::info("viewer: {}", view->url());
  }
  if (view && dense_mapper) {
    // The dense map grows on the page while the run goes: coarse, at the poses tracking gives, until the final map
    // built from the final poses replaces it.
    dense_mapper->FollowPreview({}, [viewer = view.get()](io::TriangleMesh mesh) { viewer->ShowDenseMap(mesh); });
  }

  io::AtomicFolder out(args.out, args.force, "--out", "use --force to replace it");
  for (const fs::path& stale : out.stale_removed()) {
    spdlog::info("removed {}: the unfinished output of an earlier run into the same folder that was killed", stale.string());
  }
  core::InterruptGuard interrupts;
  pipeline::RunHooks hooks{.stop_requested = [&interrupts] { return interrupts.requested(); }};
  const pipeline::Session* session = nullptr;
  core::Trajectory final_keyframes;  // the dense map is fused at the keyframes' final poses, once the run is done
  if (view) hooks.playback = &playback;
  if (view || dense_mapper) {
    hooks.started = [&](const pipeline::Session& started) {
      session = &started;
      if (view) view->FollowSession(started);
    };
    hooks.frame_tracked = [&](std::size_t index, const core::RgbdFrame& frame, const pipeline::FrameOutcome& outcome) {
      if (view) view->Publish(viewer::SnapshotOf(index, frame, outcome));
      if (dense_mapper) dense_mapper->TakeKeyFrame(*session, frame, outcome, detector.get());
    };
    hooks.finished = [&](const pipeline::Session& finished) {
      if (view) view->FinalMapOf(finished);
      if (dense_mapper) final_keyframes = finished.system().KeyFrameTrajectory();
    };
  }
  const pipeline::RunSummary summary = pipeline::RunSequence(sequence, *detector, options, out.temporary(), hooks);
  std::optional<dense::DenseSummary> dense_summary;
  if (dense_mapper) dense_summary = dense_mapper->Build(final_keyframes, out.temporary());
  // The dense map as the report and the viewer show it: mesh.ply made small enough for a browser.
  std::optional<io::TriangleMesh> dense_display;
  if (dense_summary && dense_summary->written) {
    dense_display = dense::ReadMeshForDisplay(out.temporary() / "mesh.ply", report::kReportDenseTriangles);
    if (view && dense_display) view->ShowDenseMap(*dense_display);
  }

  nlohmann::json json = pipeline::RunSummaryJson(summary, sequence.name(), options.exclusion.ModeName(),
                                                 detector->Name(), options.realtime);
  json["provenance"] = pipeline::ProvenanceJson({.command_line = CommandLineJson(),
                                                 .version = HOIDSLAM_VERSION,
                                                 .settings_file = choice.file,
                                                 .settings_chosen = std::string(io::ToString(choice.reason)),
                                                 .settings = settings,
                                                 .vocabulary = args.vocabulary,
                                                 .vocabulary_identity = summary.vocabulary_identity,
                                                 .detector_source = detector->Source()});
  if (dense_summary) json["dense"] = dense::DenseSummaryJson(*dense_summary, dense_mapper->options());
  std::optional<eval::Evaluation> evaluation;
  std::optional<eval::PoseCheck> relocalizations, loops, merges;
  std::optional<eval::LoopRecall> loop_recall;
  std::vector<std::pair<slam::MapId, eval::Evaluation>> other_maps;
  eval::DenseScoreOptions dense_score_options;
  std::optional<eval::DenseScore> dense_score;
  const eval::PoseCheckOptions relocalization_limits;
  const eval::LoopRecallOptions loop_recall_options{.closure = relocalization_limits};
  const fs::path groundtruth = sequence.root() / "groundtruth.txt";
  if (!sequence.groundtruth().empty()) {
    try {
      evaluation = eval::EvaluateTrajectoryFiles(groundtruth, out.temporary() / "trajectory.txt", {});
      evaluation->estimate_path = out.path() / "trajectory.txt";  // where it will be once the folder is complete
      json["evaluation"] = eval::EvaluationToJson(*evaluation);
      // Each pose relocalisation found, judged against the ground truth: a wrong one is worse than a lost frame.
      relocalizations = eval::CheckPoses(sequence.groundtruth(),
                                         io::ReadTumTrajectory(out.temporary() / "trajectory.txt"),
                                         evaluation->ate.alignment, summary.relocalized,
                                         evaluation->options.ate.association, relocalization_limits);
      json["evaluation"]["relocalizations"] = eval::PoseCheckToJson(*relocalizations, relocalization_limits);
      // Each loop closed, by the relative pose its verification found between its two ends: a false loop bends
      // the whole map. A merge the same way: its two ends are in different maps, but their relative pose is
      // measured all the same.
      const auto relative = [](const std::vector<slam::LoopClosure>& closures) {
        std::vector<eval::RelativePose> poses;
        for (const slam::LoopClosure& c : closures) poses.push_back({c.timestamp, c.loop_timestamp, c.T_loop_current});
        return poses;
      };
      const auto check = [&](const std::vector<slam::LoopClosure>& closures) {
        return eval::CheckRelativePoses(sequence.groundtruth(), relative(closures),
                                        evaluation->options.ate.association, relocalization_limits);
      };
      loops = check(summary.loops);
      json["evaluation"]["loops"] = eval::PoseCheckToJson(*loops, relocalization_limits);
      merges = check(summary.merges);
      json["evaluation"]["merges"] = eval::PoseCheckToJson(*merges, relocalization_limits);
      // Every return to a mapped place, and whether the map was joined there: the loops that should have been
      // closed, beside those that were (docs/evaluation.md).
      std::vector<eval::RelativePose> closures = relative(summary.loops);
      for (const eval::RelativePose& merge : relative(summary.merges)) closures.push_back(merge);
      loop_recall = eval::ComputeLoopRecall(sequence.groundtruth(),
                                            io::ReadTumTrajectory(out.temporary() / "keyframes.txt"), closures,
                                            evaluation->options.ate.association, loop_recall_options);
      json["evaluation"]["loop_recall"] = eval::LoopRecallToJson(*loop_recall, loop_recall_options);
      if (dense_summary && dense_summary->written) {
        dense_score_options.min_depth = dense_mapper->options().min_depth;
        dense_score_options.max_depth = dense_mapper->options().max_depth;
        dense_score = ScoreDenseMap(sequence, out.temporary(), *evaluation, options.system.camera, dense_score_options);
        if (dense_score) json["evaluation"]["dense"] = eval::DenseScoreJson(*dense_score, dense_score_options);
      }
      // Each other map on its own: its frames aligned to the ground truth by themselves.
      json["evaluation"]["other_maps"] = nlohmann::json::array();
      for (const slam::MapSummary& map : summary.maps) {
        if (map.id == summary.main_map) continue;
        const fs::path file = out.temporary() / pipeline::OtherMapTrajectoryName(map.id);
        try {
          eval::Evaluation other = eval::EvaluateTrajectoryFiles(groundtruth, file, {});
          other.estimate_path = out.path() / file.filename();
          nlohmann::json entry = eval::EvaluationToJson(other);
          entry["map"] = map.id;
          json["evaluation"]["other_maps"].push_back(std::move(entry));
          other_maps.emplace_back(map.id, std::move(other));
        } catch (const core::InputError& e) {
          spdlog::warn("map {} not evaluated: {}", map.id, e.what());  // too few frames to align
        }
      }
    } catch (const core::InputError& e) {
      spdlog::warn("not evaluated: {}", e.what());
    }
  }
  {
    io::AtomicFile file(out.temporary() / "summary.json");
    file.stream() << json.dump(2) << '\n';
    file.Commit();
  }
  std::vector<std::string> written = {"trajectory.txt", "keyframes.txt", "map.ply", "frames.jsonl", "summary.json"};
  for (const slam::MapSummary& map : summary.maps) {
    if (map.id != summary.main_map) written.push_back(pipeline::OtherMapTrajectoryName(map.id));
  }
  if (dense_summary && dense_summary->written) {
    for (const char* file : dense::kDenseOutputs) written.push_back(file);
  }
  if (fs::is_directory(out.temporary() / "snapshots")) written.push_back("snapshots/");
  try {
    report::WriteRunReport(out.temporary(), evaluation ? groundtruth : fs::path(), out.temporary() / "report.html",
                           out.path(), std::move(dense_display));
    written.push_back("report.html");
  } catch (const core::InputError& e) {
    spdlog::warn("no report.html: {}", e.what());  // the run's own outputs are complete; only the page is missing
  }
  out.Commit();

  fmt::print("{}: {} frames, {} tracked, {} lost, {} before initialisation; {} keyframes, {} map points\n",
             sequence.name(), summary.frames, summary.tracked, summary.lost, summary.before_initialization,
             summary.keyframes, summary.map_points);
  if (summary.withdrawn > 0) {
    fmt::print("{} of the lost frames were tracked after a loss, then withdrawn: the frames after them refuted the "
               "pose found\n",
               summary.withdrawn);
  }
  if (options.realtime.pace) {
    fmt::print("paced at the recorded rate: {} frames dropped, arriving while the system was busy ({:.1f} %)\n",
               summary.dropped, 100.0 * summary.dropped / std::max<std::size_t>(1, summary.frames + summary.dropped));
  }
  if (const nlohmann::json detections = json["detections"]; !detections.is_null()) {
    fmt::print("detections: median age {:.0f} frames ({:.1f} ms), detector {:.1f} ms a frame; {} late boxes carried "
               "by their keypoints, {} grown\n",
               detections["median_age_frames"].get<double>(), detections["median_age_ms"].get<double>(),
               detections["median_detector_ms"].get<double>(), summary.boxes_carried_by_keypoints, summary.boxes_grown);
  }
  fmt::print("{:.1f} frames per second ({} frames in {:.1f} s)\n", json["frames_per_second"].get<double>(),
             summary.frames, summary.seconds);
  fmt::print("keypoints: {} extracted, {} dropped by the filter ({:.1f} %), {} tracked ({:.0f} a frame)\n",
             summary.keypoints_extracted, summary.keypoints_dropped,
             summary.keypoints_extracted == 0 ? 0.0 : 100.0 * summary.keypoints_dropped / summary.keypoints_extracted,
             summary.keypoints_tracked,
             summary.frames == 0 ? 0.0 : static_cast<double>(summary.keypoints_tracked) / summary.frames);
  if (options.exclusion.SafetyNet()) {
    fmt::print("safety net: {} map points erased as moving\n", summary.moving_points);
  }
  if (summary.exclusion) {
    fmt::print("against the moving masks: {:.1f} % of the keypoints on moving things kept (leaked), {:.1f} % of the "
               "static ones dropped (wasted)\n",
               100.0 * summary.exclusion->Leaked(), 100.0 * summary.exclusion->Wasted());
  }
  const nlohmann::json& ms = json["median_ms"];
  fmt::print("median ms per frame: load {:.2f}, extract {:.2f}, detect {:.2f}, filter {:.3f}, track {:.2f}; "
             "tracking (extract + filter + track) {:.2f}\n",
             ms["load"].get<double>(), ms["extract"].get<double>(), ms["detect"].get<double>(),
             ms["filter"].get<double>(), ms["track"].get<double>(), ms["tracking_total"].get<double>());
  if (dense_summary) fmt::print("{}\n", dense::FormatDenseSummary(*dense_summary, dense_mapper->options()));
  if (evaluation) fmt::print("{}", eval::FormatEvaluation(*evaluation));
  if (dense_score) {
    fmt::print("dense map against the true static geometry: accuracy median {:.1f} mm (90 % within {:.1f} mm), "
               "completeness {:.1f} % (within {:g} cm), ghosts {:.3f} m² ({:.2f} % of the surface farther than {:g} cm "
               "from it), occupancy {} ghost cells of {} occupied\n",
               1000.0 * dense_score->accuracy_median, 1000.0 * dense_score->accuracy_p90,
               100.0 * dense_score->completeness, 100.0 * dense_score_options.completeness_distance,
               dense_score->ghost_area, 100.0 * dense_score->GhostShare(), 100.0 * dense_score_options.ghost_distance,
               dense_score->ghost_cells.value_or(0), dense_score->occupied_cells.value_or(0));
  }
  if (relocalizations && !relocalizations->poses.empty()) {
    fmt::print("relocalisations: {}, {} of them false (more than {:g} m or {:g}° from the ground truth)\n",
               relocalizations->poses.size(), relocalizations->Wrong(), relocalization_limits.max_position_error,
               relocalization_limits.max_rotation_error_deg);
  }
  // "loops closed: 1, 0 of them false (...)": the count, and how many the ground truth says are wrong.
  const auto print_closures = [&](std::string_view what, std::size_t count,
                                  const std::optional<eval::PoseCheck>& check) {
    if (count == 0) return;
    fmt::print("{}: {}", what, count);
    if (check) {
      fmt::print(", {} of them false (their two ends more than {:g} m or {:g}° from the true relative pose)",
                 check->Wrong(), relocalization_limits.max_position_error,
                 relocalization_limits.max_rotation_error_deg);
    }
    fmt::print("\n");
  };
  print_closures("loops closed", summary.loops.size(), loops);
  print_closures("maps merged", summary.merges.size(), merges);
  if (loop_recall) {
    // "loop recall: 5 of 6 returns (4 closed, 1 already consistent); precision 3 of 3 loops": never 100 % of nothing.
    if (loop_recall->events.empty()) {
      fmt::print("loop recall: undefined, no return to an earlier place");
    } else {
      fmt::print("loop recall: {} of {} returns ({} closed, {} already consistent)", loop_recall->Recalled(),
                 loop_recall->events.size(), loop_recall->Closed(), loop_recall->Consistent());
    }
    const std::string_view closed = summary.merges.empty() ? "loops" : "loops and merges";
    if (loop_recall->closures == 0) {
      fmt::print("; precision undefined, no {} to judge\n", closed);
    } else {
      fmt::print("; precision {} of {} {}\n", loop_recall->confirmed, loop_recall->closures, closed);
    }
  }
  for (const slam::MapSummary& map : summary.maps) {
    if (map.id == summary.main_map) continue;
    fmt::print("map {}: {} frames tracked in a map of its own, never merged ({})", map.id, map.frames,
               pipeline::OtherMapTrajectoryName(map.id));
    const auto other =
        std::find_if(other_maps.begin(), other_maps.end(), [&](const auto& m) { return m.first == map.id; });
    if (other != other_maps.end()) fmt::print(", ATE RMSE {:.4f} m on its own", other->second.ate.error.rmse);
    fmt::print("\n");
  }
  fmt::print("wrote {}/ ({})\n", out.path().string(), fmt::join(written, ", "));
  if (summary.interrupted) {
    spdlog::warn("interrupted after {} of {} frames; the outputs hold the frames done", summary.frames, sequence.size());
    std::fflush(stdout);  // the signal raised again ends the process without flushing the summary printed above
    interrupts.Reraise();
  }
  if (view) {
    view->RunFinished();
    if (args.view_keep) {
      spdlog::info("viewer: {} shows the final map until Ctrl-C", view->url());
      std::fflush(stdout);
      while (!interrupts.requested()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
}

}  // namespace

void AddRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* command = app.add_subcommand(
      "run",
      "RGB-D SLAM over a TUM / Bonn / synthetic sequence with the features of people and of the objects they handle "
      "dropped before tracking; writes the trajectory, keyframes, map and a per-frame log, and evaluates against "
      "groundtruth.txt when the sequence has one");
  AddSequenceOptions(*command, args->sequence);
  command->add_option("--settings", args->settings,
                      "Settings file (ORB-SLAM3 format with a HOID section, e.g. config/TUM3.yaml; default: the shipped "
                      "file a TUM or Bonn folder's name calls for, freiburg1 → TUM1.yaml, else the TUM fr3 camera)");
  command->add_option("--camera", args->camera,
                      "The camera's intrinsics, fx,fy,cx,cy[,k1,k2,p1,p2,k3] (pixels; OpenCV's distortion order), "
                      "in place of the settings' camera; the image size is the sequence's, the depth units "
                      "--depth-factor's")
      ->delimiter(',');
  AddDetectorOptions(*command, args->detector);
  command->add_option("--filter", args->filter,
                      "What is dropped: none, person, classes, hoid2d, hoid3d, hoidplus (HOID with depth, memory and a "
                      "safety net; hoidplus:depth+memory etc. for some parts), or oracle (the ground-truth moving "
                      "masks of a synthetic sequence); default: HOID.mode of the settings, else hoidplus");
  command->add_option("--min-interaction-area", args->min_interaction_area,
                      "Overrides HOID.minInteractionArea: the share of an object's box a person's box must cover "
                      "for the object to count as handled (0..1]")
      ->check(CLI::PositiveNumber & CLI::Range(0.0, 1.0));
  command->add_option("--depth-threshold", args->depth_threshold,
                      "Overrides HOID.depthThreshold: the largest depth difference (m) between a handled object and "
                      "its person in hoid3d")
      ->check(CLI::PositiveNumber);
  command->add_option("--keypoint-budget", args->keypoint_budget,
                      "Where a frame's ORBextractor.nFeatures keypoints go: static (to what the filter keeps: the frame "
                      "is extracted again outside what it drops, so a frame full of people still gets the whole "
                      "budget on the static world) or image (over the whole image, as ORB-SLAM does)")
      ->capture_default_str();
  command->add_option("--vocabulary", args->vocabulary,
                      "Bag-of-words vocabulary place recognition describes keyframes and lost frames with "
                      "(hoidslam vocabulary trains one; docs/vocabulary.md)")
      ->capture_default_str();
  command->add_option("--snapshots", args->snapshots,
                      "Annotated frames written to <out>/snapshots/, spread evenly over the run")
      ->capture_default_str();
  command->add_option("--out", args->out, "Output folder (created complete or not at all)")->required();
  command->add_option("--frames", args->frames, "Run only the first N frames (0 = all)")->capture_default_str();
  command->add_flag("--no-loop-closing", args->no_loop_closing,
                    "Do not close loops: the map keeps the drift of the path back to a place it has seen");
  command->add_flag("--no-final-adjustment", args->no_final_adjustment,
                    "Do not adjust the map once more at the end, with each depth weighed by the sensor's noise model "
                    "(Depth.noiseFactor): the outputs and the saved map show it as tracking left it");
  command->add_option("--new-map-after", args->new_map_after,
                      "Seconds lost before the camera is taken to be in new ground and a new map is started (the "
                      "frames are still looked for in every map; the new map is merged once it sees a place of "
                      "another). 0: never, stay lost until relocalised")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command->add_flag("--no-map-merging", args->no_map_merging,
                    "Do not merge maps: the frames of a map started in new ground stay in its own world frame "
                    "(trajectory-map<id>.txt)");
  command->add_option("--save-map", args->save_map,
                      "Write the final map (keyframes, points, covisibility, camera and vocabulary) to this map file "
                      "(docs/slam.md, \"Map reuse\")");
  command->add_option("--load-map", args->load_map,
                      "Start from the map in this map file: the first frame is relocalised in it, and new keyframes "
                      "continue it. It must have been made with the same camera and vocabulary");
  command->add_flag("--localization", args->localization,
                    "With --load-map: track against the loaded map without changing it (no new keyframes, no local "
                    "mapping, no loop closing)");
  command->add_flag("--deterministic", args->deterministic,
                    "Local mapping in step with tracking: identical output on every run (slower)");
  command->add_flag("--realtime", args->realtime,
                    "The detector in its own thread: tracking never waits for it (but for the first frame) and each "
                    "frame uses the newest detections, carried to it by the motion of their keypoints "
                    "(docs/realtime.md)");
  command->add_flag("--pace", args->pace,
                    "Play the sequence at its recorded rate, as a live camera: frames arriving while the system is "
                    "busy are dropped and counted. The frames are decoded ahead, as a camera delivers them "
                    "decoded");
  command->add_option("--preload-mb", args->preload_megabytes,
                      "With --pace: memory for the frames decoded ahead; when a sequence needs more, the clock stops "
                      "while the next part is decoded")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 20))
      ->capture_default_str();
  command->add_option("--detector-latency", args->detector_latency_ms,
                      "Every detection takes at least this many ms: a simulated network latency when replaying a "
                      "detections file")
      ->check(CLI::Range(0.0, 60000.0))
      ->capture_default_str();
  command->add_flag("--force", args->force, "Replace the --out folder when it exists and is not empty");
  CLI::Option* view = command->add_flag("--view", args->view,
                    "Show the run live in a browser: the map, the current frame with the keypoints kept and dropped, "
                    "the detector's boxes and the HOID verdicts, and pause / step / speed (docs/viewer.md)");
  command->add_option("--view-port", args->view_options.port, "With --view: the port the page is served on (0: any free one)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str()
      ->needs(view);
  command->add_option("--view-address", args->view_options.address,
                      "With --view: the address to listen on; 0.0.0.0 shows the page to other machines too (anyone who "
                      "reaches this one can then see the camera's images and pause the run)")
      ->capture_default_str()
      ->needs(view);
  command->add_flag("--view-keep", args->view_keep,
                    "With --view: once the outputs are written, keep showing the final map until Ctrl-C (exit 0)")
      ->needs(view);
  CLI::Option* dense = command->add_flag(
      "--dense", args->dense,
      "Also map the static world densely, people and what they carry left out: mesh.ply (coloured triangles), "
      "cloud.ply, occupancy.bt (OctoMap) and occupancy.pgm + .yaml (a 2D grid as ROS map_server reads it), fused from "
      "the keyframes at their final poses (docs/dense.md)");
  command->add_option("--dense-voxel", args->dense_options.voxel_size, "With --dense: the volume's voxel edge, m")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--dense-truncation", args->dense_options.truncation,
                      "With --dense: how far in front of and behind a surface a depth measurement counts, m (at least "
                      "two voxels)")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--dense-min-depth", args->dense_options.min_depth,
                      "With --dense: depth nearer than this is not fused, m")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--dense-max-depth", args->dense_options.max_depth,
                      "With --dense: depth farther than this is not fused, m (the sensor's noise grows with the square "
                      "of the depth)")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--dense-mask-margin", args->dense_options.mask_margin,
                      "With --dense: pixels the regions the filter drops grow by before fusion")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--dense-depth-extent", args->dense_options.depth_extent,
                      "With --dense: how far behind the foreground of a box hoidplus dropped the dense map still "
                      "leaves out, m (never less than the filter's own HOIDplus.depthExtent)")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--dense-box-margin", args->dense_options.box_margin,
                      "With --dense: share of the width and height of a box hoidplus dropped that the dense map "
                      "also leaves out beyond each side, there as far behind the foreground as the filter's own cut "
                      "(never less than the filter's HOIDplus.boxMargin)")
      ->capture_default_str()
      ->needs(dense);
  command->add_flag("--dense-keep-seen-through", args->dense_options.keep_seen_through,
                    "With --dense: keep surface that later keyframes looked through (by default the mesh and the "
                    "cloud leave out what lies in cells the occupancy map calls free: a person the filter missed in "
                    "a few keyframes, a chair moved away)")
      ->needs(dense);
  command->add_option("--dense-memory-mb", args->dense_options.memory_limit_mb,
                      "With --dense: memory the volume may take, MiB; a voxel size that would need more for a room is "
                      "refused before the run (0: half of this machine's memory)")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--occupancy-resolution", args->dense_options.occupancy.resolution,
                      "With --dense: the occupancy maps' cell size, m")
      ->capture_default_str()
      ->needs(dense);
  command->add_option("--occupancy-band", args->occupancy_band,
                      "With --dense: LOW:HIGH, the heights above the floor (m) whose occupied cells are obstacles in "
                      "the 2D grid (default 0.1:1.8)")
      ->needs(dense);
  command->callback([args] { RunRun(*args); });
}

}  // namespace hoidslam::apps
