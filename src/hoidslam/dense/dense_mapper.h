#pragma once
// The dense map of a run: keyframes handed over as tracking makes them, prepared in the mapper's own thread (the
// dynamic pixels and the depth the sensor model does not trust taken out, the images compressed), and fused once
// the poses are final — after loop closing and the final adjustment, since Open3D cannot take a view back out of a
// volume. Writes mesh.ply, cloud.ply, occupancy.bt, occupancy.pgm and occupancy.yaml (docs/dense.md). Asked to, it
// also grows a coarse preview while the run goes (DensePreview), at the poses tracking gave the keyframes.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/frame.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/dense/dense_options.h"
#include "hoidslam/dense/dense_preview.h"
#include "hoidslam/dense/dense_summary.h"
#include "hoidslam/detect/detector.h"
#include "hoidslam/eval/person_surface.h"
#include "hoidslam/pipeline/session.h"

namespace hoidslam::dense {

class DenseMapper {
 public:
  // Throws InputError when the options fail Check().
  DenseMapper(const DenseOptions& options, const core::CameraIntrinsics& camera);
  ~DenseMapper();  // stops the thread; what was handed over and not built is dropped
  DenseMapper(const DenseMapper&) = delete;
  DenseMapper& operator=(const DenseMapper&) = delete;

  // One keyframe: its images (copied here, the rest happens in the mapper's thread), the pixels the filter left
  // out (CV_8UC1, non-zero = dynamic; empty: none), the pose tracking gave it, which the preview fuses it at (none:
  // not in the preview), and the detector's person boxes, in which the built map is checked for people it kept
  // (eval/person_surface.h). Throws std::logic_error after Build.
  void AddKeyFrame(const core::RgbdFrame& frame, const cv::Mat& left_out,
                   const std::optional<core::Pose>& T_wc = std::nullopt, const std::vector<cv::Rect>& people = {});
  // AddKeyFrame for a frame `session` just tracked when it became a keyframe, with what the session's filter left
  // out of it (Session::StaticMapExclusion), its pose and the boxes of the session's person class it judged; the
  // command and the API call it after each frame. A session whose mode judges no boxes (none) leaves `detector`,
  // when given, free: it is asked for the keyframe's boxes here, in the caller's thread, for the check alone.
  void TakeKeyFrame(const pipeline::Session& session, const core::RgbdFrame& frame,
                    const pipeline::FrameOutcome& outcome, detect::Detector* detector = nullptr);

  // From now on, fuses each keyframe with a pose into a coarse preview in a thread of its own and hands its mesh to
  // `show` now and then (DensePreview), until Build or the mapper's end; `show` is called from that thread. Tracking
  // never waits for it: a keyframe is still only queued. Throws InputError when `preview` fails Check(), and
  // std::logic_error when already following or after Build.
  void FollowPreview(const PreviewOptions& preview, std::function<void(io::TriangleMesh)> show);

  // Waits for the keyframes handed over to be prepared, fuses those `keyframes` holds at the poses it gives
  // (matched by timestamp; the map's final keyframes), and writes the outputs into `folder` (each file complete or
  // absent). No keyframe can be added after it; it may be called again (the API's Save, once more). The preview,
  // if any, ends first.
  DenseSummary Build(const core::Trajectory& keyframes, const std::filesystem::path& folder);

  const DenseOptions& options() const { return options_; }

 private:
  // A person box with the depth measured in it, in half-millimetres as a PNG (nothing left out).
  struct PersonCrop {
    cv::Rect box;
    std::vector<unsigned char> png;
  };
  // A keyframe as kept until the build: the depth in half-millimetres (0 = not fused) as a PNG, the colour as JPEG.
  struct Prepared {
    std::vector<unsigned char> png;
    std::vector<unsigned char> jpeg;
    std::vector<PersonCrop> people;
  };
  struct Pending {
    double timestamp = 0.0;
    cv::Mat bgr, depth, left_out;
    std::optional<core::Pose> T_wc;  // as tracking gave it: for the preview
    std::vector<cv::Rect> people;    // inside the image
  };
  // A keyframe's images as they are fused: colour undistorted, depth fusible (FusibleDepth) and undistorted.
  struct View {
    cv::Mat bgr, depth;
  };
  void Work();
  void Stop();
  // The keyframe prepared at `timestamp` (within a microsecond), or null: none was handed over.
  Prepared* Held(double timestamp);
  // Fuses the keyframes' images and lets them go; the person crops stay for CheckPeople.
  DenseSummary Fuse(const core::Trajectory& keyframes, const std::filesystem::path& folder);
  View Fusible(const Pending& pending) const;
  Prepared Compress(const View& view) const;
  std::vector<PersonCrop> PersonCrops(const Pending& pending) const;
  // The person boxes of the keyframes fused, at their poses, against the map written into `folder`.
  std::optional<eval::PersonSurface> CheckPeople(const core::Trajectory& keyframes,
                                                 const std::filesystem::path& folder);

  DenseOptions options_;
  core::CameraIntrinsics camera_;  // without distortion: the images are undistorted as they are prepared
  cv::Mat undistort_x_, undistort_y_;  // the maps that undistort them; empty for a camera without distortion
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Pending> queue_;
  bool stopping_ = false;
  std::map<double, Prepared> prepared_;  // by timestamp; written by the thread, read by Build after it joined
  std::unique_ptr<DensePreview> preview_;  // set under mutex_; used by the thread, ended by Build after it joined
  std::thread thread_;
};

}  // namespace hoidslam::dense
