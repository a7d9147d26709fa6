#pragma once
// hoidslam as a library: RGB-D SLAM that drops the features of people and of the objects in their hands (HOID)
// inside your own program. Frames come in as plain buffers (width, height, stride, format) from any source: a
// camera SDK, a recording, a renderer. Poses, tracking states and every keypoint's verdict come out. No OpenCV type
// is needed here; hoidslam/hoidslam_opencv.h adds overloads that take cv::Mat.
//
//   hoidslam::Options options;
//   options.settings = hoidslam::ShippedDir() / "config/TUM3.yaml";
//   options.filter = "hoid2d";
//   hoidslam::System slam(options);
//   hoidslam::FrameResult r = slam.Track(rgb, depth, timestamp, detections);
//   if (r.T_wc) use(*r.T_wc);
//   slam.Finish();
//   slam.Save("out/");
//
// Every frame goes through what `hoidslam run` does to a frame of a recording (pipeline/session.h), so the same
// frames give the same trajectory; in the deterministic mode it is byte-identical to the command's. Errors are
// exceptions: hoidslam::InputError (a std::runtime_error) for bad input, with a message naming the parameter or
// file, as the command prints it. docs/library.md describes the API.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hoidslam/core/error.h"

namespace hoidslam {

using core::Error;       // base of every hoidslam error
using core::InputError;  // bad input: the message names the parameter, or the file and line

// The library's version, "major.minor.patch" (HOIDSLAM_VERSION of hoidslam/version.h is the headers').
std::string Version();

// Where hoidslam's shipped files are: the settings (config/TUM1.yaml, TUM2, TUM3, Bonn) and the bag-of-words
// vocabulary (data/vocabulary/). <prefix>/share/hoidslam in an installed package, else the source tree it was built
// from.
std::filesystem::path ShippedDir();

// The shipped settings file a TUM or Bonn sequence folder's name calls for, as `hoidslam run` and `bench` choose it
// without --settings: config/TUM1.yaml, TUM2 or TUM3 for freiburg1/2/3 (or fr1_, fr2_, fr3_), Bonn.yaml for bonn;
// empty for any other name (then the defaults, the TUM fr3 camera, are what Options with no settings give).
std::filesystem::path SettingsForSequence(const std::filesystem::path& folder);

// How the bytes of an image are laid out.
enum class PixelFormat {
  kBgr,   // colour, 8 bits a channel, blue first (OpenCV's order)
  kRgb,   // colour, 8 bits a channel, red first (most camera SDKs, PIL, matplotlib)
  kGray,  // 8 bits
  // Depth: 16-bit unsigned units of 1 / depth_factor metres (TUM, Kinect, RealSense: DepthMapFactor of the
  // settings). 0 means no measurement.
  kDepthUint16,
  kDepthFloat32,  // depth: 32-bit float metres; 0 and non-finite mean no measurement
};

// An image the caller owns: read, never kept past the call (but see Options::realtime).
struct ImageView {
  const void* data = nullptr;
  int width = 0;
  int height = 0;
  std::size_t stride = 0;  // bytes from one row to the next; 0: rows packed
  PixelFormat format = PixelFormat::kBgr;
};

// An axis-aligned box in pixels: top-left corner, width and height.
struct Box {
  float x = 0.0F, y = 0.0F, width = 0.0F, height = 0.0F;
};

// One object a detector found in a frame. The filter matches classes by label (COCO names: "person", "cup", ...).
struct Detection {
  std::string label;
  float score = 1.0F;
  Box box;
  int class_id = -1;  // index in the detector's class list, -1 if unknown
};

// The filter's verdict on one box (docs/hoid.md).
struct JudgedBox {
  Detection detection;
  bool dynamic = false;  // its features are dropped
  std::string reason;    // why: "person", "interaction", "no_interaction", "depth_rejected", ...
  int person = -1;       // for a handled object: the index of its person's box in the same list
  float interaction = 0.0F;  // area(object ∩ person) / area(object) with that person
};

// Which detector gives the boxes each frame is judged by.
enum class DetectorKind {
  kGiven,  // the caller passes each frame's detections to Track (its own model, a file, a tracker)
  kOnnx,   // a YOLO-family ONNX model run inside hoidslam (Options::model)
  kNone,   // no boxes: only filter "none" (the plain baseline) runs without them
};

// A camera given by its values, as its SDK reports them (docs/library.md, "Your own camera"): the colour camera's
// intrinsics at the resolution it streams, with the depth image registered to it, pixel for pixel.
struct Camera {
  double fx = 0.0, fy = 0.0;  // focal lengths, pixels (> 0)
  double cx = 0.0, cy = 0.0;  // principal point, pixels (inside the image)
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3 (OpenCV's order); all 0: none
  int width = 0, height = 0;           // image size, pixels
  // Metres per unit of uint16 depth: 0.001 for millimetres (RealSense's get_depth_scale(), OpenNI, Azure Kinect),
  // 0.0002 for TUM's 5000 units a metre. Float depth is in metres whatever this says.
  double depth_scale = 0.001;
  // Metres between the depth camera's projector and sensor (or stereo pair), as ORB-SLAM's Camera.bf / fx: points
  // nearer than 40 baselines count as close. Time-of-flight cameras have none; 0.09 makes 3.6 m close.
  double baseline = 0.075;
};

// Where the live viewer's page is served (Options::view).
struct View {
  std::string address = "127.0.0.1";  // 0.0.0.0: other machines see the page too
  int port = 8787;                     // 0: a free port (System::ViewerUrl says which)
};

// The dense map of the static world that Save writes beside the trajectory (Options::dense; docs/dense.md): mesh.ply,
// cloud.ply, occupancy.bt, occupancy.pgm and occupancy.yaml, fused from the keyframes at their final poses with
// people and what they carry left out. Bad values get an InputError naming the `hoidslam run` flag (--dense-voxel...).
struct Dense {
  double voxel_size = 0.01;            // m
  double max_depth = 3.0;              // m: farther depth is not fused
  double occupancy_resolution = 0.05;  // m
  double band_low = 0.1, band_high = 1.8;  // m above the floor: the 2D grid's obstacles
  // Keep surface that later keyframes looked through (by default left out of the mesh and the cloud: a person the
  // filter missed in a few keyframes, a chair moved away; docs/dense.md).
  bool keep_seen_through = false;
};

struct Options {
  // ORB-SLAM3-style YAML with a HOID section (e.g. ShippedDir() / "config/TUM3.yaml"); empty: the TUM fr3 camera
  // and the default ORB and HOID settings.
  std::filesystem::path settings;
  // The camera, given by the program: replaces the settings' camera, DepthMapFactor and Camera.bf (their ORB and
  // HOID sections still apply). Checked: InputError naming camera.fx, camera.width, ...
  std::optional<Camera> camera;
  // What is dropped, as `hoidslam run --filter` takes it: none, person, classes, hoid2d, hoid3d, hoidplus (or
  // hoidplus:depth+memory...); empty: HOID.mode of the settings, else hoidplus.
  std::string filter;
  DetectorKind detector = DetectorKind::kGiven;
  std::filesystem::path model;  // the ONNX model of DetectorKind::kOnnx
  // The detector in its own thread: tracking never waits for it, each frame is judged by the newest detections,
  // carried to it (docs/realtime.md); the colour image is then copied, since the detector reads it after Track
  // returns. Off: each frame waits for its own detections.
  bool realtime = false;
  // Local mapping in step with tracking: the same frames give a byte-identical trajectory on every run. Cannot go
  // with realtime.
  bool deterministic = false;
  // Where a frame's keypoint budget goes: "static" (to what the filter keeps) or "image" (as ORB-SLAM spreads it).
  std::string keypoint_budget = "static";
  std::filesystem::path vocabulary;  // bag-of-words vocabulary for relocalisation; empty: the shipped one
  // Start from the map in this map file (System::SaveMap, `hoidslam run --save-map`): the first frame is
  // relocalised in it, and new keyframes continue it. Made with the same camera and vocabulary (docs/slam.md,
  // "Map reuse").
  std::filesystem::path load_map;
  // With load_map: track against the loaded map without changing it (no new keyframes, no local mapping).
  bool localization = false;
  // A live viewer of the session in a browser (docs/viewer.md), served while the System lives: the map, the current
  // frame with its keypoints kept and dropped, the boxes and their verdicts. nullopt: none (no thread, no copies).
  std::optional<View> view;
  // Keyframes kept (their images, compressed, about 0.3 MB each) and fused densely when the session is saved.
  // nullopt: none.
  std::optional<Dense> dense;
};

// A camera pose at a time: camera to world, as a row of a TUM trajectory file.
struct StampedPose {
  double timestamp = 0.0;
  std::array<double, 3> translation{};      // metres
  std::array<double, 4> rotation{0, 0, 0, 1};  // unit quaternion x, y, z, w
};

// A 4×4 rigid transform, row-major.
using Matrix4 = std::array<double, 16>;

enum class TrackingState {
  kOk,              // tracked: FrameResult::T_wc holds the pose
  kLost,            // after initialisation, not tracked (FrameResult::failure says why)
  kNotInitialized,  // before the map could start (too few keypoints with depth)
  // Found again after a loss: FrameResult::T_wc holds the pose, but nothing enters the map from it until the next
  // frames confirm it; if they refute it, a later frame's FrameResult::withdrawn lists this one (docs/slam.md).
  kProvisional,
};
std::string_view ToString(TrackingState state);

// The keypoints of a frame and their verdicts, one entry per keypoint in each vector (structure of arrays, so
// that numpy can take them as they are).
struct Keypoints {
  std::vector<float> xy;           // x0, y0, x1, y1, ... pixels
  std::vector<std::uint8_t> kept;  // 1: used for tracking; 0: dropped by the filter
  // A dropped keypoint's dynamic box (index into FrameResult::boxes): the first that holds it, else the nearest
  // (hoidplus grows boxes a little); -1 for a kept one, and for one dropped by no box (the oracle's mask).
  std::vector<int> box;

  std::size_t size() const { return kept.size(); }
};

// What one frame went through.
struct FrameResult {
  std::size_t index = 0;  // frames count from 0
  double timestamp = 0.0;
  TrackingState state = TrackingState::kNotInitialized;
  std::optional<Matrix4> T_wc;  // camera to world, when tracked
  std::string method;   // how the pose was found: initialization, motion_model, reference_keyframe, relocalization, none
  // Why a lost frame was lost: too_few_keypoints, too_few_matches, pose_rejected, relocalization_refuted; else
  // empty. A refused pose also says why in `rejection` (too_few_inliers, too_little_support, contradicted,
  // outliers_clustered, against_motion; for a relocalisation, ambiguous).
  std::string failure;
  std::string rejection;
  // This frame refuted a provisional pose found after a loss: the indices of the frames tracked provisionally
  // since, now lost (their poses leave the trajectory).
  std::vector<std::size_t> withdrawn;
  bool keyframe = false;
  // The map it was tracked in: 0 unless tracking was lost long in new ground and started another (docs/slam.md,
  // "Several maps"); a later merge may join that map to the first. Trajectory() holds the main map's frames.
  std::uint32_t map = 0;
  std::vector<JudgedBox> boxes;  // every box judged, with the verdict
  Keypoints keypoints;
  std::size_t extracted = 0;  // keypoints of the first extraction, over the whole image
  std::size_t dropped = 0;    // of those, dropped by the filter
  int matched = 0;            // keypoints matched to map points before the final pose optimisation
  int inliers = 0;            // of those, kept by it
  double milliseconds = 0.0;  // extraction, detections, filter and tracking of this frame

  // Why keypoint `i` was dropped: its box's reason, "mask" for one dropped by no box; empty when it was kept.
  std::string_view DropReason(std::size_t i) const;
};

// A map point: position (metres, world frame), colour where first seen, and how many keyframes see it.
struct MapPoint {
  std::array<double, 3> position{};
  std::array<std::uint8_t, 3> rgb{};
  int observations = 0;
};

// One SLAM session: frames in, in time order; poses, trajectory and map out. Not copyable; movable. Tracking runs
// on the caller's thread (local mapping, and with Options::realtime the detector, in threads of their own).
//
// Safe to share between threads (a camera thread tracking, a viewer reading): every call takes one lock, so
// Track calls run one at a time, frames taken in the order the calls get the lock, and Trajectory, KeyFrames and
// MapPoints read between two frames (waiting for the frame in progress). A frame not newer than the last one
// tracked is refused with an InputError naming `timestamp`: with several tracking threads, give each frame its
// camera's timestamp and expect such refusals when two threads race. Moving or destroying a System while another
// thread uses it is the caller's error, as for any object.
class System {
 public:
  // Throws InputError naming the parameter or file: an unreadable settings file, an unknown filter, a filter that
  // needs boxes with DetectorKind::kNone, a missing model, realtime with deterministic.
  explicit System(const Options& options);
  ~System();
  System(System&&) noexcept;
  System& operator=(System&&) noexcept;

  // Tracks the next frame: `rgb` in a colour (or grey) format, `depth` in a depth format, both of the camera's size
  // (width(), height()). With
  // DetectorKind::kGiven the filter judges `detections` (boxes in pixels of `rgb`); with kOnnx the model's boxes
  // are used and `detections` must be empty. `depth_delay`: seconds from the colour image to the depth image
  // when the camera takes them apart (Frame::depth_delay of a recorded sequence; TUM fr1 up to 20 ms): hoidplus's
  // safety net does not judge a point the camera moved more than a pixel over it. Throws InputError naming rgb,
  // depth, timestamp, detections or depth_delay for a bad argument, and core::Error after Finish.
  FrameResult Track(const ImageView& rgb, const ImageView& depth, double timestamp,
                    std::span<const Detection> detections = {}, double depth_delay = 0.0);

  // Lets local mapping finish and stops it (and the detector thread), then adjusts the map once more as `hoidslam
  // run` does (docs/slam.md, "The final adjustment"): the trajectory and map are final. Idempotent; the destructor
  // calls it.
  void Finish();

  // Every frame tracked in the main map (the one with the most frames: FrameResult::map), placed relative to its
  // reference keyframe as the map has it now (final after Finish); the keyframes and points of that map.
  std::vector<StampedPose> Trajectory() const;
  std::vector<StampedPose> KeyFrames() const;
  std::vector<MapPoint> MapPoints() const;
  // Writes what `hoidslam run` writes for a sequence without ground truth into `folder` (created when missing),
  // each file complete or absent: trajectory.txt, keyframes.txt, map.ply, frames.jsonl, summary.json (with its
  // provenance: the settings or camera, the vocabulary, the detector's model) and report.html, so that `hoidslam
  // report` and `bench` read the folder, and with Options::dense the dense map. Finishes first. InputError naming
  // the folder when it cannot be made.
  void Save(const std::filesystem::path& folder);
  // Writes the map to a map file Options::load_map (and `hoidslam run --load-map`) start from. Finishes first.
  // InputError naming the file when it cannot be written.
  void SaveMap(const std::filesystem::path& path);
  // Back to no frames, as a new System with the same options (a map of Options::load_map is loaded again): for a
  // camera that was moved away, or a new recording. The next frame may have any timestamp.
  void Reset();

  int width() const;   // the camera's image size (Camera.width, Camera.height of the settings)
  int height() const;
  double depth_factor() const;  // DepthMapFactor: units of uint16 depth per metre
  std::string filter() const;   // the filter mode, as Options::filter names it
  // Where the viewer's page is (http://address:port/), empty without Options::view.
  std::string ViewerUrl() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// A recorded frame, owning its images.
struct Frame {
  double timestamp = 0.0;
  double depth_delay = 0.0;       // seconds from the colour image to the depth image (from the associated stamps)
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // height × width × 3, BGR, rows packed
  std::vector<float> depth;       // height × width, metres, 0 where the sensor gave none
  std::string rgb_path;           // where the colour image came from
};

// A recorded sequence: a TUM RGB-D or Bonn download, or a folder `hoidslam synth` wrote (rgb.txt, depth.txt,
// optional associations and groundtruth.txt; docs/slam.md). Frames are read on demand.
class Sequence {
 public:
  // `depth_factor`: depth PNG units per metre (DepthMapFactor; 5000 for TUM and Bonn). Throws InputError naming
  // the file when the folder is not a sequence.
  explicit Sequence(const std::filesystem::path& folder, double depth_factor = 5000.0);
  ~Sequence();
  Sequence(Sequence&&) noexcept;
  Sequence& operator=(Sequence&&) noexcept;

  std::size_t size() const;
  std::string name() const;  // the folder's name
  std::filesystem::path root() const;
  // Frame `index` (< size(); InputError naming index otherwise, or the image file that cannot be read).
  Frame Load(std::size_t index) const;
  std::vector<double> Timestamps() const;
  std::vector<StampedPose> Groundtruth() const;  // groundtruth.txt, empty when there is none

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// A detections file (docs/detections-file.md): the boxes of any detector for a whole sequence, by timestamp, as
// `hoidslam detect` or any other tool writes them.
class DetectionsFile {
 public:
  // Throws InputError naming the file and line.
  explicit DetectionsFile(const std::filesystem::path& path);
  ~DetectionsFile();
  DetectionsFile(DetectionsFile&&) noexcept;
  DetectionsFile& operator=(DetectionsFile&&) noexcept;
  // The detections of the frame at `timestamp` (within a millisecond, so that timestamps rounded to the
  // millisecond still match), nullopt when the file has no such frame; missed() counts those.
  std::optional<std::vector<Detection>> Find(double timestamp) const;
  std::size_t size() const;    // frames
  std::size_t missed() const;  // calls of Find that found no frame
  std::filesystem::path path() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// A YOLO-family ONNX model (YOLOX, YOLOv5, YOLOv8, YOLO11; the layout is recognised) run by OpenCV (docs/detectors.md).
class Detector {
 public:
  // Throws InputError naming the model file when it cannot be loaded, or the parameter out of range.
  explicit Detector(const std::filesystem::path& model, float confidence = 0.25F, float nms = 0.45F);
  ~Detector();
  Detector(Detector&&) noexcept;
  Detector& operator=(Detector&&) noexcept;
  // The detections in a colour image (boxes in its pixels, best score first). Throws InputError naming rgb.
  std::vector<Detection> Detect(const ImageView& rgb);
  std::string Name() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// The HOID filter on its own (docs/hoid.md): which boxes of a frame are dynamic, and why.
struct FilterOptions {
  std::string mode = "hoid2d";  // none, person, classes, hoid2d, hoid3d (hoidplus remembers frames: System only)
  double min_interaction_area = 0.4;  // HOID.minInteractionArea
  double depth_threshold = 0.2;       // HOID.depthThreshold, metres (hoid3d)
};
// One verdict per box, in order. `depth` (hoid3d reads it; may be null) and `depth_factor` as System::Track takes
// them. Throws InputError naming the parameter.
std::vector<JudgedBox> JudgeBoxes(std::span<const Detection> detections, const FilterOptions& options = {},
                                  const ImageView* depth = nullptr, double depth_factor = 5000.0);

// Errors of a trajectory against the ground truth, as TUM's evaluate_ate.py / evaluate_rpe.py compute them
// (docs/evaluation.md).
struct ErrorSummary {
  double rmse = 0.0, mean = 0.0, median = 0.0, std = 0.0, min = 0.0, max = 0.0;
  std::size_t count = 0;
};
// Absolute trajectory error after rigid alignment, with every matched pair for plots.
struct AteResult {
  ErrorSummary error;  // metres
  std::vector<double> timestamps;                   // per matched pair: the estimate's timestamp
  std::vector<std::array<double, 3>> groundtruth;  // the ground-truth position
  std::vector<std::array<double, 3>> aligned;      // the estimated position, aligned to the ground truth
};
// Throws InputError when fewer than 3 stamps match.
AteResult ComputeAte(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate);
// Relative pose error over `delta_seconds`: translation (metres) and rotation (degrees).
struct RpeSummary {
  ErrorSummary translation;
  ErrorSummary rotation_deg;
};
RpeSummary ComputeRpe(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                      double delta_seconds = 1.0);

// A synthetic dynamic-scene sequence with exact ground truth, as `hoidslam synth` renders it
// (docs/synthetic-benchmark.md): colour, depth, groundtruth.txt, detections.jsonl, moving-pixel masks.
struct SynthOptions {
  std::string scenario = "walking_xyz";  // a shipped scenario's name, or a .json scenario file
  std::filesystem::path out;             // the folder to create (complete or not at all)
  std::size_t frames = 0;                // render only the first N frames of the camera path (0: all)
  int frame_step = 1;                    // keep every n-th frame
  // The real TUM camera paths (groundtruth/, associations/) the shipped scenarios follow: the shared data's
  // data/tum. Procedural cameras need none.
  std::filesystem::path tum_dir;
  bool force = false;  // replace `out` when it exists and is not empty
  int threads = 2;     // frames rendered in parallel
};
// Renders the sequence and returns how many frames were written. Throws InputError naming the parameter.
std::size_t RenderSynthetic(const SynthOptions& options);

}  // namespace hoidslam
