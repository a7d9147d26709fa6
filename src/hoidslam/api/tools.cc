// The public API beside System (hoidslam.h): reading recorded sequences, the ONNX detector and the HOID filter on
// their own, ATE / RPE, and synthetic sequences, each a thin layer over its module.
#include <atomic>
#include <cstring>

#include <fmt/format.h>

#include "hoidslam/hoidslam.h"
#include "hoidslam/api/convert.h"
#include "hoidslam/core/options.h"
#include "hoidslam/detect/onnx_detector.h"
#include "hoidslam/eval/ate.h"
#include "hoidslam/eval/rpe.h"
#include "hoidslam/hoid/filter.h"
#include "hoidslam/io/detections_file.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/sequence_writer.h"

namespace hoidslam {
namespace {

core::Trajectory ToTrajectory(const std::vector<StampedPose>& poses, const std::string& name) {
  core::Trajectory trajectory;
  trajectory.reserve(poses.size());
  for (const StampedPose& p : poses) {
    const auto& [x, y, z, w] = p.rotation;
    const Eigen::Quaterniond q(w, x, y, z);
    if (!(q.norm() > 1e-9)) {
      throw InputError::ForParameter(name, fmt::format("the rotation at {:.6f} s is not a quaternion", p.timestamp));
    }
    trajectory.push_back(
        {p.timestamp, core::PoseFromTranslationQuaternion({p.translation[0], p.translation[1], p.translation[2]}, q)});
  }
  return trajectory;
}

ErrorSummary ToSummary(const eval::ErrorStatistics& s) { return {s.rmse, s.mean, s.median, s.std, s.min, s.max, s.count}; }

io::SequenceOptions WithDepthFactor(double depth_factor) {
  io::SequenceOptions options;
  options.depth_factor = depth_factor;
  return options;
}

}  // namespace

class Sequence::Impl {
 public:
  Impl(const std::filesystem::path& folder, double depth_factor)
      : sequence(io::RgbdSequence::OpenTum(folder, WithDepthFactor(depth_factor))) {}
  io::RgbdSequence sequence;
};

Sequence::Sequence(const std::filesystem::path& folder, double depth_factor)
    : impl_(std::make_unique<Impl>(folder, depth_factor)) {}
Sequence::~Sequence() = default;
Sequence::Sequence(Sequence&&) noexcept = default;
Sequence& Sequence::operator=(Sequence&&) noexcept = default;

std::size_t Sequence::size() const { return impl_->sequence.size(); }
std::string Sequence::name() const { return impl_->sequence.name(); }
std::filesystem::path Sequence::root() const { return impl_->sequence.root(); }
std::vector<double> Sequence::Timestamps() const { return impl_->sequence.Timestamps(); }

std::vector<StampedPose> Sequence::Groundtruth() const {
  std::vector<StampedPose> poses;
  for (const core::StampedPose& p : impl_->sequence.groundtruth()) poses.push_back(api::ToStampedPose(p));
  return poses;
}

Frame Sequence::Load(std::size_t index) const {
  if (index >= size()) {
    throw InputError::ForParameter("index", fmt::format("{} is past the last frame ({} frames)", index, size()));
  }
  const core::RgbdFrame loaded = impl_->sequence.LoadFrame(index);
  Frame frame;
  frame.timestamp = loaded.timestamp;
  frame.depth_delay = loaded.depth_delay;
  frame.width = loaded.rgb.cols;
  frame.height = loaded.rgb.rows;
  frame.rgb_path = loaded.rgb_path;
  // cv::imread's images are continuous: one copy each into storage the caller owns.
  frame.rgb.assign(loaded.rgb.datastart, loaded.rgb.dataend);
  frame.depth.resize(loaded.depth.total());
  std::memcpy(frame.depth.data(), loaded.depth.data, frame.depth.size() * sizeof(float));
  return frame;
}

class DetectionsFile::Impl {
 public:
  explicit Impl(const std::filesystem::path& path) : file(io::DetectionsFile::Read(path)) {}
  io::DetectionsFile file;
  mutable std::atomic<std::size_t> missed{0};  // Find may be called from several threads
};

DetectionsFile::DetectionsFile(const std::filesystem::path& path) : impl_(std::make_unique<Impl>(path)) {}
DetectionsFile::~DetectionsFile() = default;
DetectionsFile::DetectionsFile(DetectionsFile&&) noexcept = default;
DetectionsFile& DetectionsFile::operator=(DetectionsFile&&) noexcept = default;

std::optional<std::vector<Detection>> DetectionsFile::Find(double timestamp) const {
  const io::FrameDetections* frame = impl_->file.Find(timestamp);
  if (frame == nullptr) {
    ++impl_->missed;
    return std::nullopt;
  }
  return api::ToApiDetections(frame->detections);
}

std::size_t DetectionsFile::size() const { return impl_->file.frames().size(); }
std::size_t DetectionsFile::missed() const { return impl_->missed; }
std::filesystem::path DetectionsFile::path() const { return impl_->file.path(); }

class Detector::Impl {
 public:
  explicit Impl(const detect::OnnxDetectorOptions& options) : detector(options) {}
  detect::OnnxDetector detector;
};

Detector::Detector(const std::filesystem::path& model, float confidence, float nms) {
  detect::OnnxDetectorOptions options;
  options.model = model;
  options.confidence_threshold = confidence;
  options.nms_threshold = nms;
  impl_ = std::make_unique<Impl>(options);
}
Detector::~Detector() = default;
Detector::Detector(Detector&&) noexcept = default;
Detector& Detector::operator=(Detector&&) noexcept = default;

std::vector<Detection> Detector::Detect(const ImageView& rgb) {
  return api::ToApiDetections(impl_->detector.Detect(0.0, api::ColourMat(rgb, 0, 0, "rgb")));
}

std::string Detector::Name() const { return impl_->detector.Name(); }

std::vector<JudgedBox> JudgeBoxes(std::span<const Detection> detections, const FilterOptions& options,
                                  const ImageView* depth, double depth_factor) {
  core::HoidOptions hoid;
  hoid.mode = core::ParseFilterMode(options.mode, "mode");
  if (hoid.mode == core::FilterMode::kHoidPlus) {
    throw InputError::ForParameter("mode", "hoidplus remembers earlier frames: use System");
  }
  hoid.min_interaction_area = options.min_interaction_area;
  hoid.depth_threshold = options.depth_threshold;
  hoid.Check();
  hoid::JudgedBoxes boxes;
  boxes.detections = api::ToCoreDetections(detections, "detections");
  const cv::Mat metres = depth == nullptr ? cv::Mat() : api::DepthMetres(*depth, 0, 0, depth_factor, "depth");
  boxes.decisions = hoid::ClassifyDetections(boxes.detections, hoid, metres);
  return api::ToJudgedBoxes(boxes);
}

AteResult ComputeAte(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate) {
  const eval::AteResult ate =
      eval::ComputeAte(ToTrajectory(groundtruth, "groundtruth"), ToTrajectory(estimate, "estimate"), {});
  AteResult result{ToSummary(ate.error), {}, {}, {}};
  for (const eval::AtePair& pair : ate.pairs) {
    const Eigen::Vector3d& g = pair.groundtruth_position;
    const Eigen::Vector3d& a = pair.aligned_position;
    result.timestamps.push_back(pair.estimate_timestamp);
    result.groundtruth.push_back({g.x(), g.y(), g.z()});
    result.aligned.push_back({a.x(), a.y(), a.z()});
  }
  return result;
}

RpeSummary ComputeRpe(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                      double delta_seconds) {
  eval::RpeOptions options;
  options.delta = delta_seconds;
  options.Check();
  const eval::RpeResult rpe =
      eval::ComputeRpe(ToTrajectory(groundtruth, "groundtruth"), ToTrajectory(estimate, "estimate"), options);
  return {ToSummary(rpe.translation), ToSummary(rpe.rotation_deg)};
}

std::size_t RenderSynthetic(const SynthOptions& options) {
  synth::Scenario scenario = synth::LoadScenario(options.scenario);
  if (options.frames > 0) scenario.max_frames = options.frames;
  synth::SynthOptions synth;
  synth.out = options.out;
  synth.force = options.force;
  synth.threads = options.threads;
  synth.tum_dir = options.tum_dir;
  synth.frame_step = options.frame_step;
  return synth::WriteSequence(scenario, synth).frames;
}

}  // namespace hoidslam
