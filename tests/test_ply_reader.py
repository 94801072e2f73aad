"""The binary PLY fast path gives trimesh's mesh, and passes every other PLY on to trimesh."""
from __future__ import annotations

import numpy as np
import pytest

from en17037cli.io.ply import _binary_triangles, read_ply
from en17037cli.io.trimesh_formats import read_with_trimesh
from en17037cli.samples import write_ply


def _same(a, b) -> None:
    assert np.array_equal(a.vertices, b.vertices) and a.vertices.dtype == b.vertices.dtype
    assert np.array_equal(a.triangles, b.triangles) and a.triangles.dtype == b.triangles.dtype
    assert np.array_equal(a.part, b.part)
    assert a.parts == b.parts and (a.units, a.up_axis, a.warnings) == (b.units, b.up_axis, b.warnings)


def test_binary_triangles_as_trimesh(tmp_path):
    rng = np.random.default_rng(3)
    v = rng.normal(size=(40, 3)) * 10
    v[0] = [-0.0, 0.0, -0.0]
    f = rng.integers(0, 40, size=(60, 3))
    path = tmp_path / "m.ply"
    write_ply(path, v, f)
    assert _binary_triangles(path.read_bytes()) is not None  # the fast path took it
    _same(read_ply(path), read_with_trimesh(path))
    assert not np.signbit(read_ply(path).vertices[0]).any()


def _quad_ply(path):
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "<f4")
    rec = np.zeros(1, dtype=[("n", "u1"), ("i", "<i4", (4,))])
    rec["n"], rec["i"] = 4, [0, 1, 2, 3]
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n")
    path.write_bytes(head.encode() + v.tobytes() + rec.tobytes())


def _ascii_ply(path):
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")


@pytest.mark.parametrize("make", [_quad_ply, _ascii_ply])
def test_other_files_go_to_trimesh(tmp_path, make):
    path = tmp_path / "m.ply"
    make(path)
    assert _binary_triangles(path.read_bytes()) is None
    _same(read_ply(path), read_with_trimesh(path))
