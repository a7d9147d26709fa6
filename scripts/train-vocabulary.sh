#!/usr/bin/env bash
# Trains the shipped vocabulary, data/vocabulary/orb-k10-l5.hbow, again from nothing (docs/vocabulary.md):
#  1. renders every 12th frame of six synthetic scenarios with seeds the shipped scenarios do not use (101-106 for
#     the sensor noise and the procedural textures, where the scenarios have 1), every second one with the shared
#     photo textures on its walls, desks and posters;
#  2. trains on those frames and on the shared photos and textures (`hoidslam vocabulary`, k = 10, L = 5), never
#     on the TUM frames or the frames of the shipped scenarios that the tests and the benchmark run on.
#
#   scripts/train-vocabulary.sh [OUT]   writes OUT (default data/vocabulary/orb-k10-l5.hbow)
#
# The rendered frames stay in out/vocabulary-training/. The same build gives the same file, byte for byte.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOIDSLAM_BUILD_DIR:-$repo/build}"
shared="${HOIDSLAM_SHARED_DIR:-$repo/../shared}"
vocabulary="${1:-$repo/data/vocabulary/orb-k10-l5.hbow}"
work="$repo/out/vocabulary-training"
mkdir -p "$work"

scenarios=(walking_xyz walking_halfsphere walking_rpy sitting_static carry crowd)
folders=("$shared/data/photos" "$shared/data/textures")
for i in "${!scenarios[@]}"; do
  scenario="${scenarios[$i]}"
  seed=$((101 + i))
  # The shipped scenario with its seed replaced and a texture seed of its own.
  "$build/hoidslam" synth --print-scenario "$scenario" |
    sed "s/^  \"seed\": 1,\$/  \"seed\": $seed,\n  \"textures\": {\"seed\": $seed},/" >"$work/$scenario.json"
  if ! grep -q "\"textures\": {\"seed\": $seed}" "$work/$scenario.json"; then
    echo "train-vocabulary: scenario $scenario no longer has the line '  \"seed\": 1,' to replace" >&2
    exit 1
  fi
  photo_textures=()
  ((i % 2 == 1)) && photo_textures=(--textures "$shared/data/textures")
  "$build/hoidslam" synth --scenario "$work/$scenario.json" --data-dir "$shared/data/tum" "${photo_textures[@]}" \
    --frame-step 12 --threads 2 --out "$work/$scenario" --force
  folders+=("$work/$scenario/rgb")
done

"$build/hoidslam" vocabulary --images "${folders[@]}" --features 1000 --branching 10 --levels 5 --iterations 10 \
  --seed 1 --out "$vocabulary"
