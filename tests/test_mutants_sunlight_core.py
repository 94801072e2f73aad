"""Mutation tests (issue 21): point P of EN 17037 Annex A.3 by hand.

``reveal_depth`` and ``point_p`` are driven by a stand-in ray engine whose faces are planes
x = const parallel to a window with outward normal +x (width axis +y, so window_axes gives
a = (0, 1, 0), up = (0, 0, 1)); each ray travels along -x and meets the nearest plane behind its
origin whose lateral band holds it. The expected depths and points are worked by hand from those
planes; tolerances are 1e-9 m (float round-off of sums of a few decimetres, far below any face gap).
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from en17037cli.criteria.sunlight import point_p as pp
from en17037cli.errors import NotAssessable

TOL = 1e-9  # round-off of a few additions of decimetre values
RESTART = 1e-6  # the stand-in engine's restart offset [m]


class PlaneEngine:
    """Faces: (plane_x, y_min, y_max, triangle index); rays along -x only."""

    def __init__(self, faces):
        self.faces = faces

    def first_hit(self, group, origins, dirs):
        assert group == "interior"
        assert np.allclose(dirs, [-1.0, 0.0, 0.0])
        face = np.full(len(origins), -1)
        t = np.full(len(origins), np.inf)
        for i, (ox, oy, _) in enumerate(origins):
            best = -np.inf
            for x, y0, y1, tri in self.faces:
                if x < ox and y0 <= oy <= y1 and x > best:
                    best, face[i], t[i] = x, tri, ox - x
        return face, t

    def restart_offset(self, points):
        return np.full(len(points), RESTART)


def _scene(planes):
    """Triangle k: a 0.1 m right triangle in the plane x = planes[k] (None: a face normal to y)."""
    verts, tris = [], []
    for x in planes:
        b = len(verts)
        if x is None:
            verts += [(0.0, 3.0, 0.0), (0.1, 3.0, 0.0), (0.0, 3.0, 0.1)]
        else:
            verts += [(x, 0.0, 0.0), (x, 0.1, 0.0), (x, 0.0, 0.1)]
        tris.append((b, b + 1, b + 2))
    return SimpleNamespace(vertices=np.array(verts), triangles=np.array(tris))


N = np.array([1.0, 0.0, 0.0])
A = np.array([0.0, 1.0, 0.0])
START = np.zeros(3)
HALF = 0.5  # half width of the glass; probes at 0.52, 0.62, 0.75 m either side

# triangle 0: the wall's inner face 0.2 m behind the glazing plane; 1: a face normal to the
# window (not parallel); 2: the wall's outer face in the glazing plane
WALL = _scene([-0.2, None, 0.0])


def _wall(y0, y1):
    return [(-0.2, y0, y1, 0), (0.0, y0, y1, 2)]


def test_reveal_depth_wall_both_sides():
    # outer face at depth 0, inner face (triangle index 0, 0.1 m triangle) at 0.2 m
    eng = PlaneEngine(_wall(0.5, 10.0) + _wall(-10.0, -0.5))
    assert pp.reveal_depth(eng, WALL, START, N, A, HALF, 1.0) == pytest.approx(0.2, abs=TOL)


@pytest.mark.parametrize("y0,y1", [(0.5, 10.0), (-10.0, -0.5)])
def test_reveal_depth_wall_one_side(y0, y1):
    # a wall on one jamb only: the probes of that side find it, the others hit nothing
    eng = PlaneEngine(_wall(y0, y1))
    assert pp.reveal_depth(eng, WALL, START, N, A, HALF, 1.0) == pytest.approx(0.2, abs=TOL)


def test_reveal_depth_nothing_hit_is_float_zero():
    d = pp.reveal_depth(PlaneEngine([]), WALL, START, N, A, HALF, 1.0)
    assert isinstance(d, float) and d == 0.0


def test_reveal_depth_face_not_parallel_ignored():
    # only the face normal to y (|cos| = 0 with the window normal) at 0.3 m: no reveal
    eng = PlaneEngine([(-0.3, -10.0, 10.0, 1)])
    assert pp.reveal_depth(eng, WALL, START, N, A, HALF, 1.0) == 0.0


def test_reveal_depth_four_crossings():
    # parallel faces at 0, 0.05, 0.10, 0.15, 0.20 m: the search stops after four crossings
    # (outer face, inner face, beyond), so 0.15 m
    xs = [0.0, -0.05, -0.10, -0.15, -0.20]
    scene = _scene(xs)
    eng = PlaneEngine([(x, -10.0, 10.0, k) for k, x in enumerate(xs)])
    assert pp.reveal_depth(eng, scene, START, N, A, HALF, 1.0) == pytest.approx(0.15, abs=TOL)


def test_reveal_depth_face_at_max_depth_counts():
    # a single parallel face exactly at max_depth (0.25 m): "within max_depth" includes it
    scene = _scene([-0.25])
    eng = PlaneEngine([(-0.25, -10.0, 10.0, 0)])
    assert pp.reveal_depth(eng, scene, START, N, A, HALF, 0.25) == 0.25
    assert pp.reveal_depth(eng, scene, START, N, A, HALF, 0.24) == 0.0


def _window(verts, normal, sill, head):
    v = np.array(verts, dtype=float)
    return SimpleNamespace(name="w", normal=np.array(normal, dtype=float), triangles=v.reshape(1, 3, 3),
                           centroid=v.mean(axis=0), sill_z=sill, head_z=head)


NO_HIT = SimpleNamespace(first_hit=lambda g, o, d: (np.full(len(o), -1), np.full(len(o), np.inf)),
                         restart_offset=lambda pts: np.full(len(pts), RESTART))  # any direction, nothing hit
ROOM = SimpleNamespace(name="r", floor_z=0.0)
SETTINGS = SimpleNamespace(max_reveal_depth_m=1.0)


def test_point_p_vertical_triangle_no_reveal():
    # triangle window in x = 0: width y in [0, 2] (centre y = 1, the centroid's y is 2/3),
    # sill 1.0, head 2.0: z_p = max(0 + 1.2, 1.0 + 0.3) = 1.3; no reveal: moved 1 mm inwards
    w = _window([(0, 0, 1.0), (0, 2, 1.0), (0, 0, 2.0)], N, 1.0, 2.0)
    p, depth, notes = pp.point_p(PlaneEngine([]), WALL, ROOM, w, SETTINGS)
    np.testing.assert_allclose(p, [-0.001, 1.0, 1.3], atol=TOL)
    assert depth == 0.0
    assert len(notes) == 1 and "moved 1 mm into the room" in notes[0] and "window 'w'" in notes[0]


def test_point_p_vertical_with_reveal():
    # same window, wall 0.2 m thick on both sides of y in [0, 2] (probes at y = 1 +- 1.02 ...)
    w = _window([(0, 0, 1.0), (0, 2, 1.0), (0, 0, 2.0)], N, 1.0, 2.0)
    eng = PlaneEngine(_wall(2.0, 10.0) + _wall(-10.0, 0.0))
    p, depth, notes = pp.point_p(eng, WALL, ROOM, w, SETTINGS)
    assert depth == pytest.approx(0.2, abs=TOL)
    np.testing.assert_allclose(p, [-0.2, 1.0, 1.3], atol=TOL)
    assert notes == []


def test_point_p_tilted_window():
    # normal (0.6, 0, 0.8): a = (0, 1, 0), up = (-0.8, 0, 0.6); triangle b, b + 2a, b + up with
    # b = (0, 0, 1.5): sill 1.5, head 2.1, z_p = 1.8, i.e. 0.5 along up from b: q = (-0.4, 1, 1.8);
    # p = q - 1 mm * normal
    n = [0.6, 0.0, 0.8]
    w = _window([(0, 0, 1.5), (0, 2, 1.5), (-0.8, 0, 2.1)], n, 1.5, 2.1)
    p, depth, _ = pp.point_p(NO_HIT, WALL, ROOM, w, SETTINGS)
    np.testing.assert_allclose(p, [-0.4 - 0.0006, 1.0, 1.8 - 0.0008], atol=TOL)
    assert depth == 0.0


def test_point_p_skylight():
    # horizontal window in z = 3 (normal +z): width axis x, x in [0, 2] -> centre x = 1, the
    # centroid's y = 1/3 kept; no height to move along (up is horizontal): p = centre - 1 mm * z
    w = _window([(0, 0, 3.0), (2, 0, 3.0), (0, 1, 3.0)], [0, 0, 1], 0.0, 3.0)
    p, depth, _ = pp.point_p(NO_HIT, WALL, ROOM, w, SETTINGS)
    np.testing.assert_allclose(p, [1.0, 1.0 / 3.0, 2.999], atol=TOL)
    assert depth == 0.0


def test_point_p_reveal_of_exactly_glazing_offset_kept(monkeypatch):
    # a reveal of exactly GLAZING_OFFSET_M (1 mm) is a reveal: P 1 mm behind, no note
    monkeypatch.setattr(pp, "reveal_depth", lambda *a, **k: 1e-3)
    w = _window([(0, 0, 1.0), (0, 2, 1.0), (0, 0, 2.0)], N, 1.0, 2.0)
    p, depth, notes = pp.point_p(PlaneEngine([]), WALL, ROOM, w, SETTINGS)
    assert depth == 1e-3 and notes == []
    np.testing.assert_allclose(p, [-0.001, 1.0, 1.3], atol=TOL)


def test_point_p_height_sill_rule_and_head_boundary():
    # sill 1.0: max(1.2, 1.3) = 1.3
    assert pp.point_p_height(ROOM, SimpleNamespace(name="w", sill_z=1.0, head_z=2.0)) == pytest.approx(1.3, abs=TOL)
    # P exactly at the head (sill 0.5 -> 1.2 = head) is in the opening
    assert pp.point_p_height(ROOM, SimpleNamespace(name="w", sill_z=0.5, head_z=1.2)) == 1.2
    # head 1 nm below 1.2: head + 1e-9 == 1.2 in float, still accepted (tolerance 1e-9)
    assert pp.point_p_height(ROOM, SimpleNamespace(name="w", sill_z=0.5, head_z=1.2 - 1e-9)) == 1.2


def test_point_p_height_message_relative_to_floor():
    # floor 10, sill 10.5, head 11: P at 11.2 (1.2 above the floor) above the head (1.0 above it)
    room = SimpleNamespace(name="r", floor_z=10.0)
    with pytest.raises(NotAssessable) as e:
        pp.point_p_height(room, SimpleNamespace(name="w", sill_z=10.5, head_z=11.0))
    assert "= 1.200 m above" in str(e.value) and "(1.000 m)" in str(e.value)


def test_bisect_transitions_needs_a_stop():
    from en17037cli.bisection import bisect_transitions
    with pytest.raises(ValueError, match=r"^bisect_transitions: give iterations or max_width$"):
        bisect_transitions(lambda k, x: x > 0, np.zeros(1), np.zeros(1), np.ones(1), np.zeros(1, bool))


def test_bisect_transitions_bracket_exactly_max_width_untouched():
    # a bracket already max_width wide (1.0) is not halved: "at most max_width"
    from en17037cli.bisection import bisect_transitions
    calls = []
    lo, hi = bisect_transitions(lambda k, x: calls.append(x) or x > 0.3, np.zeros(1), np.zeros(1), np.ones(1),
                                np.zeros(1, bool), max_width=1.0)
    assert calls == [] and lo[0] == 0.0 and hi[0] == 1.0
    # 0.5 wide: one halving around the change at 0.3 -> [0.25, 0.5] after two, stop at <= 0.25
    lo, hi = bisect_transitions(lambda k, x: x > 0.3, np.zeros(1), np.zeros(1), np.ones(1), np.zeros(1, bool), max_width=0.25)
    assert (lo[0], hi[0]) == (0.25, 0.5)


def _vis(spans):
    def f(t):
        t = np.asarray(t, dtype=float)
        return np.any([(t >= a) & (t <= b) for a, b in spans], axis=0)
    return f


def test_visible_intervals_two_days_by_hand():
    # day 0: [0, 95] s, samples 0, 10, ..., 90 and 95 (t1); sun seen on [23.3, 61.7] and from
    # 92.0 to the end (its rise lies in the last, shorter step 90-95).
    # day 1: [1000, 1050] s (a shorter day), seen from its start to 1004.2 (rise-free: starts seen).
    # tolerance 0.01 s: every transition within 0.01 s of the hand value
    from en17037cli.criteria.sunlight.intervals import visible_intervals
    vis = _vis([(23.3, 61.7), (92.0, 95.0), (1000.0, 1004.2)])
    iv, err = visible_intervals(vis, np.array([0.0, 1000.0]), np.array([95.0, 1050.0]), 10.0, 0.01)
    assert len(iv) == 2
    np.testing.assert_allclose(iv[0], [[23.3, 61.7], [92.0, 95.0]], atol=0.01)
    np.testing.assert_allclose(iv[1], [[1000.0, 1004.2]], atol=0.01)
    assert np.all(err <= 3 * 0.01) and np.all(err >= 0)


def test_visible_intervals_float_even_for_whole_numbers():
    # seen all day on integer day bounds: one interval (t0, t1), returned as float (documented)
    from en17037cli.criteria.sunlight.intervals import visible_intervals
    iv, err = visible_intervals(lambda t: np.ones(len(t), bool), np.array([0]), np.array([60]), 10.0, 0.01)
    assert iv[0].dtype == np.float64 and iv[0].tolist() == [[0.0, 60.0]]
    assert err.tolist() == [0.0]


def _sun_path():
    from en17037cli.criteria.sunlight.visibility import SunPath
    loc = SimpleNamespace(latitude=48.85, longitude=2.35, elevation_m=500.0, timezone="UTC")
    settings = SimpleNamespace(refraction=True, pressure_mbar=950.0, temperature_c=25.0, min_altitude_deg=0.0)
    return loc, settings, SunPath(loc, settings)


# 2026-03-20 05:00 UTC onwards every 2 min for 300 samples (sunrise in Paris ~05:55 UTC)
T_GRID = 1773982800 + 120 * np.arange(300)


def test_sun_path_matches_pvlib_with_site_weather():
    # pvlib's SPA with the same elevation, pressure, temperature and refraction; the SPA here
    # agrees with pvlib's to ~1e-5 deg (test_mutants_spa), 1e-4 deg leaves margin. Where the sun
    # is up by more than 1 deg refraction is 0.2-0.5 deg near the horizon and depends on
    # pressure and temperature, so a dropped or shifted weather argument shows.
    from tests.oracles import sun_position
    loc, _, sp = _sun_path()
    elev, azim = sp(T_GRID.astype(float))
    e_ref, a_ref = sun_position(T_GRID.astype(float), loc.latitude, loc.longitude, refraction=True,
                                elevation_m=500.0, pressure_mbar=950.0, temperature_c=25.0)
    up = e_ref > 1.0
    assert up.sum() > 100 and (e_ref[up] < 10).any()
    np.testing.assert_allclose(elev[up], e_ref[up], atol=1e-4)
    np.testing.assert_allclose(azim[up], a_ref[up], atol=1e-4)


def test_sun_path_memo_of_long_float_grids_only():
    from en17037cli.criteria.sunlight.visibility import MEMO_MIN_TIMES
    assert MEMO_MIN_TIMES == 256
    _, _, sp = _sun_path()
    t = T_GRID[:256].astype(float)
    r1 = sp(t)
    r2 = sp(t.copy())
    assert r2[0] is r1[0] and r2[1] is r1[1]  # 256 times: remembered
    # integer times are the same float times: the same entry
    r3 = sp(T_GRID[:256])
    assert r3[0] is r1[0]
    # shorter arrays (the bisection's) are computed afresh
    s1, s2 = sp(t[:255]), sp(t[:255].copy())
    assert s1[0] is not s2[0]
    np.testing.assert_array_equal(s1[0], r1[0][:255])


def test_point_p_probe_stops_where_the_rooms_space_begins():
    """No host named; the probe finds the wall's inner face at 0.2 m and, deeper, a shelf's face at
    0.6 m: with the room's space beginning 0.2 m behind the glazing, the reveal ends at most
    SPACE_REVEAL_SLACK_M (0.15 m) beyond it, 0.35 m, with a note; without a space, the shelf's."""
    scene = _scene([-0.2, -0.6])
    eng = PlaneEngine([(-0.2, 2.0, 10.0, 0), (-0.2, -10.0, 0.0, 0), (-0.6, -10.0, 10.0, 1)])
    w = _window([(0, 0, 1.0), (0, 2, 1.0), (0, 0, 2.0)], N, 1.0, 2.0)
    _, depth, notes = pp.point_p(eng, scene, ROOM, w, SETTINGS)
    assert depth == pytest.approx(0.6, abs=TOL) and notes == []
    w.space_distance_m = 0.2
    p, depth, notes = pp.point_p(eng, scene, ROOM, w, SETTINGS)
    assert depth == pytest.approx(0.2 + pp.SPACE_REVEAL_SLACK_M, abs=TOL)
    np.testing.assert_allclose(p, [-0.35, 1.0, 1.3], atol=TOL)
    assert len(notes) == 1 and "where the room's space begins" in notes[0]
    w.space_distance_m = 0.5  # the space begins beyond the shelf: the probe's face stands
    _, depth, _ = pp.point_p(eng, scene, ROOM, w, SETTINGS)
    assert depth == pytest.approx(0.6, abs=TOL)


def test_point_p_at_the_end_of_an_open_light_well():
    """A skylight whose room lies 0.7 m below it along an open path (``open_depth_m``): P lies
    there, capped by max_reveal_depth_m (1.0 m here), with a note."""
    w = _window([(0, 0, 3.0), (2, 0, 3.0), (0, 1, 3.0)], [0, 0, 1], 0.0, 3.0)
    w.open_depth_m = 0.7
    p, depth, notes = pp.point_p(NO_HIT, WALL, ROOM, w, SETTINGS)
    np.testing.assert_allclose(p, [1.0, 1.0 / 3.0, 2.3], atol=TOL)
    assert depth == pytest.approx(0.7) and "light well" in notes[0]
    w.open_depth_m = 1.7
    _, depth, _ = pp.point_p(NO_HIT, WALL, ROOM, w, SETTINGS)
    assert depth == pytest.approx(SETTINGS.max_reveal_depth_m)
