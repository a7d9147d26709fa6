#!/usr/bin/env bash
# Installs hoidslam from a build folder into a fresh prefix and uses it as another program would: the installed
# command's --version, the shipped files where the installed library looks for them, and the C++ example of
# examples/cpp configured against the prefix (find_package(hoidslam)), built, and run on a short synthetic
# sequence the installed command renders. CTest runs it as install.PackageBuildsAndRunsAConsumer (so
# scripts/test.sh and CI do, on their clean clone); then the installed Python module. Exit status 77: shared data missing outside CI (skipped).
#
#   scripts/check-install.sh [BUILD_DIR]
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-${HOIDSLAM_BUILD_DIR:-$repo/build}}"
tum="${HOIDSLAM_SHARED_DIR:-$repo/../shared}/data/tum"
if [[ ! -d "$tum" ]]; then
  echo "shared data not found: $tum (set HOIDSLAM_SHARED_DIR)"
  [[ "${CI:-}" == "true" ]] && exit 1
  exit 77
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

cmake --install "$build" --prefix "$prefix" >/dev/null
version="$(sed -n 's/^project(hoidslam VERSION \([0-9.]*\).*/\1/p' "$repo/CMakeLists.txt")"
[[ "$("$prefix/bin/hoidslam" --version)" == "hoidslam $version" ]] || { echo "--version is not $version"; exit 1; }

cmake -S "$repo/examples/cpp" -B "$work/example" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/example" >/dev/null

"$prefix/bin/hoidslam" synth --scenario walking_xyz --frames 48 --frame-step 4 --data-dir "$tum" \
                             --out "$work/walk" >/dev/null 2>&1
"$work/example/track_folder" "$work/walk" "$work/out" --settings "$prefix/share/hoidslam/config/TUM3.yaml" \
  | tee "$work/log.txt" | tail -n 3
grep -qx "shipped files: $prefix/share/hoidslam" "$work/log.txt" || { echo "not the installed shipped files"; exit 1; }
grep -q "^12 of 12 frames tracked" "$work/log.txt"
[[ -s "$work/out/trajectory.txt" && -s "$work/out/map.ply" ]]
# The same frames with the camera given by its values, as a program takes them from its camera's SDK.
"$work/example/track_folder" "$work/walk" "$work/out-camera" --camera 535.4,539.2,320.1,247.6,640,480 \
  --depth-scale 0.0002 | tail -n 1 | grep -q "^12 of 12 frames tracked"

# The Python module from the prefix (Debian's python3 finds <prefix>/lib/python3/dist-packages by itself for
# /usr/local; elsewhere PYTHONPATH names it), over the installed libhoidslam.so and shipped files.
PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 - "$prefix" "$work/walk" <<'PYTHON'
import sys
import hoidslam
prefix, walk = sys.argv[1:]
assert hoidslam.__file__.startswith(prefix), hoidslam.__file__
assert str(hoidslam.shipped_dir()) == prefix + "/share/hoidslam", hoidslam.shipped_dir()
slam = hoidslam.System(filter="none")
states = [slam.track(f.rgb, f.depth, f.timestamp).state for f in hoidslam.Sequence(walk)]
assert states == ["ok"] * 12, states
PYTHON
echo "installed package: OK ($prefix)"
