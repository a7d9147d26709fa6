#!/usr/bin/env python3
"""Tracks a sequence with the boxes of your own detector: hoidslam takes each frame's detections as they come and
judges them with the HOID filter (detector="given").

    PYTHONPATH=build/python python3 examples/python/own_detector.py SEQUENCE --model M.onnx
    PYTHONPATH=build/python python3 examples/python/own_detector.py SEQUENCE --boxes detections.jsonl

Replace `MyDetector` with your model: all hoidslam needs is, per frame, a list of hoidslam.Detection (a COCO label
such as "person" or "cup", a box (x, y, width, height) in pixels, a score). The two stand-ins here are a YOLO
ONNX model run by hoidslam.Detector, and boxes some other tool wrote to a file.
"""

import argparse
import pathlib

import numpy as np

import hoidslam

COCO = {0: "person", 39: "bottle", 41: "cup", 56: "chair", 62: "tv", 63: "laptop", 64: "mouse", 66: "keyboard",
        73: "book"}  # the classes the filter cares about (HOID.dynamicClasses); the rest are kept as static


def to_detections(xyxy, scores, class_ids):
    """The usual output of a detection network (N x 4 corners, N scores, N class ids) as hoidslam detections."""
    return [hoidslam.Detection(COCO.get(int(c), f"class{int(c)}"), (x0, y0, x1 - x0, y1 - y0), float(s), int(c))
            for (x0, y0, x1, y1), s, c in zip(np.asarray(xyxy, float), scores, class_ids)]


class MyDetector:
    """Stand-in for your model: rgb (h, w, 3) uint8 BGR in, (xyxy, scores, class_ids) out."""

    def __init__(self, model=None, boxes=None):
        self.model = hoidslam.Detector(model) if model else None
        self.boxes = hoidslam.DetectionsFile(boxes) if boxes else None

    def __call__(self, rgb, timestamp):
        found = self.model.detect(rgb) if self.model else (self.boxes.find(timestamp) or [])
        xyxy = [(x, y, x + w, y + h) for x, y, w, h in (d.box for d in found)]
        return np.reshape(xyxy, (-1, 4)), [d.score for d in found], [d.class_id for d in found]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sequence", type=pathlib.Path)
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--model", help="a YOLO ONNX model (YOLOX, YOLOv5, YOLOv8, YOLO11)")
    source.add_argument("--boxes", help="a detections file (docs/detections-file.md) another tool wrote")
    parser.add_argument("--filter", default="hoid2d", help="person, classes, hoid2d, hoid3d or hoidplus")
    parser.add_argument("--out", type=pathlib.Path, help="folder for trajectory.txt, keyframes.txt, map.ply")
    args = parser.parse_args()

    detector = MyDetector(args.model, args.boxes)
    slam = hoidslam.System(filter=args.filter, detector="given")
    tracked = dropped = 0
    sequence = hoidslam.Sequence(args.sequence)
    for frame in sequence:
        boxes = to_detections(*detector(frame.rgb, frame.timestamp))
        result = slam.track(frame.rgb, frame.depth, frame.timestamp, boxes, depth_delay=frame.depth_delay)
        tracked += result.state == "ok"
        dropped += result.dropped
        for box in result.boxes:
            if box.dynamic and box.detection.label != "person":
                print(f"frame {result.index}: {box.detection.label} dropped ({box.reason}, "
                      f"{100 * box.interaction:.0f} % inside person #{box.person})")
    print(f"{tracked} of {len(sequence)} frames tracked; {dropped} keypoints dropped on people and what they carry")
    if args.out:
        slam.save(args.out)


if __name__ == "__main__":
    main()
