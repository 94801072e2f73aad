"""Reports of the sample projects and of the tests' scenes are pinned byte for byte (timings aside).

A refactoring must not change any report; a deliberate change regenerates the pinned files with
``python tests/golden/scenes.py`` in the same commit (see ``tests/golden/scenes.py``).
"""
from __future__ import annotations

import difflib

import pytest
from golden.scenes import BOXES, SAMPLES, pinned, run_reports


@pytest.mark.parametrize("name", [*SAMPLES, *BOXES])
def test_reports_unchanged(name, tmp_path):
    got = run_reports(name, tmp_path)
    want = pinned(name)
    for fname, text in want.items():
        if got[fname] != text:
            diff = "".join(list(difflib.unified_diff(text.splitlines(True), got[fname].splitlines(True), "pinned", "now", n=1))[:40])
            pytest.fail(f"{name}/{fname} differs from the pinned report:\n{diff}")
