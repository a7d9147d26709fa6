#!/usr/bin/env bash
# The main job, on data that needs no download:
#  1. the detector and the HOID filter on the real TUM fr3/walking_xyz frames of the shared data folder: every
#     detection's verdict is printed, and the frames are drawn with red (features dropped) and green (kept)
#     boxes into out/main-job/annotated/;
#  2. the demo (`hoidslam demo`): 300 frames of the synthetic scenario walking_rpy (people walking, picking up and
#     carrying things while the camera turns, on the real TUM camera path), SLAM on it without a filter (none),
#     with the paper's HOID filter (hoid2d) and with the default mode (hoidplus), ground-truth boxes, the ATE
#     table, and the HTML report
#     out/main-job/demo/report.html with each run's own report in out/main-job/demo/runs/<run>/report.html.
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
