#!/usr/bin/env python3
"""Live SLAM from any camera: a loop that takes colour and depth arrays from a source, hands them to hoidslam and
prints the pose. A source is any callable that returns (rgb, depth, timestamp) for the newest frame, or None when
the stream ends: a vendor SDK (see realsense_source below), OpenCV's VideoCapture of an RGB-D camera (opencv_source),
or --replay FOLDER, which plays a recording at its recorded rate as a camera would deliver it.

    PYTHONPATH=build/python python3 examples/python/live_camera.py --replay SEQUENCE --realtime --model M.onnx
    PYTHONPATH=build/python python3 examples/python/live_camera.py --opencv 0 --settings config/TUM3.yaml

With --realtime the detector runs in its own thread and tracking never waits for it (docs/realtime.md). Frames
that arrive while the system is busy are dropped, as from a live camera, and counted.
"""

import argparse
import collections
import statistics
import threading
import time

import numpy as np

import hoidslam


class Replay:
    """A recording as a live camera: frame i becomes available at its recorded time after the start; each call
    returns the newest available frame (frames passed over meanwhile are dropped), waiting for the next one when
    the caller is ahead. A camera delivers its frames decoded, so a thread decodes them ahead, up to `preload_mb`
    of them before the clock starts (the rest while the replay runs, taking CPU from tracking)."""

    def __init__(self, folder, preload_mb=2048):
        self.sequence = hoidslam.Sequence(folder)
        self.offsets = self.sequence.timestamps() - self.sequence.timestamps()[0]  # seconds after the first
        first = self.sequence[0]
        frame_bytes = first.rgb.nbytes + first.depth.nbytes
        self.ahead = max(1, min(len(self.sequence), preload_mb * 2**20 // frame_bytes))
        self.decoded = collections.deque()
        self.room = threading.Semaphore(self.ahead)
        self.ready = threading.Condition()
        self.dropped = 0
        self.next = 0  # the first frame not yet handed out
        self.start = None
        threading.Thread(target=self._decode, daemon=True).start()

    def _decode(self):
        for i in range(len(self.sequence)):
            self.room.acquire()
            frame = self.sequence[i]  # decoding releases the GIL
            with self.ready:
                self.decoded.append((i, frame))
                self.ready.notify()

    def __call__(self):
        if self.next >= len(self.sequence):
            return None
        if self.start is None:
            with self.ready:
                self.ready.wait_for(lambda: len(self.decoded) == self.ahead)
            self.start = time.monotonic()
        elapsed = time.monotonic() - self.start
        newest = max(self.next, int(np.searchsorted(self.offsets, elapsed, side="right")) - 1)
        if self.offsets[newest] > elapsed:
            time.sleep(self.offsets[newest] - elapsed)
        with self.ready:  # frames are decoded in order: drop those before `newest`, take it
            while not self.decoded or self.decoded[0][0] < newest:
                if self.decoded:
                    self.decoded.popleft()
                    self.room.release()
                else:
                    self.ready.wait()
            _, frame = self.decoded.popleft()
            self.room.release()
        self.dropped += newest - self.next
        self.next = newest + 1
        return frame.rgb, frame.depth, frame.timestamp


def opencv_source(index):
    """An RGB-D camera through OpenCV's OpenNI2 backend (Kinect, Xtion, Orbbec): needs python3-opencv."""
    import cv2

    capture = cv2.VideoCapture(index, cv2.CAP_OPENNI2)
    if not capture.isOpened():
        raise SystemExit(f"no OpenNI2 camera at index {index}")

    def read():
        if not capture.grab():
            return None
        _, depth = capture.retrieve(None, cv2.CAP_OPENNI_DEPTH_MAP)  # uint16 millimetres
        _, bgr = capture.retrieve(None, cv2.CAP_OPENNI_BGR_IMAGE)
        return bgr, depth, time.time()

    return read


def realsense_source():
    """An Intel RealSense through its SDK (pyrealsense2, not a Debian package); depth aligned to colour, in the
    camera's depth units (1 mm: use settings with DepthMapFactor 1000)."""
    import pyrealsense2 as rs

    pipeline = rs.pipeline()
    config = rs.config()
    config.enable_stream(rs.stream.color, 640, 480, rs.format.bgr8, 30)
    config.enable_stream(rs.stream.depth, 640, 480, rs.format.z16, 30)
    pipeline.start(config)
    align = rs.align(rs.stream.color)

    def read():
        frames = align.process(pipeline.wait_for_frames())
        colour, depth = frames.get_color_frame(), frames.get_depth_frame()
        return np.asanyarray(colour.get_data()), np.asanyarray(depth.get_data()), colour.get_timestamp() / 1000.0

    return read


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--replay", help="play a recorded sequence at its recorded rate")
    source.add_argument("--opencv", type=int, help="an OpenNI2 RGB-D camera by index")
    source.add_argument("--realsense", action="store_true", help="an Intel RealSense (pyrealsense2)")
    parser.add_argument("--settings", help="the camera's settings file (default: TUM fr3)")
    parser.add_argument("--model", help="YOLO ONNX model for the detector (default: no detector, filter none)")
    parser.add_argument("--realtime", action="store_true", help="the detector in its own thread")
    parser.add_argument("--preload-mb", type=int, default=2048, help="--replay: memory for frames decoded ahead")
    parser.add_argument("--quiet", action="store_true", help="only the summary, not a line per frame")
    args = parser.parse_args()

    read = Replay(args.replay, args.preload_mb) if args.replay else opencv_source(args.opencv) if args.opencv is not None \
        else realsense_source()
    detector = dict(detector="onnx", model=args.model) if args.model else dict(detector="none", filter="none")
    slam = hoidslam.System(settings=args.settings, realtime=args.realtime, **detector)
    milliseconds, tracked, begin = [], 0, None
    while (frame := read()) is not None:
        begin = begin or time.monotonic()  # from the first frame on: a replay decodes ahead before it
        rgb, depth, timestamp = frame
        result = slam.track(rgb, depth, timestamp)
        milliseconds.append(result.milliseconds)
        tracked += result.state == "ok"
        if not args.quiet and result.pose is not None:
            x, y, z = result.pose[:3, 3]
            print(f"{timestamp:.3f} {result.state} at ({x:+.3f}, {y:+.3f}, {z:+.3f}) m, "
                  f"{result.dropped} keypoints dropped")
    seconds = time.monotonic() - begin
    slam.finish()
    dropped = getattr(read, "dropped", 0)
    print(f"{len(milliseconds)} frames in {seconds:.1f} s ({len(milliseconds) / seconds:.1f} per second), "
          f"{tracked} tracked, {dropped} dropped arriving while busy; median {statistics.median(milliseconds):.1f} ms "
          f"a frame")


if __name__ == "__main__":
    main()
