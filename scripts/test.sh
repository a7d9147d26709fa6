#!/usr/bin/env bash
# Runs the whole hoidslam test suite (builds first if needed). Shared test data is looked up in
# $HOIDSLAM_SHARED_DIR, default: the `shared` folder beside the checkout.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOIDSLAM_BUILD_DIR:-$repo/build}"
"$repo/scripts/setup.sh" --no-run
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "$@"
