"""Reports of the sample projects and of the tests' scenes are pinned (timings aside).

A refactoring must not change any report; a deliberate change regenerates the pinned files with
``python tests/golden/scenes.py`` in the same commit (see ``tests/golden/scenes.py``).

The comparison is byte for byte for every word and for the layout; numbers may differ by
:data:`NUMBER_ATOL` + :data:`NUMBER_RTOL` x |pinned|. Embree traces in float32 with kernels chosen
for the CPU (AVX2, AVX-512): a ray that meets the shared edge of a landscape face and the ground
can hit either on another CPU. On the seed office an AMD EPYC (AVX2) moves two viewpoints' ground
and landscape solid angles by 5e-6 sr against the pinned (same figures run to run: byte identity on
one machine is ``test_cli.py::test_reports_are_byte_identical_apart_from_timings``).
"""
from __future__ import annotations

import difflib
import re

import pytest
from golden.scenes import BOXES, SAMPLES, pinned, run_reports

#: Allowed difference of a number between the pinned report and this machine's: absolute part
#: (one view cell's solid angle at the seed's resolution is about 5e-6 sr) and relative part.
NUMBER_ATOL = 2e-5
NUMBER_RTOL = 1e-5

_NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def differences(want: str, got: str) -> list[str]:
    """Lines of ``got`` that differ from ``want`` in a word, or in a number by more than the
    tolerance (lines must correspond one to one)."""
    a, b = want.splitlines(), got.splitlines()
    if len(a) != len(b):
        return [f"{len(a)} lines pinned, {len(b)} now"]
    out = []
    for i, (x, y) in enumerate(zip(a, b)):
        if x == y:
            continue
        if _NUMBER.sub("#", x) != _NUMBER.sub("#", y):
            out.append(f"line {i + 1}: pinned {x.strip()!r}, now {y.strip()!r}")
            continue
        for p, q in zip(_NUMBER.findall(x), _NUMBER.findall(y)):
            if abs(float(p) - float(q)) > NUMBER_ATOL + NUMBER_RTOL * abs(float(p)):
                out.append(f"line {i + 1}: {p} pinned, {q} now: {x.strip()!r}")
                break
    return out


def test_differences_sees_words_and_numbers():
    assert differences("a 0.069481 b", "a 0.069486 b") == []
    assert differences("a 0.0694 b", "a 0.0698 b")
    assert differences("level medium", "level high")
    assert differences("x\ny", "x")


@pytest.mark.parametrize("name", [*SAMPLES, *BOXES])
def test_reports_unchanged(name, tmp_path):
    got = run_reports(name, tmp_path)
    want = pinned(name)
    for fname, text in want.items():
        if got[fname] != text and differences(text, got[fname]):
            diff = "".join(list(difflib.unified_diff(text.splitlines(True), got[fname].splitlines(True), "pinned", "now", n=1))[:40])
            pytest.fail(f"{name}/{fname} differs from the pinned report:\n" + "\n".join(differences(text, got[fname])[:10]) + "\n" + diff)
