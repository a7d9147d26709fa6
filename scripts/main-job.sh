#!/usr/bin/env bash
# The main job, on data that needs no download:
#  1. the detector and the HOID filter on the real TUM fr3/walking_xyz frames of the shared data folder: every
#     detection's verdict is printed, and the frames are drawn with red (features dropped) and green (kept)
#     boxes into out/main-job/annotated/;
#  2. the first 150 frames of the shipped synthetic scenario walking_xyz (people picking up and carrying things
#     in an office, on the real TUM camera path), with its preview picture out/main-job/synth_walking_xyz.png.
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

HOIDSLAM_SHARED_DIR="$shared" "$build/hoidslam" synth --scenario walking_xyz --frames 150 --force \
  --out "$out/synth_walking_xyz" --preview "$out/synth_walking_xyz.png"

echo
echo "annotated TUM frames:      $out/annotated/"
echo "synthetic sequence:        $out/synth_walking_xyz/ (TUM layout, with ground truth)"
echo "its preview:               $out/synth_walking_xyz.png"
