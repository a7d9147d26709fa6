#pragma once
// Loop closing: when the camera comes back to a place the map already holds, the drift gathered in between is
// found and removed. Each keyframe local mapping has finished is looked up in the place-recognition database
// among the keyframes it is not connected to; a place recognised by three keyframes in a row is verified
// geometrically (the keyframe's points with depth against the place's map points: an SE(3), since depth fixes the
// scale), the two ends of the loop are joined (poses and points of the keyframe's neighbourhood moved, duplicate
// points fused), and the essential graph spreads the correction over the keyframes in between.
//
// The same recognition merges maps (the Atlas, map.h): a keyframe that recognises a place of another map, verified
// the same way (without the drift limit: two maps' world frames are unrelated), carries its whole map into the
// other's world frame, and the two ends are joined as a loop's are.
//
// Only keypoints the exclusion filter kept ever reach a keyframe, so a loop is never closed on a person.
//
// Threads: in the default mode Start() runs it in its own thread, fed by local mapping; in the deterministic mode
// the tracking thread calls ProcessQueue() after local mapping. A correction pauses local mapping
// (LocalMapper::Pause; tracking makes no keyframes meanwhile), changes the neighbourhood under Map::mutex() held
// exclusively, optimises the essential graph with no lock held, and writes the result back under the lock again,
// so tracking waits for it no longer than a copy and a write-back take. The global bundle adjustment that follows
// runs in a third thread the same way: copied under the shared lock, optimised with none, written back under the
// exclusive lock with local mapping paused.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <shared_mutex>
#include <thread>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/slam/optimize/bundle_adjustment.h"
#include "hoidslam/slam/local_mapper.h"
#include "hoidslam/slam/data/map.h"
#include "hoidslam/slam/optimize/pose_graph.h"
#include "hoidslam/slam/optimize/pose_optimizer.h"

namespace hoidslam::slam {

struct LoopClosingOptions {
  bool enabled = true;     // loops are closed (--no-loop-closing: off)
  bool merge_maps = true;  // maps are merged where one recognises a place of another
  // Keyframes the map needs, and keyframes since the last loop, before a loop is looked for.
  int min_keyframes = 10;
  // A place must be recognised by this many keyframes in a row (ORB-SLAM: 3): one look-alike is not a loop.
  int consistent_keyframes = 3;
  // Geometric verification: matches consistent with one SE(3) among the keyframe's descriptor matches to the
  // place's points, then inliers of the pose refined with the place's neighbourhood projected into the keyframe.
  int min_ransac_inliers = 20;
  int min_inliers = 40;
  int ransac_iterations = 300;
  double projection_radius = 10.0;  // pixels at level 0, searching the place's neighbourhood in the keyframe
  // The correction a loop makes must be one the drift could have made on the path since the place: at most
  // max_drift_m plus max_drift_share of the path's length, and max_drift_deg plus max_drift_deg_per_m per metre
  // (RGB-D odometry drifts about 1 % and a fraction of a degree per metre). On `loop`, two look-alike places passed
  // the checks below with 40 and 93 inliers; the corrections they asked for, 1.31 m after 3.2 m of path and 1.19 m
  // after 0.49 m, were refused by this.
  double max_drift_m = 0.05;
  double max_drift_share = 0.05;
  double max_drift_deg = 2.0;
  double max_drift_deg_per_m = 1.0;
  // Then the keyframe's strongest neighbours, moved with it, must find the place where the loop puts them: at least
  // `confirming_neighbours` of `checked_neighbours` with min_ransac_inliers inliers and a pose of their own within
  // the disagreement limits. One view of a texture met twice fits a wrong place; three seldom do (on `loop`, a look-
  // alike 0.7 m and 69° from the true place passed with 40 inliers and bent the map by a metre; its neighbours
  // refused it).
  int checked_neighbours = 3;
  int confirming_neighbours = 2;
  double max_neighbour_disagreement_m = 0.05;
  double max_neighbour_disagreement_deg = 2.0;
  PoseGraphOptions essential_graph;
  int essential_graph_min_weight = 100;  // covisibility edges at least this strong join the essential graph
  // After each loop, a bundle adjustment of the whole map refines what the essential graph moved (ORB-SLAM's global
  // BA): in a thread of its own, tracking and local mapping going on meanwhile; stopped early when another loop
  // is to be corrected.
  bool global_bundle_adjustment = true;
  int global_iterations = 10;

  void Check() const;
};

// The adjustment of each map once tracking is over (System::Finish): a global bundle adjustment with each depth
// weighed by a noise model of the sensor rather than as one pixel of virtual disparity, so that the several
// keyframes that see a point average its depth. It runs only at the end: during the run tracking leans on the map,
// and a map adjusted this way as it grew tracked worse on some paths (docs/slam.md, "The final adjustment"). `run`
// turns it on: it helps maps of long, varied paths and real recordings most and costs some short walks up to 0.9 mm.
struct FinalAdjustmentOptions {
  bool enabled = false;  // (on in pipeline::RunOptions, so in run and the API; off with --no-final-adjustment)
  core::DepthNoiseModel depth_noise;  // Depth.noiseFactor
  int huber_iterations = 10;          // with a Huber kernel, every observation
  int iterations = 10;                // then without, the first pass's outliers left out (and left in the map)

  void Check() const;
};

// A loop closed: the keyframe that recognised the place, the keyframe it recognised, and where the verification put
// the first relative to the second.
struct LoopClosure {
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  std::uint64_t loop_frame_id = 0;
  double loop_timestamp = 0.0;
  core::Pose T_loop_current;  // camera of the current keyframe into the loop keyframe's camera
  int inliers = 0;
  double correction_m = 0.0;    // how far the current keyframe was moved (a merge: 0, its map's frame is gone)
  double correction_deg = 0.0;  // and turned
  MapId map = 0;  // the map the loop was closed in (a merge: the map the other was merged into)
  std::optional<MapId> merged_map;  // a merge: the map that was moved into `map`
};

class LoopCloser {
 public:
  // Pauses `local_mapper` while it corrects a loop; both must outlive the closer.
  LoopCloser(Map& map, LocalMapper& local_mapper, const LoopClosingOptions& options);
  ~LoopCloser();  // stops the thread, if started
  LoopCloser(const LoopCloser&) = delete;
  LoopCloser& operator=(const LoopCloser&) = delete;

  // Queues a keyframe local mapping has finished. Thread-safe.
  void Insert(KeyFrame* keyframe);
  // Processes every queued keyframe in the calling thread (the deterministic mode).
  void ProcessQueue();
  // Runs in its own thread until Stop(); Stop() lets it finish the queued keyframes and the global bundle
  // adjustment under way first.
  void Start();
  void Stop();

  // The loops closed so far, in order. Thread-safe.
  std::vector<LoopClosure> closures() const;
  // The time each keyframe's loop detection took (ms: the database's candidates and their consistency), and each
  // verification (ms: one per candidate verified), in order. Thread-safe.
  struct Timings {
    std::vector<double> detection_ms;
    std::vector<double> verification_ms;
  };
  Timings timings() const;
  // Global bundle adjustments completed (not stopped early). Thread-safe.
  int global_adjustments() const { return global_adjustments_.load(); }
  // The final adjustment of `map` (FinalAdjustmentOptions), in the calling thread. Call once Stop() has returned.
  void AdjustFinally(MapId map, const FinalAdjustmentOptions& options);

 private:
  // A keyframe's view of one place the database returned, with how many keyframes in a row saw it.
  struct ConsistentGroup {
    std::set<const KeyFrame*> keyframes;
    int consistency = 0;
  };
  // The loop found for a keyframe: the keyframe of the place, the keyframe's pose that joins it to the place, and
  // the place's points matched to the keyframe's keypoints.
  struct VerifiedLoop {
    KeyFrame* loop = nullptr;
    core::Pose T_cw;
    std::vector<MapPoint*> matches;  // per keypoint of the keyframe
    int inliers = 0;
  };

  KeyFrame* NextKeyFrame();
  void Process(KeyFrame* keyframe);
  // The candidates recognised by enough keyframes in a row, in the keyframe's map (`loops`) and in the others
  // (`merges`); updates consistent_groups_. Shared lock held.
  std::vector<KeyFrame*> ConsistentCandidates(KeyFrame* keyframe, bool loops, bool merges);
  // Shared lock held.
  bool Verify(KeyFrame* keyframe, KeyFrame* candidate, VerifiedLoop& loop) const;
  void Correct(KeyFrame* keyframe, const VerifiedLoop& loop);
  void Merge(KeyFrame* keyframe, const VerifiedLoop& loop);
  // The keyframe and its good covisible keyframes, its connections updated first. Exclusive lock held.
  std::vector<KeyFrame*> Neighbourhood(KeyFrame* keyframe);
  // Makes the two ends one, the keyframe's `connected` neighbourhood already moved to where the loop puts it: the
  // place's points take over the keyframe's keypoints they matched, and the place's neighbourhood is fused into
  // `connected`. Returns the covisibility edges this made across the loop. Exclusive lock held.
  std::vector<std::pair<KeyFrame*, KeyFrame*>> Join(KeyFrame* keyframe, const std::vector<KeyFrame*>& connected,
                                                    const VerifiedLoop& loop);
  void Record(const KeyFrame* keyframe, const VerifiedLoop& loop, const core::Pose& T_cw_before,
              std::optional<MapId> merged_map);
  // Pauses local mapping and locks the map exclusively once local mapping stands still (LocalMapper::Pause).
  std::unique_lock<std::shared_mutex> LockStillMap();
  // The global bundle adjustment of one map: in its own thread when the closer runs in one, else in the caller's.
  void StartGlobalBundleAdjustment(MapId map);
  void StopGlobalBundleAdjustment();  // stops it early and waits for it
  // With `depth_noise`, each depth is weighed by it (the final adjustment); without, as one pixel of ur.
  void RunGlobalBundleAdjustment(MapId map, const BundleAdjustmentOptions& adjustment,
                                 const core::DepthNoiseModel* depth_noise = nullptr);
  void Loop(std::stop_token stop);

  Map& map_;
  LocalMapper& local_mapper_;
  LoopClosingOptions options_;

  mutable std::mutex queue_mutex_;
  std::condition_variable_any queue_changed_;
  std::deque<KeyFrame*> queue_;

  // The loop closing thread's own (or the tracking thread's, deterministic).
  std::vector<ConsistentGroup> consistent_groups_;
  std::optional<KeyFrameId> last_loop_keyframe_id_;

  mutable std::mutex closures_mutex_;  // guards closures_ and timings_
  std::vector<LoopClosure> closures_;
  Timings timings_;
  std::atomic<int> global_adjustments_{0};
  std::atomic<bool> abort_global_{false};
  bool threaded_ = false;  // Start() was called: the global adjustment gets a thread
  std::jthread global_thread_;  // owned by the loop closing thread (started and joined there), or by Stop()
  std::jthread thread_;
};

}  // namespace hoidslam::slam
