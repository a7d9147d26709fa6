"""examples/python/live_camera.py --realsense without a camera: a stand-in pyrealsense2 plays the synthetic walk as a
RealSense delivers it (colour BGR, depth aligned to colour in uint16 units of the depth scale), with the SDK's names
and shapes for each call the script makes. The script takes the camera's values from it, tracks and saves."""

import enum
import importlib.util
import os
import pathlib
import re
import sys
import types

import numpy as np
import pytest

import hoidslam

SCRIPT = pathlib.Path(os.environ.get("HOIDSLAM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2])) / \
    "examples" / "python" / "live_camera.py"

# The walk's camera, TUM fr3, as the SDK's rs.intrinsics names its fields.
FR3 = dict(fx=535.4, fy=539.2, ppx=320.1, ppy=247.6, width=640, height=480)


def stand_in_pyrealsense2(folder, depth_scale, name="Intel RealSense D435"):
    """A pyrealsense2 module whose one camera plays the frames of `folder`, the depth as uint16 millimetres, and
    reports FR3's intrinsics and `depth_scale`. Only 640x480 colour bgr8 and depth z16 at 30 Hz can be started, as
    a real camera refuses a mode it has not. After the last frame try_wait_for_frames times out: (False, frames)."""
    sequence = hoidslam.Sequence(folder)
    rs = types.ModuleType("pyrealsense2")
    rs.stream = enum.Enum("stream", [("depth", 1), ("color", 2)])  # rs2_stream's values
    rs.format = enum.Enum("format", [("z16", 1), ("bgr8", 6)])  # rs2_format's
    rs.camera_info = enum.Enum("camera_info", [("name", 0)])
    rs.aligned = []  # the stream each processed frameset was aligned to, for the test

    class frame:
        def __init__(self, data, timestamp_ms):
            self.data, self.timestamp_ms = data, timestamp_ms

        def get_data(self):
            return memoryview(self.data)  # the SDK's BufData: a buffer numpy wraps without a copy

        def get_timestamp(self):
            return self.timestamp_ms

    class composite_frame:
        def __init__(self, colour=None, depth=None):
            self.colour, self.depth = colour, depth

        def get_color_frame(self):
            return self.colour

        def get_depth_frame(self):
            return self.depth

    class intrinsics:
        def __init__(self):
            self.__dict__.update(FR3, model="brown_conrady", coeffs=[0.0] * 5)

    class video_stream_profile:
        def get_intrinsics(self):
            return intrinsics()

    class stream_profile:
        def as_video_stream_profile(self):
            return video_stream_profile()

    class depth_sensor:
        def get_depth_scale(self):
            return depth_scale

    class device:
        def get_info(self, info):
            assert info == rs.camera_info.name
            return name

        def first_depth_sensor(self):
            return depth_sensor()

    class pipeline_profile:
        def get_stream(self, stream_type):
            return stream_profile()

        def get_device(self):
            return device()

    class config:
        def __init__(self):
            self.streams = {}

        def enable_stream(self, stream_type, width, height, format, framerate):
            self.streams[stream_type] = (width, height, format, framerate)

    class pipeline:
        def __init__(self):
            self.next = None

        def start(self, config):
            if config.streams != {rs.stream.color: (640, 480, rs.format.bgr8, 30),
                                  rs.stream.depth: (640, 480, rs.format.z16, 30)}:
                raise RuntimeError("Couldn't resolve requests")
            self.next = 0
            return pipeline_profile()

        def try_wait_for_frames(self, timeout_ms=5000):
            if self.next is None:
                raise RuntimeError("try_wait_for_frames cannot be called before start()")
            if self.next == len(sequence):
                return False, composite_frame()
            recorded = sequence[self.next]
            self.next += 1
            milliseconds = recorded.timestamp * 1000.0
            depth = np.round(recorded.depth * 1000.0).astype(np.uint16)  # metres to millimetres
            return True, composite_frame(frame(np.ascontiguousarray(recorded.rgb), milliseconds),
                                         frame(depth, milliseconds))

        def stop(self):
            self.next = None

    class align:
        def __init__(self, align_to):
            self.align_to = align_to

        def process(self, frames):
            rs.aligned.append(self.align_to)  # the walk's depth is registered to its colour already
            return frames

    for cls in (frame, composite_frame, intrinsics, video_stream_profile, stream_profile, depth_sensor, device,
                pipeline_profile, config, pipeline, align):
        setattr(rs, cls.__name__, cls)
    return rs


def live_camera():
    """The script as a module, its main(argv) returning the exit status."""
    spec = importlib.util.spec_from_file_location("live_camera", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_realsense_takes_the_sdks_camera_tracks_every_frame_and_saves(walk, tmp_path, monkeypatch, capsys):
    rs = stand_in_pyrealsense2(walk, depth_scale=0.001)
    monkeypatch.setitem(sys.modules, "pyrealsense2", rs)
    assert live_camera().main(["--realsense", "--quiet", "--out", str(tmp_path / "out")]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    camera = re.search(r"^camera: Camera\(fx=([\d.]+), .*depth_scale=([\d.]+), baseline=([\d.]+)\), from the "
                       r"RealSense SDK \(Intel RealSense D435\)", out, re.M)
    assert camera, out
    assert float(camera[1]) == pytest.approx(535.4) and float(camera[2]) == 0.001 and float(camera[3]) == 0.05
    assert "baseline 0.05 m, the D435's nominal" in out
    frames, tracked = map(int, re.search(r"(\d+) frames in .*, (\d+) tracked, 0 dropped", out).groups())
    assert frames == tracked == 30
    assert rs.aligned == [rs.stream.color] * 30
    assert len((tmp_path / "out" / "trajectory.txt").read_text().splitlines()) == 31  # a header line
    assert (tmp_path / "out" / "map.ply").exists() and (tmp_path / "out" / "keyframes.txt").exists()


def test_a_depth_scale_the_data_disagree_with_stops_with_hoidslams_message(walk, tmp_path, monkeypatch, capsys):
    # millimetres said to be 0.2 mm units (5000 a metre, TUM's): five times too near for a room
    monkeypatch.setitem(sys.modules, "pyrealsense2", stand_in_pyrealsense2(walk, depth_scale=0.0002))
    assert live_camera().main(["--realsense", "--quiet", "--out", str(tmp_path / "out")]) == 1
    out, err = capsys.readouterr()
    assert "depth_scale=0.0002" in out
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("live_camera.py: parameter depth: the depth looks too near for a room"), err
    assert not (tmp_path / "out").exists()


def test_settings_override_the_sdks_camera(walk, monkeypatch, capsys):
    settings = hoidslam.shipped_dir() / "config" / "Kinect_v1_OpenNI.yaml"  # 640x480, 1000 units a metre
    monkeypatch.setitem(sys.modules, "pyrealsense2", stand_in_pyrealsense2(walk, depth_scale=0.001))
    assert live_camera().main(["--realsense", "--quiet", "--settings", str(settings)]) == 0
    out, err = capsys.readouterr()
    assert f"camera: 640x480, 1000 depth units a metre, from the settings file {settings} (not the RealSense " \
           "SDK's values)" in out
    assert "535.4" not in out and err == ""
    assert re.search(r"30 frames in .*, \d+ tracked", out)
