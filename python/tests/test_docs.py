"""The five lines of the README and of docs/python.md run as shown, in a folder holding the sequence `walk`."""

import os
import pathlib
import re

import pytest

REPO = pathlib.Path(os.environ.get("HOIDSLAM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.mark.parametrize("document", ["README.md", "docs/python.md"])
def test_the_five_line_example_tracks_the_walk(document, walk, tmp_path, monkeypatch):
    code = re.search(r"```python\n(import hoidslam.*?)```", (REPO / document).read_text(), re.S).group(1)
    assert len(code.strip().splitlines()) == 5
    (tmp_path / "walk").symlink_to(walk)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, document, "exec"), {})
    assert len((tmp_path / "out" / "trajectory.txt").read_text().splitlines()) == 31  # a header, 30 frames
