"""Type stubs of hoidslam's compiled module (bindings.cc): what editors complete and type checkers check."""

from os import PathLike
from pathlib import Path
from typing import Iterator, Sequence as _Seq

import numpy as np
import numpy.typing as npt

_Path = str | PathLike[str]

class Error(RuntimeError):
    """Base of hoidslam's errors."""

class InputError(Error, ValueError):
    """Bad input: the message names the argument, or the file and line."""

def version() -> str:
    """The library's version, "major.minor.patch"."""

def shipped_dir() -> Path:
    """Where hoidslam's shipped files are: config/*.yaml and data/vocabulary/ (<prefix>/share/hoidslam when
    installed, else the source tree)."""

def settings_for(folder: _Path) -> Path | None:
    """The shipped settings file a TUM or Bonn folder's name calls for, as hoidslam run chooses it without
    --settings (freiburg1 or fr1_ → config/TUM1.yaml, ..., bonn → Bonn.yaml); None for any other name."""

class Camera:
    """A camera given by its values, as its SDK reports them: the colour camera's intrinsics at the resolution it
    streams, depth registered to it. depth_scale: metres per uint16 depth unit (0.001: millimetres); baseline: metres
    between the depth camera's projector and sensor."""

    fx: float
    fy: float
    cx: float
    cy: float
    width: int
    height: int
    distortion: tuple[float, float, float, float, float]
    depth_scale: float
    baseline: float
    def __init__(
        self,
        *,
        fx: float,
        fy: float,
        cx: float,
        cy: float,
        width: int,
        height: int,
        distortion: _Seq[float] = (0.0, 0.0, 0.0, 0.0, 0.0),
        depth_scale: float = 0.001,
        baseline: float = 0.075,
    ) -> None: ...

class Detection:
    """One object a detector found: label (COCO name), box (x, y, width, height) in pixels, score, class_id."""

    label: str
    score: float
    box: tuple[float, float, float, float]
    class_id: int
    def __init__(self, label: str, box: _Seq[float], score: float = 1.0, class_id: int = -1) -> None: ...

class JudgedBox:
    """The HOID filter's verdict on one box (docs/hoid.md)."""

    @property
    def detection(self) -> Detection: ...
    @property
    def dynamic(self) -> bool:
        """Its features are dropped."""
    @property
    def reason(self) -> str:
        """person, interaction, no_interaction, depth_rejected, depth_confirmed, ..."""
    @property
    def person(self) -> int:
        """For a handled object: the index of its person's box in the same list; else -1."""
    @property
    def interaction(self) -> float:
        """area(object & person) / area(object) with that person."""

class FrameResult:
    """What one frame went through. Arrays are read-only views into the result."""

    @property
    def index(self) -> int: ...
    @property
    def timestamp(self) -> float: ...
    @property
    def state(self) -> str:
        """ok, lost or not_initialized."""
    @property
    def pose(self) -> npt.NDArray[np.float64] | None:
        """4 x 4 camera-to-world transform (T_wc), None when the frame was not tracked."""
    @property
    def method(self) -> str:
        """initialization, motion_model, reference_keyframe, relocalization or none."""
    @property
    def failure(self) -> str:
        """Why a lost frame was lost: too_few_keypoints, too_few_matches, pose_rejected; else ""."""
    @property
    def keyframe(self) -> bool: ...
    @property
    def map(self) -> int:
        """The map it was tracked in: 0 unless tracking was lost long in new ground and started another."""
    @property
    def boxes(self) -> list[JudgedBox]: ...
    @property
    def keypoints(self) -> npt.NDArray[np.float32]:
        """N x 2: x, y of every keypoint judged (kept and dropped), pixels."""
    @property
    def kept(self) -> npt.NDArray[np.bool_]:
        """N: the keypoint was used for tracking."""
    @property
    def keypoint_box(self) -> npt.NDArray[np.int32]:
        """N: for a dropped keypoint the index in boxes of the box that dropped it, else -1."""
    def drop_reasons(self) -> list[str]:
        """Per keypoint: its box's reason when dropped ("mask" for none), "" when kept."""
    @property
    def extracted(self) -> int: ...
    @property
    def dropped(self) -> int: ...
    @property
    def matched(self) -> int: ...
    @property
    def inliers(self) -> int: ...
    @property
    def milliseconds(self) -> float:
        """Extraction, detections, filter and tracking of this frame."""

class System:
    """One SLAM session: frames in, in time order; poses, trajectory and map out."""

    def __init__(
        self,
        *,
        settings: _Path | None = None,
        camera: Camera | None = None,
        filter: str = "",
        detector: str = "given",
        model: _Path | None = None,
        realtime: bool = False,
        deterministic: bool = False,
        keypoint_budget: str = "static",
        vocabulary: _Path | None = None,
        load_map: _Path | None = None,
        localization: bool = False,
        view: bool | int = False,
        view_address: str = "127.0.0.1",
        dense: bool | float = False,
    ) -> None:
        """settings: ORB-SLAM3-style YAML (shipped_dir()/"config/TUM3.yaml"); None: TUM fr3 defaults.
        camera: a Camera from the SDK's values, in place of the settings' camera, depth factor and baseline.
        filter: none, person, classes, hoid2d, hoid3d, hoidplus; "": the settings' HOID.mode, else hoidplus.
        detector: "given" (detections passed to track), "onnx" (model runs inside), "none".
        realtime: the detector in its own thread. deterministic: byte-identical results on every run.
        view: the live viewer in a browser: True on port 8787, a number on that port (0: any free one).
        dense: save also writes the static world densely (mesh.ply, cloud.ply, occupancy.*): True at 1 cm voxels,
        a number at that voxel size in metres."""
    def track(
        self,
        rgb: npt.NDArray[np.uint8],
        depth: npt.NDArray[np.uint16] | npt.NDArray[np.float32],
        timestamp: float,
        detections: list[Detection] | None = None,
        format: str = "bgr",
    ) -> FrameResult:
        """Tracks the next frame. rgb: (h, w, 3) uint8 in `format` order ("bgr" or "rgb") or (h, w) grey;
        depth: (h, w) uint16 units of 1/depth_factor m or float32 metres, the camera's size; timestamp: seconds,
        increasing; detections: the frame's boxes (detector "given"). Read in place; the GIL is released."""
    def finish(self) -> None:
        """Lets local mapping finish: the trajectory and map are final. Idempotent."""
    def trajectory(self) -> npt.NDArray[np.float64]:
        """N x 8 rows t tx ty tz qx qy qz qw (camera to world) of every tracked frame, as trajectory.txt."""
    def keyframes(self) -> npt.NDArray[np.float64]:
        """The keyframes, as trajectory()."""
    def map_points(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.uint8], npt.NDArray[np.int32]]:
        """(positions N x 3 metres, colours N x 3 RGB, observations N)."""
    def save(self, folder: _Path) -> None:
        """Finishes, then writes what hoidslam run writes into folder: trajectory.txt, keyframes.txt, map.ply,
        frames.jsonl, summary.json and report.html."""
    def save_map(self, path: _Path) -> None:
        """Finishes, then writes the map to a map file System(load_map=...) starts from."""
    def reset(self) -> None:
        """Back to no frames, as a new System with the same options."""
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def depth_factor(self) -> float:
        """uint16 depth units per metre (DepthMapFactor)."""
    @property
    def filter(self) -> str: ...
    @property
    def viewer_url(self) -> str:
        """Where the live viewer's page is (http://address:port/); "" without view."""
    def __enter__(self) -> System: ...
    def __exit__(self, *args: object) -> None: ...

class Frame:
    """A recorded frame; rgb and depth are views into it."""

    @property
    def timestamp(self) -> float: ...
    @property
    def rgb_path(self) -> str: ...
    @property
    def rgb(self) -> npt.NDArray[np.uint8]:
        """(h, w, 3) BGR (OpenCV's order; rgb[..., ::-1] for RGB)."""
    @property
    def depth(self) -> npt.NDArray[np.float32]:
        """(h, w) metres; 0 where the sensor gave none."""

class Sequence:
    """A TUM RGB-D / Bonn download or a `hoidslam synth` folder; frames are read on demand."""

    def __init__(self, folder: _Path, depth_factor: float = 5000.0) -> None: ...
    def __len__(self) -> int: ...
    def __getitem__(self, index: int) -> Frame: ...
    def __iter__(self) -> Iterator[Frame]: ...
    @property
    def name(self) -> str: ...
    @property
    def root(self) -> Path: ...
    def timestamps(self) -> npt.NDArray[np.float64]: ...
    def groundtruth(self) -> npt.NDArray[np.float64]:
        """groundtruth.txt as N x 8 rows t tx ty tz qx qy qz qw; empty when there is none."""

class DetectionsFile:
    """A detections file (docs/detections-file.md): any detector's boxes for a sequence, by timestamp."""

    def __init__(self, path: _Path) -> None: ...
    def find(self, timestamp: float) -> list[Detection] | None:
        """The frame's detections (within 1 ms: timestamps rounded to the millisecond match); None when the file
        has no such frame, the first time with a warning, each time counted in missed."""
    @property
    def missed(self) -> int:
        """How many calls of find found no frame."""
    @property
    def path(self) -> Path: ...
    def __len__(self) -> int: ...

class Detector:
    """A YOLO-family ONNX model (YOLOX, YOLOv5, YOLOv8, YOLO11) run by OpenCV."""

    def __init__(self, model: _Path, confidence: float = 0.25, nms: float = 0.45) -> None: ...
    def detect(self, rgb: npt.NDArray[np.uint8], format: str = "bgr") -> list[Detection]:
        """The detections in a colour image, best score first."""
    @property
    def name(self) -> str: ...

def judge_boxes(
    detections: list[Detection],
    mode: str = "hoid2d",
    min_interaction_area: float = 0.4,
    depth_threshold: float = 0.2,
    depth: npt.NDArray[np.uint16] | npt.NDArray[np.float32] | None = None,
    depth_factor: float = 5000.0,
) -> list[JudgedBox]:
    """The HOID filter on its own: one verdict per detection (modes none, person, classes, hoid2d, hoid3d)."""

class ErrorSummary:
    rmse: float
    mean: float
    median: float
    std: float
    min: float
    max: float
    count: int

class AteResult:
    """Absolute trajectory error, with every matched pair for plots."""

    error: ErrorSummary
    @property
    def rmse(self) -> float: ...
    @property
    def timestamps(self) -> npt.NDArray[np.float64]: ...
    @property
    def groundtruth(self) -> npt.NDArray[np.float64]:
        """N x 3 ground-truth positions of the matched pairs."""
    @property
    def aligned(self) -> npt.NDArray[np.float64]:
        """N x 3 estimated positions, aligned to the ground truth."""

class RpeSummary:
    translation: ErrorSummary
    rotation_deg: ErrorSummary

def ate(groundtruth: npt.ArrayLike, estimate: npt.ArrayLike) -> AteResult:
    """Absolute trajectory error (metres) as TUM's evaluate_ate.py; both N x 8 (t tx ty tz qx qy qz qw)."""

def rpe(groundtruth: npt.ArrayLike, estimate: npt.ArrayLike, delta: float = 1.0) -> RpeSummary:
    """Relative pose error over delta seconds, as TUM's evaluate_rpe.py."""

def render_synthetic(
    out: _Path,
    scenario: str = "walking_xyz",
    frames: int = 0,
    frame_step: int = 1,
    tum_dir: _Path | None = None,
    force: bool = False,
    threads: int = 2,
) -> int:
    """Renders a synthetic sequence with exact ground truth (as hoidslam synth); returns the frames written."""
