"""The vectorised OBJ reader gives the line-by-line reader's mesh, warnings and messages."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from en17037cli.errors import InputError
from en17037cli.io.obj import _read_fast, _read_lines, read_obj

ROOT = Path(__file__).resolve().parent.parent

CASES = {
    "plain": "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n",
    "names": "o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\ng x y\nusemtl glass\nf 1 2 3\no b\nf 1 2 3\nusemtl glass\no a\ng x   y\nf 3 2 1\n",
    "slashes": "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3//1\nf -4/1 -2 -1/\n",
    "ngon concave": "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 2 1 0\nv 0 4 0\nf 1 2 3 4 5\nf 1 2 3 4\nf 1 2 3\n",
    "short faces": "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\nf\nf 1 9\nf 1 2 3\n",
    "crlf and comments": "# hi\r\nv 0 0 0 1\r\nv 1 0 0 0.5 0.5 0.5\r\n\r\nv\t1 1 0\r\n   \r\nf\t1 2 3 \r\n",
    "bom and no final newline": "\ufeffv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3",
    "odd tokens": "v +1 -0 1e-3\nv inf 0 0\nv 1 nan 0\nv 1 1 1\nf 1 4 4 1\nf +1 2 -1\nvx 1 2\nfoo\n",
    "unicode names": "o caf\u00e9 \u00e0\u00a0b\nv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n",
    "no faces": "v 0 0 0\n",
    "tabs": "v 0\t0 0\nv 1.5 -.5\t0.\nv 1 1 0\t\nf 1\t2 3\nf 3 2 1\n",
    "long index": "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 0000000000000000000003\n",
    "empty": "",
    "bad vertex": "v 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n",
    "bad face": "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n",
    "index 0": "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 0 1 2\n",
    "forward reference": "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 1 1 0\n",
    "slash first": "v 0 0 0\nv 1 0 0\nv 1 1 0\nf /1 2 3\n",
    "indented": "v 0 0 0\n  v 1 0 0\nv 1 1 0\nf 1 2 3\n",
    "form feed": "v 0 0 0\nv 1 0 0\fv 1 1 0\nf 1 2 3\n",
    "nbsp tag": "v\u00a00 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 2 3 4\n",
}


def _outcome(fn, path):
    try:
        m = fn(path)
    except InputError as exc:
        return ("error", str(exc))
    return ("mesh", m.vertices.tobytes(), m.vertices.shape, m.triangles.tolist(), m.part.tolist(), m.parts, m.warnings)


@pytest.mark.parametrize("name", sorted(CASES))
def test_same_as_line_reader(tmp_path, name):
    path = tmp_path / "m.obj"
    path.write_bytes(CASES[name].encode("utf-8"))
    assert _outcome(read_obj, path) == _outcome(_read_lines, path)


def test_fast_path_taken_for_ordinary_files():
    for name in ("plain", "tabs", "long index", "names", "slashes", "ngon concave", "short faces", "crlf and comments", "odd tokens", "unicode names"):
        assert _read_fast(CASES[name].encode("utf-8")) is not None, name


@pytest.mark.parametrize("path", sorted(ROOT.glob("sample_projects/**/*.obj")), ids=lambda p: p.name)
def test_sample_files(path):
    assert _read_fast(path.read_bytes()) is not None
    a, b = _outcome(read_obj, path), _outcome(_read_lines, path)
    assert a == b


def test_shuffled_city(tmp_path):
    rng = np.random.default_rng(5)
    v = rng.normal(size=(300, 3))
    lines = []
    for i in range(300):
        lines.append(f"v {v[i, 0]!r} {v[i, 1]!r} {v[i, 2]!r}")
        if i % 37 == 5:
            lines.append(f"o building {i % 3}")
        if i >= 3 and i % 2:
            k = int(rng.integers(3, 7))
            lines.append("f " + " ".join(str(int(j) + 1) for j in rng.choice(i, size=k, replace=False)))
    path = tmp_path / "c.obj"
    path.write_text("\n".join(lines) + "\n")
    assert _outcome(read_obj, path) == _outcome(_read_lines, path)
