#!/usr/bin/env python3
"""Live SLAM from any camera: a loop that takes colour and depth arrays from a source, hands them to hoidslam and
prints the pose. A source is any callable that returns (rgb, depth, timestamp) for the newest frame, or None when
the stream ends: a vendor SDK (see realsense_source below), OpenCV's VideoCapture of an RGB-D camera (opencv_source),
or --replay FOLDER, which plays a recording at its recorded rate as a camera would deliver it.

    PYTHONPATH=build/python python3 examples/python/live_camera.py --replay SEQUENCE --realtime --model M.onnx
    PYTHONPATH=build/python python3 examples/python/live_camera.py --realsense --size 848x480 --out run1
    PYTHONPATH=build/python python3 examples/python/live_camera.py --opencv 0 --settings my_kinect.yaml

The camera's values (intrinsics, image size, depth units) come from the camera where it reports them: a RealSense's
from its SDK, into a hoidslam.Camera. OpenNI reports no colour intrinsics, so --opencv takes the shipped Kinect v1
file's nominal ones; a replay takes the settings its folder's name calls for. --settings FILE overrides them all.
The script prints once which values it uses and where they come from.

With --realtime the detector runs in its own thread and tracking never waits for it (docs/realtime.md). Frames
that arrive while the system is busy are dropped, as from a live camera, and counted. The run ends when the stream
does or on Ctrl-C; --out FOLDER then keeps its trajectory, keyframes and map.
"""

import argparse
import collections
import statistics
import sys
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
    """An RGB-D camera through OpenCV's OpenNI2 backend (Kinect, Xtion, Orbbec): needs python3-opencv. Depth is
    registered to colour, in millimetres."""
    try:
        import cv2
    except ImportError:
        raise SystemExit("--opencv needs OpenCV's Python module (apt install python3-opencv)") from None

    capture = cv2.VideoCapture(index, cv2.CAP_OPENNI2)
    if not capture.isOpened():
        raise SystemExit(f"no OpenNI2 camera at index {index}")
    capture.set(cv2.CAP_PROP_OPENNI_REGISTRATION, 1)  # depth seen from the colour camera, pixel for pixel

    def read():
        if not capture.grab():
            return None
        _, depth = capture.retrieve(None, cv2.CAP_OPENNI_DEPTH_MAP)  # uint16 millimetres
        _, bgr = capture.retrieve(None, cv2.CAP_OPENNI_BGR_IMAGE)
        return bgr, depth, time.time()

    return read


# The D4xx's nominal stereo baselines, metres, by model: the SDK reports none for depth aligned to colour.
# hoidslam uses the baseline only for the close/far depth threshold (ThDepth baselines, docs/settings.md).
D4XX_BASELINES = {"D405": 0.018, "D415": 0.055, "D435": 0.050, "D455": 0.095, "D456": 0.095, "D457": 0.095}


def realsense_source(width, height):
    """An Intel RealSense through its SDK (pyrealsense2, not a Debian package), colour and depth at width x height,
    depth aligned to colour. Returns the reader, the hoidslam.Camera of the values the SDK reports (the colour
    stream's intrinsics in this mode, the depth sensor's depth scale) and where they come from."""
    try:
        import pyrealsense2 as rs
    except ImportError:
        raise SystemExit("--realsense needs Intel's pyrealsense2 (pip install pyrealsense2)") from None

    pipeline = rs.pipeline()
    config = rs.config()
    config.enable_stream(rs.stream.color, width, height, rs.format.bgr8, 30)
    config.enable_stream(rs.stream.depth, width, height, rs.format.z16, 30)
    try:
        profile = pipeline.start(config)
    except RuntimeError as error:  # no camera, or none with this mode
        raise SystemExit(f"RealSense: cannot stream colour and depth at {width}x{height}, 30 Hz: {error}") from None
    intrinsics = profile.get_stream(rs.stream.color).as_video_stream_profile().get_intrinsics()
    device = profile.get_device()
    name = device.get_info(rs.camera_info.name)  # "Intel RealSense D435I"
    model = next((model for model in D4XX_BASELINES if model in name), None)
    # coeffs: k1 k2 p1 p2 k3, taken as OpenCV's model as the shipped RealSense files do (0 on a D435's colour stream)
    camera = hoidslam.Camera(fx=intrinsics.fx, fy=intrinsics.fy, cx=intrinsics.ppx, cy=intrinsics.ppy,
                             width=intrinsics.width, height=intrinsics.height, distortion=intrinsics.coeffs,
                             depth_scale=device.first_depth_sensor().get_depth_scale(),  # metres per depth unit
                             **({"baseline": D4XX_BASELINES[model]} if model else {}))
    baseline = f"the {model}'s nominal" if model else "hoidslam's default: no nominal value for this model"
    origin = (f"the RealSense SDK ({name}): the colour stream's intrinsics at {width}x{height}, the depth sensor's "
              f"depth scale; baseline {camera.baseline:g} m, {baseline} (the SDK reports none)")
    align = rs.align(rs.stream.color)

    def read():
        arrived, frames = pipeline.try_wait_for_frames(5000)
        if not arrived:  # no frame for 5 s: the camera has stopped
            return None
        frames = align.process(frames)
        colour, depth = frames.get_color_frame(), frames.get_depth_frame()
        return np.asanyarray(colour.get_data()), np.asanyarray(depth.get_data()), colour.get_timestamp() / 1000.0

    return read, camera, origin


def image_size(text):
    """--size WIDTHxHEIGHT."""
    try:
        width, height = map(int, text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not WIDTHxHEIGHT, e.g. 848x480") from None
    return width, height


def open_camera(args, options):
    """The source and the System for its camera: the values --settings gives, else the camera's own (the RealSense
    SDK's), else the shipped file the source calls for. Prints once which values and where they come from."""
    slam = hoidslam.System(settings=args.settings, **options) if args.settings else None  # overrides the camera's
    origin = f"the settings file {args.settings}"
    if args.replay:
        read = Replay(args.replay, args.preload_mb)
        if not slam:
            settings = hoidslam.settings_for(args.replay)
            slam = hoidslam.System(settings=settings, **options)
            origin = f"{settings}, the file the folder's name calls for" if settings else \
                "hoidslam's default, the TUM fr3 camera (the folder's name calls for no shipped file)"
    elif args.opencv is not None:
        read = opencv_source(args.opencv)
        if not slam:
            # OpenNI reports no intrinsics of the colour camera: OpenCV's CAP_PROP_OPENNI_FOCAL_LENGTH is the IR
            # camera's focal length, not the colour camera's, from whose view the registered depth is seen.
            settings = hoidslam.shipped_dir() / "config" / "Kinect_v1_OpenNI.yaml"
            slam = hoidslam.System(settings=settings, **options)
            origin = (f"{settings}: the Kinect v1's nominal values, as OpenNI reports no colour intrinsics (OpenCV's "
                      "OpenNI focal length is the IR camera's); --settings with your camera's calibration is better")
    else:
        size = args.size or ((slam.width, slam.height) if slam else (640, 480))  # --settings: the file's size
        read, camera, sdk_origin = realsense_source(*size)
        if not slam:
            print(f"camera: {camera}, from {sdk_origin}")
            return read, hoidslam.System(camera=camera, **options)
        origin += " (not the RealSense SDK's values)"
        if abs(camera.depth_scale * slam.depth_factor - 1) > 0.01:
            print(f"warning: the camera's depth scale is {camera.depth_scale:g} m a unit, but {args.settings} has "
                  f"{slam.depth_factor:g} units a metre (DepthMapFactor)", file=sys.stderr)
    print(f"camera: {slam.width}x{slam.height}, {slam.depth_factor:g} depth units a metre, from {origin}")
    return read, slam


def run(args):
    detector = dict(detector="onnx", model=args.model) if args.model else dict(detector="none", filter="none")
    read, slam = open_camera(args, dict(realtime=args.realtime, **detector))
    milliseconds, tracked, begin = [], 0, None
    try:
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
    except KeyboardInterrupt:  # Ctrl-C ends the run as the end of the stream does
        print("stopped (Ctrl-C)")
    if not milliseconds:
        print("no frames from the camera", file=sys.stderr)
        return 1
    seconds = time.monotonic() - begin
    if args.out:
        slam.save(args.out)  # finishes first
    else:
        slam.finish()
    dropped = getattr(read, "dropped", 0)
    print(f"{len(milliseconds)} frames in {seconds:.1f} s ({len(milliseconds) / seconds:.1f} per second), "
          f"{tracked} tracked, {dropped} dropped arriving while busy; median {statistics.median(milliseconds):.1f} ms "
          f"a frame")
    if args.out:
        print(f"wrote {args.out}/: trajectory.txt, keyframes.txt, map.ply")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--replay", help="play a recorded sequence at its recorded rate")
    source.add_argument("--opencv", type=int, help="an OpenNI2 RGB-D camera by index")
    source.add_argument("--realsense", action="store_true", help="an Intel RealSense (pyrealsense2)")
    parser.add_argument("--settings", help="the camera's settings file, in place of the values the camera reports "
                        "(default: --realsense the SDK's, --opencv config/Kinect_v1_OpenNI.yaml, --replay the file "
                        "the folder's name calls for, else TUM fr3)")
    parser.add_argument("--size", type=image_size, help="--realsense: the stream size, e.g. 848x480 (default: the "
                        "--settings file's, else 640x480)")
    parser.add_argument("--out", help="at the end or on Ctrl-C, save trajectory.txt, keyframes.txt and map.ply here")
    parser.add_argument("--model", help="YOLO ONNX model for the detector (default: no detector, filter none)")
    parser.add_argument("--realtime", action="store_true", help="the detector in its own thread")
    parser.add_argument("--preload-mb", type=int, default=2048, help="--replay: memory for frames decoded ahead")
    parser.add_argument("--quiet", action="store_true", help="only the camera and the summary, not a line per frame")
    args = parser.parse_args(argv)
    if args.size and not args.realsense:
        parser.error("--size is for --realsense")
    try:
        return run(args)
    except hoidslam.InputError as error:  # bad settings, or frames the camera's values do not fit: one line
        print(f"live_camera.py: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
