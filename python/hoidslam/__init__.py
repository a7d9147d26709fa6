"""hoidslam: RGB-D SLAM that drops the features of people and of the objects in their hands (HOID).

Frames come in as numpy arrays from any source (a recording, a camera SDK, a renderer); poses, tracking states
and every keypoint's verdict come out::

    import hoidslam
    slam = hoidslam.System(filter="hoid2d", deterministic=True)
    for frame, boxes in zip(hoidslam.Sequence("walk"), my_detector_boxes):
        result = slam.track(frame.rgb, frame.depth, frame.timestamp, boxes, depth_delay=frame.depth_delay)
    slam.save("out")

docs/python.md describes the module; help(hoidslam.System) each class.
"""

from ._hoidslam import (
    AteResult,
    Camera,
    Detection,
    DetectionsFile,
    Detector,
    Error,
    ErrorSummary,
    Frame,
    FrameResult,
    InputError,
    JudgedBox,
    RpeSummary,
    Sequence,
    System,
    ate,
    judge_boxes,
    render_synthetic,
    rpe,
    settings_for,
    shipped_dir,
    version,
)

__version__ = version()

__all__ = [
    "AteResult", "Camera", "Detection", "DetectionsFile", "Detector", "Error", "ErrorSummary", "Frame", "FrameResult", "InputError", "JudgedBox",
    "RpeSummary", "Sequence", "System", "ate", "judge_boxes", "render_synthetic", "rpe", "settings_for", "shipped_dir",
    "version",
]
