#pragma once
// Local mapping: what happens to a keyframe after tracking made it. Its points get their normals, distance
// ranges and descriptors; its covisibility edges are made; new points are triangulated with its covisible
// keyframes; duplicates in its neighbourhood are fused; a local bundle adjustment (Ceres) refines the
// neighbourhood; and points that tracking does not find again, and keyframes whose points others see as well,
// are culled.
//
// Threads: in the default mode Start() runs it in its own thread, fed by Insert(); in the deterministic mode
// nobody calls Start() and the tracking thread calls ProcessQueue() after each new keyframe, so the map evolves
// identically on every run. Either way it changes the map under Map::mutex() held exclusively (map.h).

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/slam/optimize/bundle_adjustment.h"
#include "hoidslam/slam/data/map.h"

namespace hoidslam::slam {

struct LocalMapperOptions {
  int triangulation_neighbours = 10;  // covisible keyframes searched for new points
  int fusion_neighbours = 10;         // covisible keyframes (plus 5 of each of theirs) searched for duplicates
  double redundant_ratio = 0.9;       // a keyframe is culled when this share of its close points is seen by >= 3 others
  BundleAdjustmentOptions bundle_adjustment;

  void Check() const;
};

class LocalMapper {
 public:
  // Keyframes are described with `vocabulary` for place recognition; it must outlive the mapper. `mapped`, when
  // given, is called with each keyframe once it is mapped (loop closing takes it from there), in the mapper's
  // thread.
  LocalMapper(Map& map, const bow::Vocabulary& vocabulary, const LocalMapperOptions& options,
              std::function<void(KeyFrame*)> mapped = {});
  ~LocalMapper();  // stops the thread, if started
  LocalMapper(const LocalMapper&) = delete;
  LocalMapper& operator=(const LocalMapper&) = delete;

  // Queues a keyframe that tracking has just added to the map; a running bundle adjustment stops early so the new
  // keyframe is handled soon. Thread-safe.
  void Insert(KeyFrame* keyframe);
  // True when nothing is queued or being processed. Thread-safe.
  bool Idle() const;
  std::size_t Queued() const;

  // While a loop is corrected, local mapping must not change the map and tracking makes no keyframes: Pause()
  // asks for that, lets the mapper finish what is queued, and returns once it stands still; it goes on when the
  // returned guard is destroyed. Called from another thread than the mapper's (or, in the deterministic mode, once
  // the queue has been processed).
  class PauseGuard {
   public:
    explicit PauseGuard(LocalMapper& mapper) : mapper_(&mapper) {}
    PauseGuard(const PauseGuard&) = delete;
    PauseGuard& operator=(const PauseGuard&) = delete;
    ~PauseGuard() { mapper_->Resume(); }

   private:
    LocalMapper* mapper_;
  };
  [[nodiscard]] PauseGuard Pause();
  // Whether a pause is asked for or under way: tracking makes no keyframe then. Thread-safe.
  bool Paused() const;
  // Returns once nothing is queued or being processed. A keyframe tracking made just before the pause may still
  // arrive after Pause() returned: the caller checks Idle() again with the map's lock held (tracking queues its
  // keyframes under it) and waits again if need be.
  void WaitUntilIdle();

  // Processes every queued keyframe in the calling thread (the deterministic mode).
  void ProcessQueue();
  // Runs the loop in its own thread until Stop(); Stop() lets it finish the queued keyframes first.
  void Start();
  void Stop();

 private:
  KeyFrame* NextKeyFrame();  // the oldest queued keyframe, or nullptr
  void Process(KeyFrame* keyframe);
  void CullRecentPoints(const KeyFrame* keyframe);
  void CreateNewPoints(KeyFrame* keyframe);
  void FuseNeighbours(KeyFrame* keyframe);
  void RunLocalBundleAdjustment(KeyFrame* keyframe);
  void CullKeyFrames(KeyFrame* keyframe);
  void Loop(std::stop_token stop);
  void Resume();

  Map& map_;
  const bow::Vocabulary& vocabulary_;
  LocalMapperOptions options_;
  std::function<void(KeyFrame*)> mapped_;

  mutable std::mutex queue_mutex_;
  std::condition_variable_any queue_changed_;
  std::deque<KeyFrame*> queue_;
  bool busy_ = false;
  bool paused_ = false;
  std::atomic<bool> abort_bundle_adjustment_{false};

  std::vector<MapPoint*> recent_points_;  // created lately, still on probation; local mapping thread only
  std::jthread thread_;
};

}  // namespace hoidslam::slam
