"""Fixtures of hoidslam's Python tests: the shared data (../shared beside the checkout, or $HOIDSLAM_SHARED_DIR;
missing: skipped, in CI a failure, as the C++ tests do) and a short synthetic sequence rendered once a session."""

import os
import pathlib

import pytest

import hoidslam

REPO = pathlib.Path(os.environ.get("HOIDSLAM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def shared_path(relative: str) -> pathlib.Path:
    shared = os.environ.get("HOIDSLAM_SHARED_DIR") or os.environ.get("HOIDSLAM_DEFAULT_SHARED_DIR") or REPO / ".." / "shared"
    path = pathlib.Path(shared) / relative
    if not path.exists():
        if os.environ.get("CI") == "true":
            pytest.fail(f"shared test data missing in CI: {path}")
        pytest.skip(f"shared test data not found: {path} (set HOIDSLAM_SHARED_DIR)")
    return path


@pytest.fixture(scope="session")
def walk(tmp_path_factory) -> pathlib.Path:
    """30 frames of walking_xyz (every 4th: people carry things in view from about frame 25), exact boxes."""
    folder = tmp_path_factory.mktemp("sequences") / "walk"
    hoidslam.render_synthetic(folder, "walking_xyz", frames=120, frame_step=4, tum_dir=shared_path("data/tum"))
    return folder
