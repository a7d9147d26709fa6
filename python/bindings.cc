// The Python module hoidslam (its compiled part, hoidslam._hoidslam): the public C++ API (hoidslam.h) with numpy
// arrays in and out. Contiguous rows of uint8 colour and uint16 / float32 depth are read where they lie (no copy);
// results are numpy views of the C++ result they belong to. Tracking releases the GIL. Bad arguments raise
// hoidslam.InputError (a ValueError) with the C++ API's message, which names the argument.
#include <algorithm>
#include <cstdint>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "hoidslam/hoidslam.h"

namespace py = pybind11;

namespace hoidslam::python {
namespace {

std::string DtypeName(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

// What a wrong argument was, for messages: its type's name, never its contents (a list of a frame's pixels prints
// megabytes).
std::string TypeName(const py::handle& value) {
  if (value.is_none()) return "None";
  return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>();
}

// The methods that take frames take every argument as an object and check it here, so that a wrong one raises an
// InputError naming it rather than pybind11's TypeError, which prints every argument given, arrays included.
py::array ArrayArgument(const py::handle& value, const std::string& name, const std::string& expected) {
  if (!py::isinstance<py::array>(value)) {
    throw InputError::ForParameter(name, "must be a numpy array, " + expected + ", got " + TypeName(value));
  }
  return py::reinterpret_borrow<py::array>(value);
}

template <typename T>
T ValueArgument(const py::handle& value, const std::string& name, const std::string& expected) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw InputError::ForParameter(name, "must be " + expected + ", got " + TypeName(value));
  }
}

// None (empty) or a str or os.PathLike.
std::filesystem::path PathArgument(const py::handle& value, const std::string& name) {
  if (value.is_none()) return {};
  if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__")) {
    throw InputError::ForParameter(name, "must be a path (str or os.PathLike) or None, got " + TypeName(value));
  }
  return value.cast<std::filesystem::path>();
}

// None or a list of Detection.
std::vector<Detection> DetectionsArgument(const py::handle& value) {
  std::vector<Detection> detections;
  if (value.is_none()) return detections;
  if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value)) {
    throw InputError::ForParameter("detections", "must be a list of hoidslam.Detection or None, got " + TypeName(value));
  }
  for (const py::handle item : value) {
    if (!py::isinstance<Detection>(item)) {
      throw InputError::ForParameter("detections[" + std::to_string(detections.size()) + "]",
                                     "must be a hoidslam.Detection, got " + TypeName(item));
    }
    detections.push_back(item.cast<Detection>());
  }
  return detections;
}

constexpr const char* kColourShape = "uint8 (height, width, 3) or (height, width)";
constexpr const char* kDepthShape = "(height, width) uint16 or float32";

// `a` (rows × columns [× channels]) as a view of `format`, after checking that its pixels are packed (the rows
// may have any stride, as a crop of a larger image has).
ImageView View(const py::array& a, PixelFormat format, std::size_t channels, std::size_t item, const std::string& name) {
  const std::size_t ndim = channels == 1 ? 2 : 3;
  if (static_cast<std::size_t>(a.ndim()) != ndim || (ndim == 3 && static_cast<std::size_t>(a.shape(2)) != channels)) {
    std::string shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i > 0 ? ", " : "") + std::to_string(a.shape(i));
    throw InputError::ForParameter(
        name, "must have shape (height, width" + std::string(ndim == 3 ? ", 3)" : ")") + ", got (" + shape + ")");
  }
  const bool packed = a.strides(1) == static_cast<py::ssize_t>(channels * item) &&
                      (ndim == 2 || a.strides(2) == static_cast<py::ssize_t>(item));
  if (!packed || a.strides(0) <= 0) {
    throw InputError::ForParameter(name, "pixels must lie packed in each row (a numpy view with steps or reversed "
                                         "rows is not; numpy.ascontiguousarray makes a copy that is)");
  }
  return {a.data(), static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), static_cast<std::size_t>(a.strides(0)),
          format};
}

PixelFormat ParseColourFormat(const std::string& format) {
  if (format == "bgr") return PixelFormat::kBgr;
  if (format == "rgb") return PixelFormat::kRgb;
  throw InputError::ForParameter("format", "must be \"bgr\" or \"rgb\", got \"" + format + "\"");
}

// A colour image: uint8, (h, w, 3) in the channel order `format` says, or (h, w) grey.
ImageView ColourView(const py::array& a, const std::string& format, const std::string& name) {
  if (a.dtype().num() != py::dtype::of<std::uint8_t>().num()) {
    throw InputError::ForParameter(name, "dtype must be uint8, got " + DtypeName(a));
  }
  if (a.ndim() == 2) return View(a, PixelFormat::kGray, 1, 1, name);
  return View(a, ParseColourFormat(format), 3, 1, name);
}

// A depth image: (h, w) uint16 in units of 1 / depth_factor metres, or float32 metres.
ImageView DepthView(const py::array& a, const std::string& name) {
  const int num = a.dtype().num();
  if (num == py::dtype::of<std::uint16_t>().num()) return View(a, PixelFormat::kDepthUint16, 1, 2, name);
  if (num == py::dtype::of<float>().num()) return View(a, PixelFormat::kDepthFloat32, 1, 4, name);
  throw InputError::ForParameter(name, "dtype must be uint16 (depth units) or float32 (metres), got " + DtypeName(a));
}

// What `read` returns, called with the GIL released: reading a System waits for a frame another thread tracks.
template <typename Read>
auto WithoutGil(Read read) {
  py::gil_scoped_release release;
  return read();
}

// N × 8 rows (t, tx, ty, tz, qx, qy, qz, qw), as a TUM trajectory file and numpy.loadtxt of it hold them.
std::vector<StampedPose> ToPoses(const py::array& a, const std::string& name) {
  if (a.ndim() != 2 || a.shape(1) != 8) {
    throw InputError::ForParameter(name, "must be an N x 8 array of rows t tx ty tz qx qy qz qw");
  }
  const auto rows = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!rows) throw InputError::ForParameter(name, "must hold numbers, got " + DtypeName(a));
  const auto r = rows.unchecked<2>();
  std::vector<StampedPose> poses(static_cast<std::size_t>(r.shape(0)));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) {
    poses[i] = {r(i, 0), {r(i, 1), r(i, 2), r(i, 3)}, {r(i, 4), r(i, 5), r(i, 6), r(i, 7)}};
  }
  return poses;
}

py::array_t<double> ToArray(const std::vector<StampedPose>& poses) {
  py::array_t<double> a({static_cast<py::ssize_t>(poses.size()), py::ssize_t{8}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const StampedPose& p = poses[i];
    const double row[8] = {p.timestamp,   p.translation[0], p.translation[1], p.translation[2],
                           p.rotation[0], p.rotation[1],    p.rotation[2],    p.rotation[3]};
    for (py::ssize_t k = 0; k < 8; ++k) r(static_cast<py::ssize_t>(i), k) = row[k];
  }
  return a;
}

py::array_t<double> Positions(const std::vector<std::array<double, 3>>& positions) {
  py::array_t<double> a({static_cast<py::ssize_t>(positions.size()), py::ssize_t{3}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < positions.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) r(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k)) = positions[i][k];
  }
  return a;
}

// A numpy view of `data` (owned by the C++ object behind `owner`), which keeps `owner` alive.
template <typename T>
py::array ViewOf(const T* data, std::vector<py::ssize_t> shape, const py::object& owner,
                 py::dtype dtype = py::dtype::of<T>()) {
  std::vector<py::ssize_t> strides(shape.size(), sizeof(T));
  for (std::size_t i = shape.size() - 1; i > 0; --i) strides[i - 1] = strides[i] * shape[i];
  py::array a(dtype, shape, strides, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;  // results are read only
  return a;
}

DetectorKind ParseDetectorKind(const std::string& kind) {
  if (kind == "given") return DetectorKind::kGiven;
  if (kind == "onnx") return DetectorKind::kOnnx;
  if (kind == "none") return DetectorKind::kNone;
  throw InputError::ForParameter("detector", "must be \"given\", \"onnx\" or \"none\", got \"" + kind + "\"");
}

std::string DetectionRepr(const Detection& d) {
  return "Detection('" + d.label + "', score=" + py::repr(py::float_(d.score)).cast<std::string>() + ", box=(" +
         std::to_string(d.box.x) + ", " + std::to_string(d.box.y) + ", " + std::to_string(d.box.width) + ", " +
         std::to_string(d.box.height) + "))";
}

py::tuple BoxTuple(const Box& b) { return py::make_tuple(b.x, b.y, b.width, b.height); }
Box ToBox(const std::vector<float>& v) {
  if (v.size() != 4) throw InputError::ForParameter("box", "must be (x, y, width, height)");
  return {v[0], v[1], v[2], v[3]};
}

}  // namespace
}  // namespace hoidslam::python

PYBIND11_MODULE(_hoidslam, m) {
  using namespace hoidslam;
  using namespace hoidslam::python;
  m.doc() = "hoidslam: RGB-D SLAM that drops the features of people and of the objects in their hands (HOID).";

  // Registered base first: pybind11 tries the newest translator first, so InputError is matched before Error.
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.doc() = "Base of hoidslam's errors.";
  // Both a hoidslam.Error (every error of the module) and a ValueError (what Python calls bad input).
  static py::exception<InputError> input_error(m, "InputError", py::make_tuple(error, py::handle(PyExc_ValueError)));
  input_error.doc() = "Bad input: the message names the argument, or the file and line.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  m.def("version", &Version, "The library's version, \"major.minor.patch\".");
  m.def("shipped_dir", &ShippedDir,
        "Where hoidslam's shipped files are: config/*.yaml (settings) and data/vocabulary/. "
        "<prefix>/share/hoidslam when installed, else the source tree.");
  m.def(
      "settings_for",
      [](const std::filesystem::path& folder) -> std::optional<std::filesystem::path> {
        std::filesystem::path settings = SettingsForSequence(folder);
        if (settings.empty()) return std::nullopt;
        return settings;
      },
      py::arg("folder"),
      "The shipped settings file a TUM or Bonn folder's name calls for, as hoidslam run chooses it without "
      "--settings (freiburg1 or fr1_ → config/TUM1.yaml, ..., bonn → Bonn.yaml); None for any other name.");

  py::class_<Camera>(m, "Camera", R"(A camera given by its values, as its SDK reports them: the colour camera's
intrinsics at the resolution it streams, with depth registered to it pixel for pixel.

fx, fy, cx, cy: pixels; width, height: the image size; distortion: (k1, k2, p1, p2, k3), OpenCV's order;
depth_scale: metres per unit of uint16 depth (0.001 for millimetres: RealSense's get_depth_scale(), OpenNI, Azure
Kinect); baseline: metres between the depth camera's projector and sensor (points nearer than 40 baselines count as
close).)")
      .def(py::init([](const py::object& fx, const py::object& fy, const py::object& cx, const py::object& cy,
                       const py::object& width, const py::object& height, const py::object& distortion,
                       const py::object& depth_scale, const py::object& baseline) {
             const auto number = [](const py::object& value, const char* name) {
               return ValueArgument<double>(value, std::string("camera.") + name, "a number");
             };
             const auto pixels = [](const py::object& value, const char* name) {
               return ValueArgument<int>(value, std::string("camera.") + name, "an int");
             };
             return Camera{number(fx, "fx"),
                           number(fy, "fy"),
                           number(cx, "cx"),
                           number(cy, "cy"),
                           ValueArgument<std::array<double, 5>>(distortion, "camera.distortion",
                                                                "5 numbers k1, k2, p1, p2, k3"),
                           pixels(width, "width"),
                           pixels(height, "height"),
                           number(depth_scale, "depth_scale"),
                           number(baseline, "baseline")};
           }),
           py::kw_only(), py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("width"),
           py::arg("height"), py::arg("distortion") = std::array<double, 5>{}, py::arg("depth_scale") = 0.001,
           py::arg("baseline") = 0.075)
      .def_readwrite("fx", &Camera::fx)
      .def_readwrite("fy", &Camera::fy)
      .def_readwrite("cx", &Camera::cx)
      .def_readwrite("cy", &Camera::cy)
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height)
      .def_readwrite("distortion", &Camera::distortion)
      .def_readwrite("depth_scale", &Camera::depth_scale)
      .def_readwrite("baseline", &Camera::baseline)
      .def("__repr__", [](const Camera& c) {
        std::ostringstream repr;
        repr << "Camera(fx=" << c.fx << ", fy=" << c.fy << ", cx=" << c.cx << ", cy=" << c.cy << ", width=" << c.width
             << ", height=" << c.height << ", distortion=(" << c.distortion[0];
        for (std::size_t k = 1; k < c.distortion.size(); ++k) repr << ", " << c.distortion[k];
        repr << "), depth_scale=" << c.depth_scale << ", baseline=" << c.baseline << ")";
        return repr.str();
      });

  py::class_<Detection>(m, "Detection", "One object a detector found: label (COCO name), box (x, y, width, height) "
                                        "in pixels, score, class_id (-1 if unknown).")
      .def(py::init([](std::string label, const std::vector<float>& box, float score, int class_id) {
             return Detection{std::move(label), score, ToBox(box), class_id};
           }),
           py::arg("label"), py::arg("box"), py::arg("score") = 1.0F, py::arg("class_id") = -1)
      .def_readwrite("label", &Detection::label)
      .def_readwrite("score", &Detection::score)
      .def_property("box", [](const Detection& d) { return BoxTuple(d.box); },
                    [](Detection& d, const std::vector<float>& box) { d.box = ToBox(box); },
                    "(x, y, width, height), pixels")
      .def_readwrite("class_id", &Detection::class_id)
      .def("__repr__", &DetectionRepr);

  py::class_<JudgedBox>(m, "JudgedBox", "The HOID filter's verdict on one box (docs/hoid.md).")
      .def_readonly("detection", &JudgedBox::detection)
      .def_readonly("dynamic", &JudgedBox::dynamic, "its features are dropped")
      .def_readonly("reason", &JudgedBox::reason, "person, interaction, no_interaction, depth_rejected, ...")
      .def_readonly("person", &JudgedBox::person, "for a handled object: the index of its person's box, else -1")
      .def_readonly("interaction", &JudgedBox::interaction, "area(object & person) / area(object)")
      .def("__repr__", [](const JudgedBox& b) {
        return "JudgedBox(" + DetectionRepr(b.detection) + ", " + (b.dynamic ? "dynamic" : "static") + ": " +
               b.reason + ")";
      });

  py::class_<FrameResult>(m, "FrameResult", "What one frame went through. Arrays are read-only views into it.")
      .def_readonly("index", &FrameResult::index)
      .def_readonly("timestamp", &FrameResult::timestamp)
      .def_property_readonly("state", [](const FrameResult& r) { return std::string(ToString(r.state)); },
                             "ok, provisional (found again after a loss, not yet confirmed), lost or not_initialized")
      .def_property_readonly(
          "pose",
          [](const FrameResult& r) -> std::optional<py::array_t<double>> {
            if (!r.T_wc) return std::nullopt;
            py::array_t<double> pose({4, 4});
            std::copy(r.T_wc->begin(), r.T_wc->end(), pose.mutable_data());
            return pose;
          },
          "4 x 4 camera-to-world transform (T_wc), or None when the frame was not tracked")
      .def_readonly("method", &FrameResult::method)
      .def_readonly("failure", &FrameResult::failure)
      .def_readonly("rejection", &FrameResult::rejection, "why the last pose tried was refused, or empty")
      .def_readonly("withdrawn", &FrameResult::withdrawn,
                    "indices of frames tracked provisionally that this frame refuted: they are lost after all")
      .def_readonly("keyframe", &FrameResult::keyframe)
      .def_readonly("map", &FrameResult::map,
                    "the map it was tracked in: 0 unless tracking was lost long in new ground and started another")
      .def_readonly("boxes", &FrameResult::boxes, "every box judged, with the verdict")
      .def_property_readonly(
          "keypoints",
          [](py::object self) {
            const FrameResult& r = self.cast<const FrameResult&>();
            return ViewOf(r.keypoints.xy.data(), {static_cast<py::ssize_t>(r.keypoints.size()), 2}, self);
          },
          "N x 2 float32: x, y of every keypoint judged (kept and dropped), pixels")
      .def_property_readonly(
          "kept",
          [](py::object self) {
            const FrameResult& r = self.cast<const FrameResult&>();
            return ViewOf(r.keypoints.kept.data(), {static_cast<py::ssize_t>(r.keypoints.size())}, self,
                          py::dtype("bool"));
          },
          "N bool: the keypoint was used for tracking")
      .def_property_readonly(
          "keypoint_box",
          [](py::object self) {
            const FrameResult& r = self.cast<const FrameResult&>();
            return ViewOf(r.keypoints.box.data(), {static_cast<py::ssize_t>(r.keypoints.size())}, self);
          },
          "N int32: for a dropped keypoint the index in boxes of the dynamic box that dropped it, else -1")
      .def(
          "drop_reasons",
          [](const FrameResult& r) {
            std::vector<std::string> reasons;
            reasons.reserve(r.keypoints.size());
            for (std::size_t i = 0; i < r.keypoints.size(); ++i) reasons.emplace_back(r.DropReason(i));
            return reasons;
          },
          "Per keypoint: why it was dropped (its box's reason, \"mask\" for none), \"\" when kept.")
      .def_readonly("extracted", &FrameResult::extracted)
      .def_readonly("dropped", &FrameResult::dropped)
      .def_readonly("matched", &FrameResult::matched)
      .def_readonly("inliers", &FrameResult::inliers)
      .def_readonly("milliseconds", &FrameResult::milliseconds)
      .def("__repr__", [](const FrameResult& r) {
        return "FrameResult(index=" + std::to_string(r.index) + ", state=" + std::string(ToString(r.state)) +
               ", keypoints=" + std::to_string(r.keypoints.size()) + ", dropped=" + std::to_string(r.dropped) + ")";
      });

  py::class_<System>(m, "System", R"(One SLAM session: frames in, in time order; poses, trajectory and map out.

settings: ORB-SLAM3-style YAML with a HOID section (shipped_dir()/"config/TUM3.yaml"); None: TUM fr3 defaults.
camera: a Camera from the SDK's values; replaces the settings' camera, depth factor and baseline.
filter: none, person, classes, hoid2d, hoid3d, hoidplus[:parts]; "": the settings' HOID.mode, else hoidplus.
detector: "given" (pass each frame's detections to track), "onnx" (model runs inside), "none".
realtime: the detector in its own thread; deterministic: byte-identical results on every run.
load_map: a map file (save_map, hoidslam run --save-map) to start from; localization: track against it unchanged.
view: a live viewer in the browser (docs/viewer.md): True serves it on port 8787, a number on that port (0: any
free one); viewer_url says where. view_address: 127.0.0.1 (this machine only), or 0.0.0.0 for every machine.
dense: save also writes the static world densely (docs/dense.md): True at 1 cm voxels, a number at that voxel size (m).
Threads may share it: track calls run one at a time (a frame not newer than the last one tracked raises an
InputError naming timestamp), and trajectory(), keyframes() and map_points() read between two frames.)")
      .def(py::init([](const py::object& settings, const py::object& camera, const py::object& filter,
                       const py::object& detector, const py::object& model, const py::object& realtime,
                       const py::object& deterministic, const py::object& keypoint_budget,
                       const py::object& vocabulary, const py::object& load_map, const py::object& localization,
                       const py::object& view, const py::object& view_address, const py::object& dense) {
             Options options;
             options.settings = PathArgument(settings, "settings");
             if (!camera.is_none()) {
               if (!py::isinstance<Camera>(camera)) {
                 throw InputError::ForParameter("camera", "must be a hoidslam.Camera or None, got " + TypeName(camera));
               }
               options.camera = camera.cast<Camera>();
             }
             options.filter = ValueArgument<std::string>(filter, "filter", "a str");
             options.detector = ParseDetectorKind(ValueArgument<std::string>(detector, "detector", "a str"));
             options.model = PathArgument(model, "model");
             options.realtime = ValueArgument<bool>(realtime, "realtime", "True or False");
             options.deterministic = ValueArgument<bool>(deterministic, "deterministic", "True or False");
             options.keypoint_budget = ValueArgument<std::string>(keypoint_budget, "keypoint_budget", "a str");
             options.vocabulary = PathArgument(vocabulary, "vocabulary");
             options.load_map = PathArgument(load_map, "load_map");
             options.localization = ValueArgument<bool>(localization, "localization", "True or False");
             if (py::isinstance<py::bool_>(view)) {
               if (view.cast<bool>()) options.view.emplace();
             } else if (py::isinstance<py::int_>(view)) {
               options.view.emplace().port = view.cast<int>();
             } else {
               throw InputError::ForParameter("view", "must be True, False or a port number, got " + TypeName(view));
             }
             if (options.view) options.view->address = ValueArgument<std::string>(view_address, "view_address", "a str");
             if (py::isinstance<py::bool_>(dense)) {
               if (dense.cast<bool>()) options.dense.emplace();
             } else if (py::isinstance<py::float_>(dense) || py::isinstance<py::int_>(dense)) {
               options.dense.emplace().voxel_size = dense.cast<double>();
             } else {
               throw InputError::ForParameter("dense", "must be True, False or a voxel size in metres, got " +
                                                           TypeName(dense));
             }
             py::gil_scoped_release release;  // loading the vocabulary and the model takes a moment
             return System(options);
           }),
           py::kw_only(), py::arg("settings") = py::none(), py::arg("camera") = py::none(), py::arg("filter") = "", py::arg("detector") = "given",
           py::arg("model") = py::none(), py::arg("realtime") = false, py::arg("deterministic") = false,
           py::arg("keypoint_budget") = "static", py::arg("vocabulary") = py::none(), py::arg("load_map") = py::none(),
           py::arg("localization") = false, py::arg("view") = false, py::arg("view_address") = "127.0.0.1",
           py::arg("dense") = false)
      .def(
          "track",
          [](System& system, const py::object& rgb, const py::object& depth, const py::object& timestamp,
             const py::object& detections, const py::object& format, const py::object& depth_delay) {
            const py::array rgb_array = ArrayArgument(rgb, "rgb", kColourShape);
            const py::array depth_array = ArrayArgument(depth, "depth", kDepthShape);
            const ImageView colour = ColourView(rgb_array, ValueArgument<std::string>(format, "format", "a str"), "rgb");
            const ImageView depth_view = DepthView(depth_array, "depth");
            const double t = ValueArgument<double>(timestamp, "timestamp", "a number of seconds");
            const double delay = ValueArgument<double>(depth_delay, "depth_delay", "a number of seconds");
            const std::vector<Detection> boxes = DetectionsArgument(detections);
            py::gil_scoped_release release;
            return system.Track(colour, depth_view, t, boxes, delay);
          },
          py::arg("rgb"), py::arg("depth"), py::arg("timestamp"), py::arg("detections") = py::none(),
          py::arg("format") = "bgr", py::arg("depth_delay") = 0.0,
          R"(Tracks the next frame; returns a FrameResult.

rgb: uint8 (height, width, 3) in `format` order ("bgr" as OpenCV, "rgb" as most SDKs) or (height, width) grey.
depth: (height, width) uint16 in units of 1/depth_factor metres, or float32 metres; the camera's size.
timestamp: seconds, increasing. detections: the frame's boxes (detector "given"), a list of Detection.
depth_delay: seconds from the colour to the depth image when the camera takes them apart (a recorded
Frame's depth_delay); hoidplus's safety net does not judge what the camera moved over it.
Arrays are read in place when their rows hold packed pixels; the GIL is released while tracking.)")
      .def("finish", &System::Finish, py::call_guard<py::gil_scoped_release>(),
           "Lets local mapping finish and adjusts the map once more, as hoidslam run does: the trajectory and map are "
           "final. Idempotent.")
      .def(
          "trajectory", [](const System& s) { return ToArray(WithoutGil([&] { return s.Trajectory(); })); },
          "N x 8 float64 rows t tx ty tz qx qy qz qw (camera to world), every tracked frame: trajectory.txt's rows.")
      .def(
          "keyframes", [](const System& s) { return ToArray(WithoutGil([&] { return s.KeyFrames(); })); },
          "The keyframes, as trajectory().")
      .def(
          "map_points",
          [](const System& s) {
            const std::vector<MapPoint> points = WithoutGil([&] { return s.MapPoints(); });
            const auto n = static_cast<py::ssize_t>(points.size());
            py::array_t<double> positions({n, py::ssize_t{3}});
            py::array_t<std::uint8_t> colours({n, py::ssize_t{3}});
            py::array_t<int> observations(n);
            for (py::ssize_t i = 0; i < n; ++i) {
              for (py::ssize_t k = 0; k < 3; ++k) {
                positions.mutable_at(i, k) = points[i].position[k];
                colours.mutable_at(i, k) = points[i].rgb[k];
              }
              observations.mutable_at(i) = points[i].observations;
            }
            return py::make_tuple(positions, colours, observations);
          },
          "(positions N x 3 metres, colours N x 3 uint8 RGB, observations N) of the map points.")
      .def("save", &System::Save, py::arg("folder"), py::call_guard<py::gil_scoped_release>(),
           "Finishes, then writes what hoidslam run writes into folder: trajectory.txt, keyframes.txt, map.ply, "
           "frames.jsonl, summary.json and report.html (hoidslam report and bench read it).")
      .def("save_map", &System::SaveMap, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
           "Finishes, then writes the map to a map file that System(load_map=...) and hoidslam run --load-map start "
           "from.")
      .def("reset", &System::Reset, py::call_guard<py::gil_scoped_release>(),
           "Back to no frames, as a new System with the same options; the next frame may have any timestamp.")
      .def_property_readonly("width", &System::width)
      .def_property_readonly("height", &System::height)
      .def_property_readonly("depth_factor", &System::depth_factor, "uint16 depth units per metre")
      .def_property_readonly("filter", &System::filter)
      .def_property_readonly("viewer_url", &System::ViewerUrl,
                             "Where the live viewer's page is (http://address:port/); \"\" without view")
      .def("__enter__", [](System& s) -> System& { return s; }, py::return_value_policy::reference)
      .def("__exit__", [](System& s, const py::args&) {
        py::gil_scoped_release release;
        s.Finish();
      });

  py::class_<Frame>(m, "Frame", "A recorded frame; rgb and depth are views into it.")
      .def_readonly("timestamp", &Frame::timestamp)
      .def_readonly("depth_delay", &Frame::depth_delay, "seconds from the colour image to the depth image")
      .def_readonly("rgb_path", &Frame::rgb_path)
      .def_property_readonly(
          "rgb",
          [](py::object self) {
            const Frame& f = self.cast<const Frame&>();
            return ViewOf(f.rgb.data(), {f.height, f.width, 3}, self);
          },
          "(height, width, 3) uint8, BGR (OpenCV's order; [..., ::-1] for RGB)")
      .def_property_readonly(
          "depth",
          [](py::object self) {
            const Frame& f = self.cast<const Frame&>();
            return ViewOf(f.depth.data(), {f.height, f.width}, self);
          },
          "(height, width) float32, metres; 0 where the sensor gave none");

  py::class_<Sequence>(m, "Sequence", R"(A recorded sequence: a TUM RGB-D / Bonn download or a `hoidslam synth` folder.

for frame in Sequence(folder): frame.timestamp, frame.rgb, frame.depth. Frames are read on demand.)")
      .def(py::init<const std::filesystem::path&, double>(), py::arg("folder"), py::arg("depth_factor") = 5000.0)
      .def("__len__", &Sequence::size)
      .def(
          "__getitem__",
          [](const Sequence& s, py::ssize_t index) {
            const auto size = static_cast<py::ssize_t>(s.size());
            if (index < 0) index += size;
            if (index < 0 || index >= size) throw py::index_error("frame index out of range");
            py::gil_scoped_release release;
            return s.Load(static_cast<std::size_t>(index));
          },
          py::arg("index"))
      .def_property_readonly("name", &Sequence::name)
      .def_property_readonly("root", &Sequence::root)
      .def("timestamps", [](const Sequence& s) { return py::array_t<double>(py::cast(s.Timestamps())); })
      .def("groundtruth", [](const Sequence& s) { return ToArray(s.Groundtruth()); },
           "groundtruth.txt as an N x 8 array (t tx ty tz qx qy qz qw); empty when there is none.");

  py::class_<DetectionsFile>(m, "DetectionsFile", R"(A detections file (docs/detections-file.md): the boxes of any
detector for a whole sequence, by timestamp, as `hoidslam detect` or another tool writes them.)")
      .def(py::init<const std::filesystem::path&>(), py::arg("path"))
      .def(
          "find",
          [](const DetectionsFile& file, double timestamp) {
            std::optional<std::vector<Detection>> found = file.Find(timestamp);
            if (!found && file.missed() == 1) {
              std::ostringstream warning;
              warning << file.path().string() << ": no line for timestamp " << std::fixed << std::setprecision(6)
                      << timestamp << " (within 1 ms): that frame gets no boxes; further misses are counted in "
                      << "DetectionsFile.missed, not warned";
              py::module_::import("warnings").attr("warn")(warning.str());
            }
            return found;
          },
          py::arg("timestamp"),
          "The detections of the frame at timestamp (within 1 ms, so timestamps rounded to the millisecond match); "
          "None when the file has no such frame: the first time with a warning, each time counted in missed.")
      .def_property_readonly("missed", &DetectionsFile::missed, "How many calls of find found no frame.")
      .def_property_readonly("path", &DetectionsFile::path)
      .def("__len__", &DetectionsFile::size);

  py::class_<Detector>(m, "Detector", "A YOLO-family ONNX model (YOLOX, YOLOv5, YOLOv8, YOLO11) run by OpenCV.")
      .def(py::init<const std::filesystem::path&, float, float>(), py::arg("model"), py::arg("confidence") = 0.25F,
           py::arg("nms") = 0.45F)
      .def(
          "detect",
          [](Detector& d, const py::object& rgb, const py::object& format) {
            const py::array array = ArrayArgument(rgb, "rgb", kColourShape);
            const ImageView view = ColourView(array, ValueArgument<std::string>(format, "format", "a str"), "rgb");
            py::gil_scoped_release release;
            return d.Detect(view);
          },
          py::arg("rgb"), py::arg("format") = "bgr", "The detections in a colour image, best score first.")
      .def_property_readonly("name", &Detector::Name);

  m.def(
      "judge_boxes",
      [](const std::vector<Detection>& detections, const std::string& mode, double min_interaction_area,
         double depth_threshold, const std::optional<py::array>& depth, double depth_factor) {
        const FilterOptions options{mode, min_interaction_area, depth_threshold};
        if (!depth) return JudgeBoxes(detections, options);
        const ImageView view = DepthView(*depth, "depth");
        return JudgeBoxes(detections, options, &view, depth_factor);
      },
      py::arg("detections"), py::arg("mode") = "hoid2d", py::arg("min_interaction_area") = 0.4,
      py::arg("depth_threshold") = 0.2, py::arg("depth") = py::none(), py::arg("depth_factor") = 5000.0,
      "The HOID filter on its own: one JudgedBox per detection (mode none, person, classes, hoid2d, hoid3d; "
      "hoid3d reads depth).");

  py::class_<ErrorSummary>(m, "ErrorSummary", "Statistics of an error over the matched poses.")
      .def_readonly("rmse", &ErrorSummary::rmse)
      .def_readonly("mean", &ErrorSummary::mean)
      .def_readonly("median", &ErrorSummary::median)
      .def_readonly("std", &ErrorSummary::std)
      .def_readonly("min", &ErrorSummary::min)
      .def_readonly("max", &ErrorSummary::max)
      .def_readonly("count", &ErrorSummary::count)
      .def("__repr__", [](const ErrorSummary& e) {
        return "ErrorSummary(rmse=" + std::to_string(e.rmse) + ", count=" + std::to_string(e.count) + ")";
      });
  py::class_<AteResult>(m, "AteResult", "Absolute trajectory error, with every matched pair for plots.")
      .def_readonly("error", &AteResult::error, "metres")
      .def_property_readonly("rmse", [](const AteResult& a) { return a.error.rmse; }, "metres")
      .def_property_readonly("timestamps", [](const AteResult& a) { return py::array_t<double>(py::cast(a.timestamps)); },
                             "N: the estimate's timestamp of each matched pair")
      .def_property_readonly("groundtruth", [](const AteResult& a) { return Positions(a.groundtruth); },
                             "N x 3 ground-truth positions")
      .def_property_readonly("aligned", [](const AteResult& a) { return Positions(a.aligned); },
                             "N x 3 estimated positions aligned to the ground truth")
      .def("__repr__", [](const AteResult& a) {
        return "AteResult(rmse=" + std::to_string(a.error.rmse) + ", count=" + std::to_string(a.error.count) + ")";
      });
  py::class_<RpeSummary>(m, "RpeSummary", "Relative pose error: translation (metres), rotation (degrees).")
      .def_readonly("translation", &RpeSummary::translation)
      .def_readonly("rotation_deg", &RpeSummary::rotation_deg);
  m.def(
      "ate",
      [](const py::array& groundtruth, const py::array& estimate) {
        return ComputeAte(ToPoses(groundtruth, "groundtruth"), ToPoses(estimate, "estimate"));
      },
      py::arg("groundtruth"), py::arg("estimate"),
      "Absolute trajectory error (metres) as TUM's evaluate_ate.py: both N x 8 (t tx ty tz qx qy qz qw).");
  m.def(
      "rpe",
      [](const py::array& groundtruth, const py::array& estimate, double delta) {
        return ComputeRpe(ToPoses(groundtruth, "groundtruth"), ToPoses(estimate, "estimate"), delta);
      },
      py::arg("groundtruth"), py::arg("estimate"), py::arg("delta") = 1.0,
      "Relative pose error over delta seconds, as TUM's evaluate_rpe.py.");
  m.def(
      "render_synthetic",
      [](const std::filesystem::path& out, const std::string& scenario, std::size_t frames, int frame_step,
         const std::optional<std::filesystem::path>& tum_dir, bool force, int threads) {
        SynthOptions options;
        options.out = out;
        options.scenario = scenario;
        options.frames = frames;
        options.frame_step = frame_step;
        options.tum_dir = tum_dir.value_or("");
        options.force = force;
        options.threads = threads;
        py::gil_scoped_release release;
        return RenderSynthetic(options);
      },
      py::arg("out"), py::arg("scenario") = "walking_xyz", py::arg("frames") = 0, py::arg("frame_step") = 1,
      py::arg("tum_dir") = py::none(), py::arg("force") = false, py::arg("threads") = 2,
      "Renders a synthetic sequence with exact ground truth (as hoidslam synth); returns the frames written. "
      "tum_dir: the real TUM camera paths (the shared data's data/tum) the shipped scenarios follow.");
}
