"""The Python examples run as a user runs them, on a short synthetic sequence."""

import os
import pathlib
import re
import subprocess
import sys

from conftest import shared_path

EXAMPLES = pathlib.Path(os.environ.get("HOIDSLAM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2])) / \
    "examples" / "python"


def run(script, *args):
    done = subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_track_sequence_writes_the_trajectory_and_the_ate_plot(walk, tmp_path):
    out = run("track_sequence.py", walk, "--out", tmp_path / "out", "--filter", "hoid2d")
    assert "walk: 30 frames, 0 not tracked, filter hoid2d" in out
    assert re.search(r"ATE RMSE \d+\.\d mm over 30 poses", out)
    assert (tmp_path / "out" / "ate.png").stat().st_size > 10000
    assert len((tmp_path / "out" / "trajectory.txt").read_text().splitlines()) == 31  # a header line


def test_own_detector_passes_each_frames_boxes(walk):
    out = run("own_detector.py", walk, "--boxes", walk / "detections.jsonl")
    assert "30 of 30 frames tracked" in out
    assert re.search(r"(cup|book|bottle|laptop|chair) dropped \(interaction, \d+ % inside person #\d+\)", out)


def test_live_camera_tracks_a_replay_at_the_recorded_rate_with_the_detector_in_its_thread(walk):
    out = run("live_camera.py", "--replay", walk, "--quiet", "--realtime", "--model",
              shared_path("models/yolox_nano.onnx"))
    frames, tracked, dropped = map(int, re.search(r"(\d+) frames in .* (\d+) tracked, (\d+) dropped", out).groups())
    assert frames + dropped == 30 and tracked == frames
