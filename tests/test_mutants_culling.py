"""Mutation tests (issue 39): the culling of the exact sun hours (``criteria/sunlight/culling.py``):
the extent of spherical triangles against a brute force over their surface, the window pyramids and
which faces are kept, by hand.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

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


def test_spherical_extent_of_triangles_around_the_axis_and_of_arcs():
    axis = np.array([0.0, 0.0, 1.0])
    up = np.array([[[1.0, 0.0, 1.0], [-1.0, 1.0, 1.0], [-1.0, -1.0, 1.0]]])  # holds +z: the top is 1
    lo, hi = culling.spherical_extent(up, axis)
    assert hi[0] == 1.0 and lo[0] == pytest.approx(1 / np.sqrt(3), abs=1e-12)
    lo, hi = culling.spherical_extent(-up, axis)  # holds -z: the bottom is -1
    assert lo[0] == -1.0 and hi[0] == pytest.approx(-1 / np.sqrt(3), abs=1e-12)
    # an arc from the horizon to 45 deg up, through azimuths: its extremes at its ends; a great-circle arc over
    # the top (from (1, 0, 1) to (-1, 0, 1)) reaches the zenith in its middle
    arc = np.array([[[1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [1.0, 0.0, 0.0]], [[1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 1.0]]])
    lo, hi = culling.spherical_extent(arc, axis)
    assert lo.tolist() == pytest.approx([0.0, np.sqrt(0.5)], abs=1e-12) and hi.tolist() == pytest.approx([np.sqrt(0.5), 1.0], abs=1e-12)
    # a triangle with a zero-length edge is its arc
    lo, hi = culling.spherical_extent(np.array([[[1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]]]), axis)
    assert hi[0] == pytest.approx(1.0, abs=1e-12) and lo[0] == pytest.approx(np.sqrt(0.5), abs=1e-12)


WIN = SimpleNamespace(normal=np.array([0.0, -1.0, 0.0]), centroid=np.array([0.5, 0.0, 1.5]),
                      triangles=np.array([[[-1.0, 0.0, 1.0], [2.0, 0.0, 1.0], [2.0, 0.0, 2.0]],
                                          [[-1.0, 0.0, 1.0], [2.0, 0.0, 2.0], [-1.0, 0.0, 2.0]]]))


def test_window_pyramid_holds_exactly_the_rays_through_the_rectangle():
    p = np.array([0.3, 2.0, 1.2])
    tri = SimpleNamespace(normal=np.array([0.0, -1.0, 0.0]), centroid=np.array([0.0, 0.0, 1.0]),
                          triangles=np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 3.0]]]))
    g = culling.window_pyramid(p, [WIN, tri])
    assert g.shape == (2, 4, 3)
    xs, zs = np.meshgrid(np.linspace(-3, 4, 141), np.linspace(-2, 5, 141))
    q = np.column_stack([xs.ravel(), np.zeros(xs.size), zs.ravel()])
    for k, (x0, x1, z0, z1) in enumerate(((-1.0, 2.0, 1.0, 2.0), (0.0, 1.0, 0.0, 3.0))):  # a triangle: its bounding rectangle
        inside = np.all((q - p) @ g[k].T >= -1e-12, axis=1)
        rect = (q[:, 0] >= x0 - 1e-9) & (q[:, 0] <= x1 + 1e-9) & (q[:, 2] >= z0 - 1e-9) & (q[:, 2] <= z1 + 1e-9)
        assert np.array_equal(inside, rect)
        assert np.all((q[rect] - p) @ g[k].T > -1e-9)
    assert culling.window_pyramid(p, []).shape == (0, 4, 3)


def _square(c, half, axis):
    """Two triangles of a square of side 2 half centred on c, normal to ``axis`` (0, 1 or 2)."""
    i, j = [k for k in range(3) if k != axis]
    corners = []
    for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        v = np.array(c, float)
        v[i] += a * half
        v[j] += b * half
        corners.append(v)
    return [corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]]


def test_cull_triangles_by_hand():
    """From P inside a south window (room at y > 0, window in y = 0, x in [-1, 2], z in [1, 2]) at 52 deg N,
    1 February to 21 March (declinations -17.5 to 0.5 deg), minimum altitude 10 deg. Faces: 0 outside in
    front, in the band and the pyramid (kept); 1 behind the window's plane; 2 far to the east-south-east,
    17 deg up, in the band but outside the pyramid; 3 in the band but 4-6 deg up; 4 high overhead, out of
    the band; 5 one corner at P (kept); 6 a huge face around P (kept: its radius passes 90 deg)."""
    from en17037cli.criteria.sunlight.exact import pole_vector

    p = np.array([0.5, 1.0, 1.5])
    faces = [_square((0.5, -5.0, 4.0), 1.0, 1), _square((0.5, 3.0, 1.5), 1.0, 1), _square((32.5, -19.0, 13.5), 1.0, 1),
             _square((27.5, -11.0, 4.1), 0.5, 1), _square((0.5, -5.0, 60.0), 1.0, 2),
             [p, p + [0.1, -3.0, 0.0], p + [0.0, -3.0, 0.5], p, p + [0.0, -3.0, 0.5], p + [-0.1, -3.0, 0.2]],
             _square((0.5, -1.0, 1.5), 1000.0, 1)]
    verts = np.array([v for f in faces for v in f])
    tris = np.arange(len(verts)).reshape(-1, 3)
    pole = pole_vector(52.0, 0.0)
    band = (np.sin(np.radians(-17.5)), np.sin(np.radians(0.5)))
    low = np.sin(np.radians(10.0))
    pyr = culling.window_pyramid(p, [WIN])
    kept = culling.cull_triangles(verts, tris, np.arange(len(tris)), p, WIN.normal, pyr, pole, band, low)
    assert sorted(set((kept // 2).tolist())) == [0, 5, 6]
    # without pyramids only the window's plane, the band and the altitude count: face 2 comes back
    none = np.zeros((0, 4, 3))
    kept = culling.cull_triangles(verts, tris, np.arange(len(tris)), p, WIN.normal, none, pole, band, low)
    assert sorted(set((kept // 2).tolist())) == [0, 2, 5, 6]
    # and with a lower minimum altitude (3 deg) face 3 too; in the summer's band (17-23 deg) not face 0
    kept = culling.cull_triangles(verts, tris, np.arange(len(tris)), p, WIN.normal, none, pole, band, np.sin(np.radians(3.0)))
    assert sorted(set((kept // 2).tolist())) == [0, 2, 3, 5, 6]
    assert len(culling.cull_triangles(verts, tris, np.array([0, 1]), p, WIN.normal, pyr, pole, (0.3, 0.4), low)) == 0
    assert len(culling.cull_triangles(verts, tris, np.zeros(0, int), p, WIN.normal, pyr, pole, band, low)) == 0
