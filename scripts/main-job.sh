#!/usr/bin/env bash
# The main job, on data that needs no download:
#  1. the detector and the HOID filter on the real TUM fr3/walking_xyz frames of the shared data folder: every
#     detection's verdict is printed, and the frames are drawn with red (features dropped) and green (kept)
#     boxes into out/main-job/annotated/;
#  2. 150 frames of the shipped synthetic scenario walking_xyz (every second frame of its first ten seconds:
#     people walking, picking up and carrying things in an office, on the real TUM camera path), with its preview
#     picture out/main-job/synth_walking_xyz.png;
#  3. SLAM on that sequence with the HOID filter (hoid2d, ground-truth boxes) and without any filter (none): the
#     trajectory, map and per-frame log of each in out/main-job/run_<mode>/, and the ATE against ground truth.
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

HOIDSLAM_SHARED_DIR="$shared" "$build/hoidslam" synth --scenario walking_xyz --frames 300 --frame-step 2 --force \
  --out "$out/synth_walking_xyz" --preview "$out/synth_walking_xyz.png"

for mode in hoid2d none; do
  echo
  "$build/hoidslam" run "$out/synth_walking_xyz" --settings "$repo/config/TUM3.yaml" --filter "$mode" \
    --out "$out/run_$mode" --force
done

echo
echo "annotated TUM frames:      $out/annotated/"
echo "synthetic sequence:        $out/synth_walking_xyz/ (TUM layout, with ground truth)"
echo "its preview:               $out/synth_walking_xyz.png"
echo "SLAM runs (hoid2d, none):  $out/run_hoid2d/, $out/run_none/ (trajectory.txt, map.ply, frames.jsonl, ...)"
