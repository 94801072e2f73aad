"""Triangles handed to Embree through its buffers (numpy) trace as embreex's TriangleMesh does."""
from __future__ import annotations

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

from en17037cli.raytrace import _embree_c, add_triangles


def test_buffers_trace_as_triangle_mesh():
    assert _embree_c() is not None  # the layout checks pass with the embreex this project installs
    rng = np.random.default_rng(7)
    m = 5000
    tri = (rng.random((m, 1, 3)) * 20 + rng.random((m, 3, 3))).astype(np.float32)
    a, b = rtcs.EmbreeScene(), rtcs.EmbreeScene()
    TriangleMesh(a, tri)
    assert add_triangles(b, tri)
    o = (rng.random((20000, 3)) * 20).astype(np.float32)
    d = rng.normal(size=(20000, 3)).astype(np.float32)
    d /= np.linalg.norm(d, axis=1)[:, None]
    ra, rb = a.run(o, d, output=1), b.run(o, d, output=1)
    assert (ra["primID"] >= 0).mean() > 0.2  # enough hits to mean something
    for key in ra:
        assert np.array_equal(ra[key], rb[key]), key
    assert np.array_equal(a.run(o, d, query="OCCLUDED"), b.run(o, d, query="OCCLUDED"))
