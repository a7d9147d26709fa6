#!/usr/bin/env bash
# Sets up hoidslam on Debian 12 from nothing: installs the build dependencies from Debian's packages,
# builds the Release binaries into build/, and runs the main job on data that needs no download. Chromium (the
# report and viewer tests open pages headless), Node.js and npm (the viewer's page is bundled at build time), GNU
# parallel (bench sweeps across cores or machines), and clang with its sanitizer and libFuzzer runtimes and the lld
# linker (scripts/sanitize.sh, scripts/fuzz.sh) are Debian packages too.
#
#   scripts/setup.sh            install + build + run the main job
#   scripts/setup.sh --no-run   install + build only (used by CI and scripts/test.sh)
#
# Safe to run again: packages already installed are not touched, and the build is incremental.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOIDSLAM_BUILD_DIR:-$repo/build}"
run_main_job=1
[[ "${1:-}" == "--no-run" ]] && run_main_job=0

packages=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libeigen3-dev libceres-dev
  libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev libssl-dev libcpp-httplib-dev
  # dense mapping: Open3D's TSDF volume, OctoMap; Open3D's Python bindings open the meshes in the tests
  libopen3d-dev liboctomap-dev python3-open3d
  libgtest-dev libgmock-dev libbenchmark-dev
  chromium parallel
  # the viewer's page (web/): npm installs three.js and esbuild at build time
  nodejs npm
  # the Python module (python/) and its tests and examples
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-pil
  # scripts/sanitize.sh and scripts/fuzz.sh: clang with the sanitizer and libFuzzer runtimes, llvm-symbolizer, lld
  clang-14 libclang-rt-14-dev llvm-14 lld-14
)

# A package counts as there when an installed package provides it: NodeSource's nodejs provides npm, and
# Debian's npm conflicts with it.
provided=" $(dpkg-query -W -f='${Status}|${Provides}\n' 2>/dev/null | sed -n 's/^install ok installed|//p' |
             tr ',' '\n' | sed 's/([^)]*)//; s/^ *//; s/ *$//' | tr '\n' ' ') "
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
    [[ "$provided" == *" $package "* ]] || missing+=("$package")
done
if ((${#missing[@]} > 0)); then
  echo "hoidslam setup: installing ${missing[*]}"
  sudo_cmd=()
  [[ "$(id -u)" -ne 0 ]] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# A new build folder is a unity build (CMakeLists.txt): the first build takes about half as long. A folder that
# exists keeps its own choice; a developer who edits one file at a time may turn it off there
# (cmake -B build -DCMAKE_UNITY_BUILD=OFF) to recompile only that file.
unity=()
[[ -f "$build/CMakeCache.txt" ]] || unity=(-DCMAKE_UNITY_BUILD=ON)
cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "${unity[@]}"
cmake --build "$build" -j "$(nproc)"

if ((run_main_job)); then
  "$repo/scripts/main-job.sh"
fi
