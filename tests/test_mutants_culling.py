"""Mutation tests (issue 39): the culling of the exact sun hours (``criteria/sunlight/culling.py``):
the extent of spherical triangles against a brute force over their surface, the window pyramids and
which faces are kept, by hand.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.sunlight import culling


def _brute_extent(tri, axis, n=400):
    """Smallest and largest axis . x over the spherical triangle, from points spread over it."""
    i, j = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    keep = i + j <= 1
    a, b = i[keep], j[keep]
    p = tri[0] + a[:, None] * (tri[1] - tri[0]) + b[:, None] * (tri[2] - tri[0])
    v = (p / np.linalg.norm(p, axis=1)[:, None]) @ axis
    return v.min(), v.max()


def test_spherical_extent_against_a_brute_force():
    rng = np.random.default_rng(3)
    axis = np.array([0.0, 0.6, 0.8])
    for _ in range(20):
        tri = rng.normal(size=(3, 3)) + [0.0, 0.0, 0.5]
        lo, hi = culling.spherical_extent(tri[None], axis)
        blo, bhi = _brute_extent(tri, axis)
        # the brute force samples the surface: it lies inside the exact range, within its spacing
        assert lo[0] <= blo + 1e-12 and hi[0] >= bhi - 1e-12
        assert blo - lo[0] < 5e-3 and hi[0] - bhi < 5e-3
