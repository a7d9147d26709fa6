"""hoidslam's Python module against the command: the same deterministic run gives the same bytes and the same
ATE; bad arrays raise an InputError that names the argument."""

import json
import os
import subprocess

import numpy as np
import pytest

import hoidslam

BINARY = os.environ.get("HOIDSLAM_BINARY", "hoidslam")


def test_a_deterministic_run_equals_the_command_byte_for_byte(walk, tmp_path):
    subprocess.run([BINARY, "run", str(walk), "--filter", "hoid2d", "--deterministic", "--snapshots", "0",
                    "--out", str(tmp_path / "run")], check=True, capture_output=True)

    detections = hoidslam.DetectionsFile(walk / "detections.jsonl")
    sequence = hoidslam.Sequence(walk)
    slam = hoidslam.System(filter="hoid2d", deterministic=True)
    results = [slam.track(f.rgb, f.depth, f.timestamp, detections.find(f.timestamp)) for f in sequence]
    assert [r.state for r in results] == ["ok"] * len(sequence)
    assert sum(r.dropped for r in results) > 0  # people are in view
    slam.save(tmp_path / "api")
    for name in ("trajectory.txt", "keyframes.txt", "map.ply"):
        assert (tmp_path / "api" / name).read_bytes() == (tmp_path / "run" / name).read_bytes(), name

    # The ATE the command reported, from the trajectory file and from the trajectory in memory.
    reported = json.loads((tmp_path / "run" / "summary.json").read_text())["evaluation"]["ate"]["error_m"]["rmse"]
    groundtruth = np.loadtxt(walk / "groundtruth.txt")
    assert hoidslam.ate(groundtruth, np.loadtxt(tmp_path / "api" / "trajectory.txt")).rmse == reported
    assert hoidslam.ate(sequence.groundtruth(), slam.trajectory()).rmse == pytest.approx(reported, rel=1e-6)


def test_results_are_views_with_verdicts(walk):
    detections = hoidslam.DetectionsFile(walk / "detections.jsonl")
    slam = hoidslam.System(filter="hoid2d")
    sequence = hoidslam.Sequence(walk)
    result = None
    for frame in sequence:
        result = slam.track(frame.rgb, frame.depth, frame.timestamp, detections.find(frame.timestamp))
    n = len(result.kept)
    assert result.keypoints.shape == (n, 2) and result.keypoints.dtype == np.float32
    assert result.pose.shape == (4, 4) and np.allclose(result.pose[3], [0, 0, 0, 1])
    assert not result.keypoints.flags.writeable
    dropped = ~result.kept
    assert dropped.sum() == result.dropped > 0
    assert (result.keypoint_box[dropped] >= 0).all() and (result.keypoint_box[~dropped] == -1).all()
    reasons = result.drop_reasons()
    assert {reasons[i] for i in np.flatnonzero(dropped)} <= {"person", "interaction"}
    assert all(result.boxes[b].dynamic for b in result.keypoint_box[dropped])
    positions, colours, observations = slam.map_points()
    assert positions.shape == (len(observations), 3) and colours.dtype == np.uint8
    slam.finish()
    assert slam.trajectory().shape == (len(sequence), 8)


def message(call):
    with pytest.raises(hoidslam.InputError) as error:
        call()
    return str(error.value)


def test_wrong_arrays_raise_an_error_naming_the_argument():
    slam = hoidslam.System(filter="none")
    rgb = np.zeros((480, 640, 3), np.uint8)
    depth = np.zeros((480, 640), np.uint16)
    assert message(lambda: slam.track(rgb.astype(np.float64), depth, 1.0)) == \
        "parameter rgb: dtype must be uint8, got float64"
    assert message(lambda: slam.track(np.zeros((480, 640, 4), np.uint8), depth, 1.0)).startswith(
        "parameter rgb: must have shape (height, width, 3), got (480, 640, 4)")
    assert message(lambda: slam.track(np.zeros((960, 1280, 3), np.uint8)[::2, ::2], depth, 1.0)).startswith(
        "parameter rgb: pixels must lie packed in each row")
    assert message(lambda: slam.track(rgb, depth.astype(np.int32), 1.0)) == \
        "parameter depth: dtype must be uint16 (depth units) or float32 (metres), got int32"
    assert message(lambda: slam.track(rgb, np.zeros((240, 320), np.uint16), 1.0)).startswith(
        "parameter depth: is 320x240 but the camera's images are 640x480")
    assert message(lambda: slam.track(rgb, depth, 1.0, format="yuv")).startswith("parameter format")
    assert message(lambda: slam.track(rgb, depth, 1.0, depth_delay=float("nan"))).startswith("parameter depth_delay")
    assert message(lambda: hoidslam.System(detector="yolo")).startswith("parameter detector")
    assert message(lambda: hoidslam.System(filter="hoid2d", detector="none")).startswith("parameter detector")
    assert message(lambda: hoidslam.ate(np.zeros((5, 7)), np.zeros((5, 8)))).startswith("parameter groundtruth")
    assert isinstance(hoidslam.InputError("x"), ValueError)


def test_rows_with_padding_and_rgb_order_are_taken():
    slam = hoidslam.System(filter="none")
    padded = np.zeros((480, 700, 3), np.uint8)[:, :640]  # each row 700 pixels apart, as a crop is
    assert not padded.flags.c_contiguous
    assert slam.track(padded, np.zeros((480, 640), np.float32), 1.0).state == "not_initialized"
    assert slam.track(padded, np.zeros((480, 640), np.uint16), 2.0, format="rgb").index == 1
    assert slam.track(np.zeros((480, 640), np.uint8), np.zeros((480, 640), np.uint16), 3.0).index == 2


def test_sequence_filter_and_errors_on_their_own(walk):
    sequence = hoidslam.Sequence(walk)
    assert len(sequence) == 30 and sequence.name == "walk"
    frame = sequence[-1]
    assert frame.rgb.shape == (480, 640, 3) and frame.depth.dtype == np.float32
    assert frame.timestamp == sequence.timestamps()[-1]
    assert abs(frame.depth_delay) < 0.001  # a synthetic depth image is stamped with its colour image
    with pytest.raises(IndexError):
        sequence[30]

    person = hoidslam.Detection("person", (100, 100, 200, 300), 0.9)
    cup = hoidslam.Detection("cup", (150, 200, 40, 40), 0.8)
    chair = hoidslam.Detection("chair", (500, 300, 100, 100), 0.8)
    verdicts = hoidslam.judge_boxes([person, cup, chair], mode="hoid2d")
    assert [(v.dynamic, v.reason) for v in verdicts] == [(True, "person"), (True, "interaction"),
                                                           (False, "no_interaction")]
    assert verdicts[1].person == 0 and verdicts[1].interaction == 1.0

    groundtruth = sequence.groundtruth()
    assert hoidslam.ate(groundtruth, groundtruth).rmse < 1e-9
    assert hoidslam.rpe(groundtruth, groundtruth, delta=0.5).translation.rmse < 1e-9
