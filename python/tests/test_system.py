"""hoidslam's Python module against the command: the same deterministic run gives the same bytes and the same
ATE; bad arrays raise an InputError that names the argument."""

import json
import os
import subprocess
import threading

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


def test_save_writes_a_run_folder_the_command_reads_and_a_map_to_start_from(walk, tmp_path):
    sequence = hoidslam.Sequence(walk)
    slam = hoidslam.System(filter="none", deterministic=True)
    for f in sequence:
        slam.track(f.rgb, f.depth, f.timestamp)
    slam.save(tmp_path / "out")
    for name in ("trajectory.txt", "keyframes.txt", "map.ply", "frames.jsonl", "summary.json", "report.html"):
        assert (tmp_path / "out" / name).is_file(), name
    report = subprocess.run([BINARY, "report", str(tmp_path / "out"), "--out", str(tmp_path / "again.html")],
                            capture_output=True, text=True)
    assert report.returncode == 0, report.stderr
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["tracked"] == len(sequence)

    slam.save_map(tmp_path / "walk.hmap")
    again = hoidslam.System(filter="none", load_map=tmp_path / "walk.hmap", localization=True)
    results = [again.track(f.rgb, f.depth, f.timestamp) for f in sequence]
    assert sum(r.pose is not None for r in results) >= len(sequence) - 1
    again.reset()
    assert again.track(sequence[0].rgb, sequence[0].depth, sequence[0].timestamp).index == 0


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


def test_threads_share_one_system(walk):
    """A camera thread and a replay thread tracking, a viewer reading: every call is tracked whole or refused for
    coming after a newer frame, never a crash or a hang."""
    sequence = hoidslam.Sequence(walk)
    frames = list(sequence)
    slam = hoidslam.System(filter="none")
    next_frame = iter(range(len(frames)))
    lock = threading.Lock()
    results, refused, errors = [], [], []
    done = threading.Event()

    def track():
        while True:
            with lock:
                i = next(next_frame, None)
            if i is None:
                return
            try:
                results.append(slam.track(frames[i].rgb, frames[i].depth, frames[i].timestamp))
            except hoidslam.InputError as e:
                (refused if "frames must come in time order" in str(e) else errors).append(str(e))

    def read():
        while not done.is_set():
            slam.map_points()
            slam.keyframes()
            slam.trajectory()

    trackers = [threading.Thread(target=track) for _ in range(4)]
    reader = threading.Thread(target=read)
    for t in trackers + [reader]:
        t.start()
    for t in trackers:
        t.join(timeout=120)
    done.set()
    reader.join(timeout=120)
    assert not any(t.is_alive() for t in trackers + [reader])
    assert errors == []
    assert len(results) + len(refused) == len(frames)
    results.sort(key=lambda r: r.index)
    assert [r.index for r in results] == list(range(len(results)))
    assert all(a.timestamp < b.timestamp for a, b in zip(results, results[1:]))
    slam.finish()
    assert len(slam.trajectory()) == sum(r.pose is not None for r in results)


def test_a_camera_given_by_its_values_takes_millimetres(walk):
    """Intrinsics and depth scale from the camera's SDK; millimetre depth as RealSense and OpenNI give it."""
    camera = hoidslam.Camera(fx=535.4, fy=539.2, cx=320.1, cy=247.6, width=640, height=480, depth_scale=0.001)
    slam = hoidslam.System(camera=camera, filter="none")
    assert slam.depth_factor == 1000.0
    frames = list(hoidslam.Sequence(walk))
    millimetres = [np.round(f.depth * 1000).astype(np.uint16) for f in frames]
    results = [slam.track(f.rgb, mm, f.timestamp) for f, mm in zip(frames, millimetres)]
    assert all(r.pose is not None for r in results)
    # The same millimetres read as TUM's 5000 units a metre: refused on the first frame, saying so.
    error = message(lambda: hoidslam.System(filter="none").track(frames[0].rgb, millimetres[0], frames[0].timestamp))
    assert error.startswith("parameter depth: the depth looks too near for a room")
    assert "1000 units a metre would put it where a room is" in error
    camera.cx = 700.0
    assert message(lambda: hoidslam.System(camera=camera)).startswith("parameter camera.cx: must be in [0, width=640]")
    assert "Camera(fx=535.4" in repr(camera)


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


def test_wrong_argument_types_are_named_and_never_printed():
    """What a camera loop gets wrong on its first day: a None frame, a list of pixels, a string timestamp."""
    slam = hoidslam.System(filter="none")
    rgb = np.zeros((480, 640, 3), np.uint8)
    depth = np.zeros((480, 640), np.uint16)
    pixels = rgb.tolist()  # printed, this list would be megabytes
    for call, expected in [
        (lambda: hoidslam.System(settings=5), "parameter settings: must be a path (str or os.PathLike) or None, got int"),
        (lambda: hoidslam.System(camera="d435"), "parameter camera: must be a hoidslam.Camera or None, got str"),
        (lambda: hoidslam.System(filter=None), "parameter filter: must be a str, got None"),
        (lambda: hoidslam.Camera(fx="615", fy=615, cx=320, cy=240, width=640, height=480),
         "parameter camera.fx: must be a number, got str"),
        (lambda: hoidslam.Camera(fx=615, fy=615, cx=320, cy=240, width=640, height=480, distortion=(0, 0)),
         "parameter camera.distortion: must be 5 numbers k1, k2, p1, p2, k3, got tuple"),
        (lambda: slam.track(None, depth, 1.0), "parameter rgb: must be a numpy array, uint8 (height, width, 3) or "
                                               "(height, width), got None"),
        (lambda: slam.track(pixels, depth, 1.0), "parameter rgb: must be a numpy array, uint8 (height, width, 3) or "
                                                 "(height, width), got list"),
        (lambda: slam.track(rgb, None, 1.0), "parameter depth: must be a numpy array, (height, width) uint16 or "
                                             "float32, got None"),
        (lambda: slam.track(rgb, depth, "now"), "parameter timestamp: must be a number of seconds, got str"),
        (lambda: slam.track(rgb, depth, 1.0, [{"label": "person"}]),
         "parameter detections[0]: must be a hoidslam.Detection, got dict"),
        (lambda: slam.track(rgb, depth, 1.0, "person"),
         "parameter detections: must be a list of hoidslam.Detection or None, got str"),
    ]:
        error = message(call)
        assert error == expected
        assert len(error) < 200


def test_save_into_a_folder_that_cannot_be_made_names_it(walk):
    slam = hoidslam.System(filter="none")
    frame = hoidslam.Sequence(walk)[0]
    slam.track(frame.rgb, frame.depth, frame.timestamp)
    with pytest.raises(hoidslam.Error) as error:
        slam.save("/proc/hoidslam-out")
    assert str(error.value).startswith("/proc/hoidslam-out: cannot create the folder to save into")


def test_detections_rounded_to_the_millisecond_are_found_and_misses_are_counted(walk, tmp_path):
    rounded = tmp_path / "rounded.jsonl"
    lines = []
    for line in (walk / "detections.jsonl").read_text().splitlines():
        entry = json.loads(line)
        if "timestamp" in entry:
            entry["timestamp"] = round(entry["timestamp"], 3)
        lines.append(json.dumps(entry))
    rounded.write_text("\n".join(lines) + "\n")
    detections = hoidslam.DetectionsFile(rounded)
    timestamps = hoidslam.Sequence(walk).timestamps()
    assert all(detections.find(t) is not None for t in timestamps)
    assert detections.missed == 0
    with pytest.warns(UserWarning, match="no line for timestamp 1.000000 .within 1 ms.: that frame gets no boxes"):
        assert detections.find(1.0) is None
    assert detections.find(2.0) is None  # counted, not warned again
    assert detections.missed == 2


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


def test_a_system_asked_to_show_itself_serves_the_viewer(walk):
    import urllib.request

    sequence = hoidslam.Sequence(walk)
    detections = hoidslam.DetectionsFile(walk / "detections.jsonl")
    with hoidslam.System(filter="hoid2d", view=0) as slam:
        assert slam.viewer_url.startswith("http://127.0.0.1:")
        for frame in list(sequence)[:5]:
            slam.track(frame.rgb, frame.depth, frame.timestamp, detections.find(frame.timestamp))
        with urllib.request.urlopen(slam.viewer_url, timeout=10) as page:
            assert b"<html" in page.read().lower()
    assert hoidslam.System().viewer_url == ""
    with pytest.raises(hoidslam.InputError, match="view"):
        hoidslam.System(view="yes")


def test_a_dense_system_saves_a_mesh_open3d_opens_and_a_grid_map_server_reads(walk, tmp_path):
    import open3d  # Debian's python3-open3d, as a user opens the files

    sequence = hoidslam.Sequence(walk)
    detections = hoidslam.DetectionsFile(walk / "detections.jsonl")
    slam = hoidslam.System(filter="hoidplus", dense=0.02)
    for frame in sequence:
        slam.track(frame.rgb, frame.depth, frame.timestamp, detections.find(frame.timestamp))
    slam.save(tmp_path / "out")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())["dense"]
    assert summary["written"] and summary["options"]["voxel_size"] == 0.02
    assert summary["keyframes"] == len(slam.keyframes())

    mesh = open3d.io.read_triangle_mesh(str(tmp_path / "out" / "mesh.ply"))
    assert len(mesh.triangles) == summary["mesh"]["triangles"] > 1000
    assert mesh.has_vertex_colors() and mesh.has_vertex_normals()
    cloud = open3d.io.read_point_cloud(str(tmp_path / "out" / "cloud.ply"))
    assert len(cloud.points) == summary["cloud_points"] > 1000
    # The cloud lies on the mesh (but at its open edges, where marching cubes stops short of the last voxel).
    scene = open3d.t.geometry.RaycastingScene()
    scene.add_triangles(open3d.t.geometry.TriangleMesh.from_legacy(mesh))
    distances = scene.compute_distance(np.asarray(cloud.points, dtype=np.float32)).numpy()
    assert np.median(distances) < 0.002 and np.percentile(distances, 95) < 0.02

    # The grid as map_server reads it: the YAML's image, resolution and origin; the PGM's trinary values.
    yaml = dict(line.split(": ", 1) for line in (tmp_path / "out" / "occupancy.yaml").read_text().splitlines()
                if ": " in line and not line.startswith("#"))
    assert yaml["image"] == "occupancy.pgm" and float(yaml["resolution"]) == 0.05 and yaml["mode"] == "trinary"
    origin = [float(v) for v in yaml["origin"].strip("[]").split(",")]
    assert len(origin) == 3 and origin[2] == 0.0
    from PIL import Image  # what map_server's image loader does in Python tools: Pillow reads PGM

    grid = np.asarray(Image.open(tmp_path / "out" / "occupancy.pgm"))
    assert grid.ndim == 2 and set(np.unique(grid)) <= {0, 205, 254} and (grid == 0).any() and (grid == 254).any()

    with pytest.raises(hoidslam.InputError, match="dense"):
        hoidslam.System(dense="yes")
    with pytest.raises(hoidslam.InputError, match="--dense-voxel"):
        hoidslam.System(dense=-0.01)
