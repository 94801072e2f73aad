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


# --- cull_triangles face by face: each test of the cull in isolation --------------------------------

POLE52 = np.array([0.0, np.cos(np.radians(52.0)), np.sin(np.radians(52.0))])
ALL = (-1.0, 1.0)  # every declination (sines)
NO_PYRAMID = np.zeros((0, 4, 3))


def _dec_dir(dec_deg, h_deg):
    """Unit vector at declination ``dec_deg`` and hour angle ``h_deg`` about POLE52 (meridian towards -y)."""
    m0 = np.array([0.0, -np.sin(np.radians(52.0)), np.cos(np.radians(52.0))])
    w = np.array([-1.0, 0.0, 0.0])
    d, h = np.radians(dec_deg), np.radians(h_deg)
    return np.cos(d) * (np.cos(h) * m0 + np.sin(h) * w) + np.sin(d) * POLE52


def _alt_dir(alt_deg, az_deg):
    a, e = np.radians(az_deg), np.radians(alt_deg)
    return np.array([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), np.sin(e)])


def _cull(corners, normal, pyramids=NO_PYRAMID, band=ALL, sin_alt=-1.0, p=None):
    """cull_triangles of faces given as corners (f, 3, 3) [m] seen from ``p``: the kept face numbers."""
    p = np.zeros(3) if p is None else p
    corners = np.asarray(corners, float)
    verts = corners.reshape(-1, 3)
    tris = np.arange(len(verts)).reshape(-1, 3)
    return culling.cull_triangles(verts, tris, np.arange(len(tris)), p, np.asarray(normal, float), pyramids, POLE52, band,
                                  sin_alt).tolist()


def test_cull_of_a_single_face():
    """One face behind the plane of the window (normal -y through P): dropped; one in front but wholly below
    the horizon with a minimum altitude of 10 deg: dropped by the later tests."""
    behind = [[[0.0, 2.0, 0.0], [1.0, 2.0, 0.0], [0.0, 2.0, 1.0]]]
    assert _cull(behind, [0.0, -1.0, 0.0]) == []
    low = [[[-0.2, -5.0, -1.0], [0.2, -5.0, -1.0], [0.0, -5.0, -0.8]]]
    assert _cull(low, [0.0, -1.0, 0.0], sin_alt=np.sin(np.radians(10.0))) == []
    assert _cull(low, [0.0, -1.0, 0.0]) == [0]


def test_cull_keeps_faces_within_the_slack_of_the_plane_and_of_a_pyramid_side():
    """A face whose corners lie 0.5 ANGLE_SLACK x their distance behind the plane through P: kept; 2 x:
    dropped. The same across a side of the pyramid over the window of test_cull_triangles_by_hand."""
    s = culling.ANGLE_SLACK
    n = np.array([0.0, -1.0, 0.0])
    base = np.array([[3.0, 0.0, 4.0], [-2.0, 0.0, 6.0], [1.0, 0.0, 9.0]])  # in the plane y = 0 through P = 0
    for k, want in ((0.5, [0]), (2.0, [])):
        face = base - k * s * np.linalg.norm(base, axis=1)[:, None] * n  # behind: against the normal
        assert _cull([face], n) == want, k
    p = np.array([0.5, 1.0, 1.5])
    g = culling.window_pyramid(p, [WIN])[0]
    east = g[np.argmax(g[:, 0] < 0)]  # the side through the window's east edge x = 2: inward normal towards -x
    east = east / np.linalg.norm(east)
    on = p + np.array([[4.5, -3.0, 0.0], [4.8, -3.2, 0.1], [4.6, -3.1, 0.3]])  # beyond the east edge's line ...
    on -= ((on - p) @ east)[:, None] * east  # ... moved into the side plane exactly
    assert np.all(((on - p) @ g[[i for i in range(4) if not np.allclose(g[i] / np.linalg.norm(g[i]), east)]].T) > 0)
    for k, want in ((0.0, [0]), (0.5, [0]), (2.0, [])):
        face = on - k * s * np.linalg.norm(on - p, axis=1)[:, None] * east  # outside the side by k slacks
        assert _cull([face], WIN.normal, culling.window_pyramid(p, [WIN]), p=p) == want, k


def test_cull_with_two_windows_and_a_face_seen_through_one_corner():
    """Two windows: a face inside the first one's pyramid only is kept. A face with only its second corner
    in front of the window and inside its pyramid (the others far behind P): kept."""
    p = np.array([0.5, 1.0, 1.5])
    far = SimpleNamespace(normal=np.array([0.0, -1.0, 0.0]), centroid=np.array([30.5, 0.0, 1.5]),
                          triangles=WIN.triangles + [30.0, 0.0, 0.0])
    pyr = culling.window_pyramid(p, [WIN, far])
    ahead = np.array([[0.3, -5.0, 1.4], [0.7, -5.0, 1.4], [0.5, -5.0, 1.7]])  # straight out through WIN
    assert _cull([ahead], WIN.normal, pyr, p=p) == [0]
    assert _cull([ahead], WIN.normal, pyr[::-1], p=p) == [0]
    one = np.array([[100.0, 50.0, -50.0], [0.5, -5.0, 1.5], [-100.0, 60.0, -40.0]])
    assert _cull([one], WIN.normal, culling.window_pyramid(p, [WIN]), p=p) == [0]


def test_cull_quick_bound_keeps_what_the_exact_extent_keeps():
    """Faces the quick cap bound must not drop (each then kept by the exact extent of spherical_extent):
    one with a corner at P, whose cap is 60 deg about the zero vector, under a minimum altitude of 70 deg;
    one whose cap passes 90 deg (not convex: its edge bulges out of it to declination -76.5 deg, the
    band -78 to -72 deg); the cap through the farthest corner (the second), not the third; the altitude
    and the declination of the first corner, not the second's; faces within 1 m of P (unit vectors)."""
    # a corner at P
    close = np.array([[0.0, 0.0, 0.0], [0.0, -1.0, 10.0], [0.1, -1.0, 10.0]])
    assert _cull([close], [0.0, -1.0, 0.0], band=(0.3, 0.4), sin_alt=np.sin(np.radians(70.0))) == [0]
    # a cap over 90 deg: corners at declination 80 (hour angle 0) and -20 (hour angles -85, +85)
    wide = np.array([_dec_dir(80.0, 0.0), _dec_dir(-20.0, -85.0), _dec_dir(-20.0, 85.0)]) * 10.0
    mid = wide[1] + wide[2]
    assert np.degrees(np.arcsin(mid @ POLE52 / np.linalg.norm(mid))) == pytest.approx(-76.5, abs=0.1)
    band = (np.sin(np.radians(-78.0)), np.sin(np.radians(-72.0)))
    assert _cull([wide], _dec_dir(80.0, 0.0), band=band) == [0]
    # the farthest corner is the second: declinations 0, -30, -2 (hour angle 0), band -35 to -25
    far2 = np.array([_dec_dir(0.0, 0.0), _dec_dir(-30.0, 0.0), _dec_dir(-2.0, 0.0)]) * 10.0
    band = (np.sin(np.radians(-35.0)), np.sin(np.radians(-25.0)))
    assert _cull([far2], _dec_dir(0.0, 0.0), band=band) == [0]
    # altitudes 40 (first), 10 (second, the farthest), 45 (third), minimum altitude 44
    alts = np.array([_alt_dir(40.0, 180.0), _alt_dir(10.0, 180.0), _alt_dir(45.0, 182.0)]) * 10.0
    assert _cull([alts], _alt_dir(0.0, 180.0), sin_alt=np.sin(np.radians(44.0))) == [0]
    # declinations 0 (first), -30 (second, the farthest), 5 (third), band 4 to 6
    decs = np.array([_dec_dir(0.0, 0.0), _dec_dir(-30.0, 0.0), _dec_dir(5.0, 3.0)]) * 10.0
    band = (np.sin(np.radians(4.0)), np.sin(np.radians(6.0)))
    assert _cull([decs], _dec_dir(0.0, 0.0), band=band) == [0]
    # 0.5 m from P, 80 deg up, minimum altitude 60 deg
    near = np.array([_alt_dir(80.0, 0.0), _alt_dir(80.0, 10.0), _alt_dir(78.0, 5.0)]) * 0.5
    assert _cull([near], [0.0, 0.0, 1.0], sin_alt=np.sin(np.radians(60.0))) == [0]
    # and the same faces out of reach are dropped: under a minimum altitude of 89 deg, or a band beyond
    assert _cull([near], [0.0, 0.0, 1.0], sin_alt=np.sin(np.radians(89.0))) == []
    assert _cull([decs], _dec_dir(0.0, 0.0), band=(np.sin(np.radians(6.0)), np.sin(np.radians(8.0)))) == []


def test_cull_of_faces_nearly_opposite_and_on_the_slack():
    """A face whose corners are 156 deg apart (declination 80 deg against -70 deg at hour angles +-80): its
    cap is no bound, its edge reaches declination -86.4 deg, in the band -89 to -85: kept. A face up to
    20 deg only, its cap wide: dropped under a minimum altitude of 30 deg. Faces that reach the minimum
    altitude or the band by half the slack (ANGLE_SLACK, on sines) short: kept; the quick cap bound when
    its farthest corner lies straight above the first (the bound is then exact): kept."""
    s = culling.ANGLE_SLACK
    wide = np.array([_dec_dir(80.0, 0.0), _dec_dir(-70.0, -80.0), _dec_dir(-70.0, 80.0)]) * 10.0
    mid = wide[1] + wide[2]
    assert np.degrees(np.arcsin(mid @ POLE52 / np.linalg.norm(mid))) == pytest.approx(-86.4, abs=0.1)
    assert _cull([wide], _dec_dir(80.0, 0.0), band=(np.sin(np.radians(-89.0)), np.sin(np.radians(-85.0)))) == [0]
    # a sliver from declination 80 to its far second corner at -70 (156 deg away), its third corner by the first
    sliver = np.array([_dec_dir(80.0, 0.0), _dec_dir(-70.0, -80.0), _dec_dir(79.0, 2.0)]) * 10.0
    assert _cull([sliver], _dec_dir(80.0, 0.0), band=(np.sin(np.radians(-75.0)), np.sin(np.radians(-65.0)))) == [0]
    low = np.array([_alt_dir(20.0, 180.0), _alt_dir(-60.0, 170.0), _alt_dir(-60.0, 190.0)]) * 10.0
    assert _cull([low], _alt_dir(0.0, 180.0), sin_alt=np.sin(np.radians(30.0))) == []
    assert _cull([low], _alt_dir(0.0, 180.0), sin_alt=np.sin(np.radians(19.0))) == [0]
    # a face 0.01 deg across (its edges bulge from the great circles of its corners' values by ~1e-9, well
    # under the slack): its highest point, and its extreme declinations, are corners
    face = np.array([_alt_dir(30.0, 180.0), _alt_dir(29.99, 179.99), _alt_dir(29.99, 180.01)]) * 10.0
    top = face[0][2] / np.linalg.norm(face[0])
    n = _alt_dir(0.0, 180.0)
    for k, want in ((0.5, [0]), (1.5, [])):
        assert _cull([face], n, sin_alt=top + k * s) == want, k
    d = face @ POLE52 / np.linalg.norm(face, axis=1)
    for k, want in ((0.5, [0]), (1.5, [])):
        assert _cull([face], n, band=(d.max() + k * s, 1.0)) == want, k
        assert _cull([face], n, band=(-1.0, d.min() - k * s)) == want, k
    # corner 0 at 10 deg, the farthest corner 1 straight above it at 30 deg: the cap reaches 30 deg exactly
    cap = np.array([_alt_dir(10.0, 180.0), _alt_dir(30.0, 180.0), _alt_dir(11.0, 180.5)]) * 10.0
    assert _cull([cap], n, sin_alt=np.sin(np.radians(30.0) + 0.5 * s)) == [0]


def test_spherical_extent_of_several_triangles_at_once():
    """Each triangle of a batch on its own: one holding +z (top 1), one holding -z (bottom -1), one beside."""
    up = [[1.0, 0.0, 1.0], [-1.0, 1.0, 1.0], [-1.0, -1.0, 1.0]]
    down = [[1.0, 0.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, -1.0]]
    side = [[1.0, 0.0, 0.0], [1.0, 0.1, 0.0], [1.0, 0.0, 0.1]]
    lo, hi = culling.spherical_extent(np.array([up, down, side]), np.array([0.0, 0.0, 1.0]))
    assert hi[0] == 1.0 and lo[1] == -1.0
    assert lo.tolist()[0] == pytest.approx(1 / np.sqrt(3), abs=1e-12) and hi.tolist()[1] == pytest.approx(-1 / np.sqrt(3), abs=1e-12)
    assert lo[2] == pytest.approx(0.0, abs=1e-12) and hi[2] == pytest.approx(0.1 / np.hypot(1.0, 0.1), abs=1e-12)
