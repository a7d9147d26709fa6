#!/usr/bin/env python3
"""What the Python call adds to a frame over the C++ call: the same deterministic frames (150 of walking_xyz,
hoid2d, each frame's boxes given) tracked through the Python module and through the C++ API (the Google Benchmark
program api_bench). Each side measures its call's wall time less the time the frame spent inside hoidslam
(FrameResult.milliseconds), frame by frame, so tracking's own variation cancels; the overhead is the Python
median of that difference less the C++ one. docs/library.md has the figures.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [--build build] [--runs 3]
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import tempfile
import time

import hoidslam

REPO = pathlib.Path(__file__).resolve().parents[1]


def python_side(folder):
    """Medians over the frames: the call's wall time, the time inside hoidslam, and their difference (ms)."""
    sequence = hoidslam.Sequence(folder)
    detections = hoidslam.DetectionsFile(folder / "detections.jsonl")
    slam = hoidslam.System(filter="hoid2d", deterministic=True)
    call, inside, extra = [], [], []
    for frame in sequence:
        boxes = detections.find(frame.timestamp) or []
        rgb, depth = frame.rgb, frame.depth
        begin = time.perf_counter()
        result = slam.track(rgb, depth, frame.timestamp, boxes)
        _ = result.keypoints, result.kept, result.pose  # what a caller reads, as views
        ms = 1000 * (time.perf_counter() - begin)
        call.append(ms)
        inside.append(result.milliseconds)
        extra.append(ms - result.milliseconds)
    return statistics.median(call), statistics.median(inside), statistics.median(extra)


def cpp_side(binary, folder):
    done = subprocess.run([binary, "--benchmark_format=json"], capture_output=True, text=True, check=True,
                          env=dict(os.environ, HOIDSLAM_BENCH_SEQUENCE=str(folder)))
    counters = json.loads(done.stdout)["benchmarks"][0]
    return counters["call_ms"], counters["inside_ms"], counters["api_ms"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    parser.add_argument("--runs", type=int, default=3, help="runs of each side, alternating")
    parser.add_argument("--shared", type=pathlib.Path,
                        default=pathlib.Path(os.environ.get("HOIDSLAM_SHARED_DIR", REPO.parent / "shared")))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder = pathlib.Path(scratch) / "walking_xyz"
        hoidslam.render_synthetic(folder, "walking_xyz", frames=150, tum_dir=args.shared / "data" / "tum")
        rows = []
        for run in range(args.runs):
            cpp = cpp_side(args.build / "src" / "hoidslam" / "api" / "api_bench", folder)
            py = python_side(folder)
            rows.append((cpp, py))
            print(f"run {run + 1}: C++ call {cpp[0]:.3f} ms (inside {cpp[1]:.3f}, API {cpp[2]:.4f}); "
                  f"Python call {py[0]:.3f} ms (inside {py[1]:.3f}, API + binding {py[2]:.4f}); "
                  f"Python adds {py[2] - cpp[2]:.4f} ms")
    added = statistics.median(py[2] - cpp[2] for cpp, py in rows)
    print(f"median over {args.runs} runs: the Python call adds {added:.4f} ms a frame to the C++ call")


if __name__ == "__main__":
    main()
