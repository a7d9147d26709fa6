#!/usr/bin/env bash
# The main job, on data that needs no download:
#  1. the detector and the HOID filter on the real TUM fr3/walking_xyz frames of the shared data folder: every
#     detection's verdict is printed, and the frames are drawn with red (features dropped) and green (kept)
#     boxes into out/main-job/annotated/;
#  2. the demo (`hoidslam demo`): the synthetic scenario crowd (people walk up to the camera, talk to it and carry
#     things past it, filling most of the image for seconds, on the real TUM camera path), SLAM on it without a
#     filter (none), with the paper's HOID filter (hoid2d) and with the default mode (hoidplus), 3 threaded runs
#     each with ground-truth boxes, the median ATE beside the frames tracked, and the HTML report
#     out/main-job/demo/report.html with each run's own report in out/main-job/demo/runs/<run>/report.html;
#  3. on a machine with a display and a browser, a default-mode run of the same sequence shown live in the browser
#     (`hoidslam run --view`); elsewhere, the command that does it.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOIDSLAM_BUILD_DIR:-$repo/build}"
shared="${HOIDSLAM_SHARED_DIR:-$repo/../shared}"
out="$repo/out/main-job"
mkdir -p "$out"

"$build/hoidslam" detect "$shared/data/tum/fr3_walking_xyz_pair" \
  --model "$shared/models/yolox_nano.onnx" \
  --settings "$repo/config/TUM3.yaml" --mode hoid3d \
  --out "$out/detections.jsonl" --explain --annotate "$out/annotated" --force
echo "annotated TUM frames: $out/annotated/"
echo

HOIDSLAM_SHARED_DIR="$shared" "$build/hoidslam" demo --out "$out/demo"

if [[ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]] && command -v xdg-open > /dev/null; then
  port=8787
  echo
  echo "the live viewer: a default-mode run of the demo's sequence at http://127.0.0.1:$port/"
  "$build/hoidslam" run "$out/demo/sequences/crowd" --out "$out/live" --force --snapshots 0 \
    --view --view-port "$port" > "$out/live.log" 2>&1 &
  sleep 2
  xdg-open "http://127.0.0.1:$port/" > /dev/null 2>&1 || echo "open http://127.0.0.1:$port/ in a browser"
  wait
fi
