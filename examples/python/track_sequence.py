#!/usr/bin/env python3
"""Tracks a recorded sequence (a TUM RGB-D / Bonn download or a `hoidslam synth` folder) with hoidslam's Python
module, writes the trajectory, keyframes and map, and with ground truth plots the trajectory against it and the
error over time (ATE) with matplotlib.

    PYTHONPATH=build/python python3 examples/python/track_sequence.py SEQUENCE --out OUT [--settings S.yaml]

The boxes each frame is judged by come from the folder's detections.jsonl (`hoidslam detect` writes one; a
synthetic sequence has the exact ones); without it the filter is none.
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt
import numpy as np

import hoidslam


def plot_ate(ate, path):
    """Top view of the aligned trajectory over the ground truth, and the position error over time."""
    figure, (top, error) = plt.subplots(1, 2, figsize=(11, 4.5))
    top.plot(ate.groundtruth[:, 0], ate.groundtruth[:, 1], color="0.6", label="ground truth")
    top.plot(ate.aligned[:, 0], ate.aligned[:, 1], color="tab:green", label="hoidslam")
    top.set(xlabel="x (m)", ylabel="y (m)", title="trajectory, aligned")
    top.set_aspect("equal", adjustable="datalim")
    top.legend()
    seconds = ate.timestamps - ate.timestamps[0]
    error.plot(seconds, 1000 * np.linalg.norm(ate.aligned - ate.groundtruth, axis=1), color="tab:red")
    error.set(xlabel="time (s)", ylabel="position error (mm)", title=f"ATE RMSE {1000 * ate.rmse:.1f} mm")
    figure.tight_layout()
    figure.savefig(path, dpi=100)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sequence", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, required=True)
    parser.add_argument("--settings", help="settings file (default: TUM fr3), e.g. config/TUM3.yaml")
    parser.add_argument("--filter", default="", help="none, person, hoid2d, hoid3d, hoidplus (default: hoidplus)")
    args = parser.parse_args()

    detections_file = args.sequence / "detections.jsonl"
    detections = hoidslam.DetectionsFile(detections_file) if detections_file.exists() else None
    sequence = hoidslam.Sequence(args.sequence)
    slam = hoidslam.System(settings=args.settings, filter=args.filter if detections else "none")
    lost = 0
    for frame in sequence:
        boxes = (detections.find(frame.timestamp) or []) if detections else None
        lost += slam.track(frame.rgb, frame.depth, frame.timestamp, boxes, depth_delay=frame.depth_delay).state != "ok"
    slam.save(args.out)
    print(f"{sequence.name}: {len(sequence)} frames, {lost} not tracked, filter {slam.filter}; wrote {args.out}/")

    groundtruth = sequence.groundtruth()
    if len(groundtruth):
        ate = hoidslam.ate(groundtruth, slam.trajectory())
        plot_ate(ate, args.out / "ate.png")
        print(f"ATE RMSE {1000 * ate.rmse:.1f} mm over {ate.error.count} poses; plot: {args.out / 'ate.png'}")


if __name__ == "__main__":
    main()
