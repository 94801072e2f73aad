"""Mutation tests (issue 39): the exact sun intervals (``criteria/sunlight/exact.py``) and their
culling (``culling.py``), piece by piece against hand values, closed forms and brute force.
"""
from __future__ import annotations

import numpy as np
import pytest

from en17037cli.criteria.sunlight import culling, exact


def test_union_over_points_by_hand():
    # day 0: A sees [0, 10] and [20, 30], B [5, 12] and [30, 40]: merged [0, 12] and [20, 40] (touching at 30);
    # day 1: A [100, 110], B nothing
    a = [np.array([[0.0, 10.0], [20.0, 30.0]]), np.array([[100.0, 110.0]])]
    b = [np.array([[5.0, 12.0], [30.0, 40.0]]), np.zeros((0, 2))]
    iv, err = exact.union_intervals([a, b], [np.array([0.5, 0.25]), np.array([1.0, 0.0])], 2)
    assert iv[0].tolist() == [[0.0, 12.0], [20.0, 40.0]]
    assert iv[1].tolist() == [[100.0, 110.0]]
    assert err.tolist() == [1.5, 0.25]


def test_triangle_edges_are_the_distinct_sorted_edges():
    tri = np.array([[0, 1, 2], [2, 1, 3], [4, 5, 6]])
    assert culling.triangle_edges(tri, np.array([0, 1])).tolist() == [[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]
    assert culling.triangle_edges(tri, np.array([], int)).shape == (0, 2)


# --- the spline of the sun's path -----------------------------------------------------------------

W = 2 * np.pi / 86400.0  # a stand-in sun turning once a day at 30 deg elevation: a circle, |s''| = W^2 cos 30


def circle(t):
    t = np.asarray(t, float)
    return np.full(len(t), 30.0), np.degrees(W * t) % 360.0


def circle_vec(t):
    a = W * np.asarray(t, float)
    c = np.cos(np.radians(30.0))
    return np.column_stack([np.sin(a) * c, np.cos(a) * c, np.full(len(a), 0.5)])


def test_spline_of_a_circle_by_closed_form():
    sp = exact.SunSpline(circle, 1000.0, 1000.0 + 86400.0, 0.0)
    # knots every 600 s from two before the start: ceil(86400 / 600) + 1 + 4 of them
    assert sp.h == 600.0 and sp.t0 == 1000.0 - 1200.0 and len(sp.s) == 145 + 4 and sp.elev.tolist() == [30.0] * 149
    t = np.linspace(1000.0, 87400.0, 997)
    # Hermite interpolation of a circle: error (W h)^4 / 384 of its radius (7e-9 here)
    assert np.abs(sp(t) - circle_vec(t)).max() < 1e-8
    assert np.abs(sp(t, sp.piece(t)) - sp(t)).max() == 0.0
    # the knots' derivatives: fourth-order central differences (error (W h)^4 / 30 = 1.2e-7 of W); the two knots
    # at each end, outside the period, are never used inside it (the pieces there start at a knot, where the
    # interpolant is the knot's value whatever the derivatives)
    ds = W * np.column_stack([np.cos(W * (sp.t0 + sp.h * np.arange(149))) * np.cos(np.radians(30)),
                              -np.sin(W * (sp.t0 + sp.h * np.arange(149))) * np.cos(np.radians(30)), np.zeros(149)])
    assert np.abs(sp.ds[2:-2] - ds[2:-2]).max() < 1.2e-7 * W
    # the bound on |s''| per piece is that of the circle, W^2 cos 30, to the interpolant's accuracy
    assert np.allclose(sp.curvature[2:-2], W * W * np.cos(np.radians(30)), rtol=1e-3)


def test_spline_pieces_and_true_north():
    sp = exact.SunSpline(circle, 1000.0, 4000.0, 90.0)
    assert sp.piece(np.array([-1e9, -200.0, -199.0, 400.0, 1000.0, 1599.0, 1600.0, 1e12])).tolist() == [0, 0, 0, 1, 2, 2, 3, 8]
    # true north 90 deg clockwise from +y: the sun's azimuth A lies at A + 90 deg
    t = np.array([1500.0, 3000.0])
    a = W * t + np.pi / 2
    c = np.cos(np.radians(30.0))
    assert np.abs(sp(t) - np.column_stack([np.sin(a) * c, np.cos(a) * c, [0.5, 0.5]])).max() < 1e-8


# --- root brackets --------------------------------------------------------------------------------


def test_root_brackets_find_every_root_within_the_tolerance():
    fs = [np.sin, lambda t: (t - 5.0) ** 2 + 1.0, lambda t: np.cos(3 * t), lambda t: (t - 2.0) ** 2 - 1e-14]
    curv = np.array([1.0, 2.0, 9.0, 2.0])  # |f''| on every piece

    def values(k, t, pc):
        out = np.empty(len(t))
        for j, f in enumerate(fs):
            out[k == j] = f(t[k == j])
        return out

    key = np.array([0, 1, 2, 3])
    a, b = np.array([0.5, 0.0, 0.0, 0.0]), np.array([10.0, 10.0, 2.0, 4.0])
    k, lo, hi, simple = exact.root_brackets(values, lambda kk, pc: curv[kk], key, a, b, 1e-6, 1.0)
    roots = {0: [np.pi, 2 * np.pi, 3 * np.pi], 2: [np.pi / 6, np.pi / 2]}
    for j, rs in roots.items():
        sel = k == j
        assert sel.sum() == len(rs) and simple[sel].all()
        for r in rs:  # each root in one bracket no wider than the tolerance
            inside = sel & (lo <= r) & (r <= hi)
            assert inside.sum() == 1 and (hi - lo)[inside][0] <= 1e-6
    assert not (k == 1).any()  # (t - 5)^2 + 1 has none
    # a double root (two 1e-7 apart): pieces narrower than the tolerance, neither simple nor ruled out
    sel = k == 3
    assert sel.any() and not simple[sel].any() and np.all(hi[sel] - lo[sel] <= 1e-6)
    assert np.all((lo[sel] <= 2.0 + 1e-6) & (hi[sel] >= 2.0 - 1e-6))


def test_root_brackets_on_a_grid_of_pieces():
    # pieces of 2 s from the origin 1 s; the bound on |f''| per piece: f = sin(t) has |f''| <= 1, but a
    # bound of 0 on the pieces away from its roots would rule them out wrongly: the bounds are per piece
    calls = []

    def values(k, t, pc):
        calls.append((t.copy(), pc.copy()))
        return np.sin(t)

    k, lo, hi, simple = exact.root_brackets(values, lambda kk, pc: np.ones(len(kk)), np.array([7]), np.array([2.5]),
                                            np.array([10.0]), 1e-4, 2.0, lambda t: np.floor((np.asarray(t) - 1.0) / 2.0).astype(int),
                                            origin=1.0)
    assert k.tolist() == [7, 7, 7] and simple.all()
    assert np.allclose(0.5 * (lo + hi), [np.pi, 2 * np.pi, 3 * np.pi], atol=1e-4)
    # the first pieces: [2.5, 3], [3, 5], [5, 7], [7, 9], [9, 10] (the grid from the origin 1), evaluated at
    # both ends, each with the piece of its middle
    assert calls[0][0].tolist() == [2.5, 3.0, 5.0, 7.0, 9.0] and calls[1][0].tolist() == [3.0, 5.0, 7.0, 9.0, 10.0]
    assert calls[0][1].tolist() == calls[1][1].tolist() == [0, 1, 2, 3, 4]


def test_pole_vector_by_hand():
    c, s = np.cos(np.radians(52.0)), np.sin(np.radians(52.0))
    assert np.allclose(exact.pole_vector(52.0, 0.0), [0.0, c, s])
    assert np.allclose(exact.pole_vector(52.0, 90.0), [c, 0.0, s])
    c, s = np.cos(np.radians(33.0)), np.sin(np.radians(33.0))
    assert np.allclose(exact.pole_vector(-33.0, 0.0), [0.0, -c, s])
    # near the equator the north pole stands just above the northern horizon; on it, the northern horizon
    c, s = np.cos(np.radians(0.5)), np.sin(np.radians(0.5))
    assert np.allclose(exact.pole_vector(0.5, 0.0), [0.0, c, s]) and np.allclose(exact.pole_vector(-0.5, 0.0), [0.0, -c, s])
    assert np.allclose(exact.pole_vector(0.0, 0.0), [0.0, 1.0, 0.0])


def test_min_altitude_crossings_of_a_sine_day():
    # a stand-in sun whose elevation is 30 sin(W t) deg: it crosses 10 deg at asin(1/3) / W and (pi - asin(1/3)) / W
    def path(t):
        t = np.asarray(t, float)
        return 30.0 * np.sin(W * t), np.degrees(W * t) % 360.0

    t0, t1 = np.array([0.0, 86400.0]), np.array([86400.0, 172800.0])
    sp = exact.SunSpline(path, 0.0, 172800.0, 0.0)
    k, lo, hi, simple = exact._min_altitude_roots(sp, path, t0, t1, 10.0, 1e-3)
    r = np.arcsin(1 / 3) / W
    want = np.array([r, 43200.0 - r, 86400.0 + r, 129600.0 - r])
    assert k.tolist() == [0, 0, 1, 1] and simple.all()
    order = np.argsort(lo)
    assert np.all(lo[order] <= want + 1e-9) and np.all(hi[order] >= want - 1e-9) and np.all(hi - lo <= 1e-3)


# --- the merge of the intervals between candidate times -------------------------------------------


def test_merge_by_hand():
    # day 0: candidates 0, 1, 2, 3, 5; day 1: 10, 11, 12; the intervals between them seen or not
    t_c = np.array([0.0, 1.0, 2.0, 3.0, 5.0, 10.0, 11.0, 12.0])
    err = np.array([0.0, 0.1, 0.2, 0.3, 0.0, 0.0, 0.5, 0.0])
    d_c = np.array([0, 0, 0, 0, 0, 1, 1, 1])
    i0 = np.array([0, 1, 2, 3, 5, 6])
    iv, e = exact._merge(t_c, err, d_c, i0, np.array([True, True, False, True, False, True]), 2)
    # [0, 1] and [1, 2] run on: [0, 2]; [3, 5]; day 1: [11, 12]; each day's error: its intervals' ends'
    assert iv[0].tolist() == [[0.0, 2.0], [3.0, 5.0]] and iv[1].tolist() == [[11.0, 12.0]]
    assert e.tolist() == pytest.approx([0.0 + 0.2 + 0.3 + 0.0, 0.5 + 0.0])
    # a run does not continue across a day, even where the times meet
    t_c = np.array([0.0, 5.0, 5.0, 9.0])
    iv, e = exact._merge(t_c, np.array([0.0, 0.25, 0.5, 0.0]), np.array([0, 0, 1, 1]), np.array([0, 2]), np.array([True, True]), 2)
    assert iv[0].tolist() == [[0.0, 5.0]] and iv[1].tolist() == [[5.0, 9.0]] and e.tolist() == [0.25, 0.5]
    iv, e = exact._merge(t_c, np.zeros(4), np.array([0, 0, 1, 1]), np.array([0, 2]), np.array([False, False]), 2)
    assert [x.shape for x in iv] == [(0, 2), (0, 2)] and e.tolist() == [0.0, 0.0]


# --- the hour-angle windows of an edge's arc --------------------------------------------------------


def _equatorial(lat_deg, north_deg):
    """Pole, meridian (hour angle 0 at declination 0) and west, in the model frame at latitude ``lat_deg`` with
    true north ``north_deg`` clockwise from +y (a horizon azimuth A lies at model azimuth A + north)."""
    f, t = np.radians(lat_deg), np.radians(north_deg)
    rot = np.array([[np.cos(t), np.sin(t), 0.0], [-np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])  # clockwise by t
    return rot @ [0.0, np.cos(f), np.sin(f)], rot @ [0.0, -np.sin(f), np.cos(f)], rot @ [-1.0, 0.0, 0.0], rot


def _direction(h_deg, dec_deg, lat_deg, north_deg):
    """Model-frame unit vector at hour angle ``h_deg`` (westwards from the meridian) and declination ``dec_deg``."""
    pole, m0, w, _ = _equatorial(lat_deg, north_deg)
    h, d = np.radians(h_deg), np.radians(dec_deg)
    return np.cos(d) * (np.cos(h) * m0 + np.sin(h) * w) + np.sin(d) * pole


@pytest.mark.parametrize("lat, north", [(52.0, 30.0), (90.0, 0.0), (-33.0, 0.0), (0.0, 90.0)])
def test_hour_angle_windows_by_hand(lat, north):
    """A stand-in sun at declination -10 deg whose hour angle turns once a day, 0 at noon (43200 s): the
    arc from hour angle -30 deg (declination 25) to +15 deg (declination -35) is crossed, if at all,
    between 36000 s and 46800 s, widened by HOUR_ANGLE_SLACK_S; the hour angle is the sun's turn about
    the pole whatever the latitude and true north (at 90 deg the pole is exactly the zenith; at the
    equator with true north along +x, exactly +x)."""
    _, _, _, rot = _equatorial(lat, north)

    def path(t):
        h = np.degrees(W * (np.asarray(t, float) - 43200.0))
        s = np.array([_direction(x, -10.0, lat, north) for x in h]) @ rot  # back to the horizon frame
        return np.degrees(np.arcsin(s[:, 2])), np.degrees(np.arctan2(s[:, 0], s[:, 1]))

    sp = exact.SunSpline(path, 0.0, 86400.0, north)
    pole = _equatorial(lat, north)[0]
    pole = np.where(np.abs(pole) < 1e-12, 0.0, pole)  # (0, 0, 1) and (1, 0, 0) exactly, not 6e-17 off
    u, v = _direction(-30.0, 25.0, lat, north), _direction(15.0, -35.0, lat, north)
    slack = exact.HOUR_ANGLE_SLACK_S
    for a_, b_ in ((u, v), (v, u)):  # the short way round, either way
        lo, hi = exact._hour_angle_windows(sp, pole, a_[None], b_[None], np.array([0.0]), np.array([86400.0]))
        open_ = hi[0] > lo[0]
        assert open_.sum() == 1
        assert (lo[0][open_][0], hi[0][open_][0]) == pytest.approx((36000.0 - slack, 46800.0 + slack), abs=1e-3)
    # clipped to the day's span; a day starting 70 s before the window's end (inside the slack); a day
    # from noon to noon, which meets the window of that turn and of the next; the third of three days

    def windows(a, b, spline=sp):
        lo, hi = exact._hour_angle_windows(spline, pole, u[None], v[None], np.array([a]), np.array([b]))
        open_ = hi[0] > lo[0]
        return sorted(zip(lo[0][open_].tolist(), hi[0][open_].tolist()))

    assert _flat_pairs(windows(40000.0, 86400.0)) == pytest.approx([40000.0, 46800.0 + slack], abs=1e-3)
    assert _flat_pairs(windows(46850.0, 86400.0)) == pytest.approx([46850.0, 46800.0 + slack], abs=1e-3)
    sp3 = exact.SunSpline(path, 0.0, 3 * 86400.0, north)
    assert _flat_pairs(windows(43200.0, 129600.0, sp3)) == pytest.approx(
        [43200.0, 46800.0 + slack, 122400.0 - slack, 129600.0], abs=1e-3)
    assert _flat_pairs(windows(172800.0, 259200.0, sp3)) == pytest.approx(
        [172800.0 + 36000.0 - slack, 172800.0 + 46800.0 + slack], abs=1e-3)
    if lat == 52.0:  # the fifteenth of fifteen days: the hour angle has turned 14 times since the start
        sp15 = exact.SunSpline(path, 0.0, 15 * 86400.0, north)
        d14 = 14 * 86400.0
        assert _flat_pairs(windows(d14, d14 + 86400.0, sp15)) == pytest.approx(
            [d14 + 36000.0 - slack, d14 + 46800.0 + slack], abs=1e-3)


def _flat_pairs(pairs):
    return [x for pair in pairs for x in pair]


# --- an edge whose band of declinations only just reaches the sun's ----------------------------------


def _post_behind_the_sun(date, azimuth_deg, distance_m, above_deg, half, below_deg=None):
    """A square post (half-width ``half`` [m]) ``distance_m`` from P (tests/test_sunlight_exact.P) at
    ``azimuth_deg``, its top ``above_deg`` above the sun's elevation when the sun is at that azimuth
    (pvlib's sun, tests/oracles.py, bisected to 1e-6 s), its foot on the ground or, with ``below_deg``,
    that far below the sun (a hanging box): its faces and the closed-form ray test."""
    from oracles import local_midnight, sun_position
    from test_sunlight_exact import LAT, LON, P

    lo, hi = local_midnight(date) + 6 * 3600.0, local_midnight(date) + 12 * 3600.0  # the morning: azimuth rising
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sun_position(np.array([mid]), LAT, LON, refraction=True)[1][0] < azimuth_deg else (lo, mid)
    elev = sun_position(np.array([lo]), LAT, LON, refraction=True)[0][0]
    a = np.radians(azimuth_deg)
    cx, cy = P[0] + distance_m * np.sin(a), P[1] + distance_m * np.cos(a)
    top = P[2] + distance_m * np.tan(np.radians(elev + above_deg))
    foot = 0.0 if below_deg is None else P[2] + distance_m * np.tan(np.radians(elev - below_deg))
    x0, x1, y0, y1, z0 = cx - half, cx + half, cy - half, cy + half, foot
    faces = [[(x0, y0, z0), (x1, y0, z0), (x1, y0, top), (x0, y0, top)], [(x1, y0, z0), (x1, y1, z0), (x1, y1, top), (x1, y0, top)],
             [(x1, y1, z0), (x0, y1, z0), (x0, y1, top), (x1, y1, top)], [(x0, y1, z0), (x0, y0, z0), (x0, y0, top), (x0, y1, top)],
             [(x0, y0, top), (x1, y0, top), (x1, y1, top), (x0, y1, top)], [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)]]
    lo3, hi3 = np.array([x0, y0, z0]), np.array([x1, y1, top])

    def clear(v):  # slab test of the ray from P against the post's box
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (lo3 - P) / v, (hi3 - P) / v
        tmin = np.nanmax(np.minimum(t1, t2), axis=1)
        tmax = np.nanmin(np.maximum(t1, t2), axis=1)
        return ~(tmax >= np.maximum(tmin, 0.0))

    return faces, clear


@pytest.mark.parametrize("above, below", [(1.5, None), (20.0, 1.5)])
def test_a_post_whose_end_just_clears_the_sun_is_searched(tmp_path, above, below):
    """A post 10 m south-south-east of P (azimuth 150 deg), its top 1.5 deg above the sun's path there (or
    a box hanging from 20 deg above it to 1.5 deg below), on 21 March at 52 N: the sun passes behind it
    for a few minutes. The edges' declinations reach past the sun's by about 1 deg only, under the band's
    slack (3.8 deg, OMEGA_BOUND x KNOT_S): still searched. Hours and the gap against the brute force of
    tests/test_sunlight_exact.py (pvlib's sun every second)."""
    import test_sunlight_exact as tse

    faces, clear = _post_behind_the_sun("03-21", 150.0, 10.0, above, 0.15, below)
    truth = tse.brute_force_hours("03-21", clear)
    open_ = tse.brute_force_hours("03-21", lambda v: np.ones(len(v), bool))
    assert 60.0 < (open_ - truth) * 3600 < 1800.0  # the post hides the sun for minutes
    _, r = tse.built_with(tmp_path, faces, "post", "03-21")
    assert abs(r.hours[0] - truth) * 3600 <= tse.DAY_S
    assert len(r.intervals[0]) == 2  # the gap behind the post


def test_merge_runs_of_three_and_runs_on_a_later_day():
    # day 0: [0, 1], [1, 2], [2, 3] seen: one run [0, 3]; day 1: [10, 11], [11, 12] seen: one run [10, 12]
    t_c = np.array([0.0, 1.0, 2.0, 3.0, 10.0, 11.0, 12.0])
    d_c = np.array([0, 0, 0, 0, 1, 1, 1])
    err = np.array([0.5, 0.0, 0.0, 0.25, 0.125, 0.0, 2.0])
    iv, e = exact._merge(t_c, err, d_c, np.array([0, 1, 2, 4, 5]), np.ones(5, bool), 2)
    assert iv[0].tolist() == [[0.0, 3.0]] and iv[1].tolist() == [[10.0, 12.0]]
    assert e.tolist() == [0.75, 2.125]


def test_min_altitude_glimpse_inside_one_knot_piece():
    """A stand-in sun peaking at 30 deg at 21900 s, mid-way between knots (21600 and 22200 s), and a minimum
    altitude of 29.999 deg: above it for 2 acos(29.999 / 30) / W = 225 s, both ends of the knot piece below.
    The bound on |f''| (OMEGA_BOUND^2 on the sine of the elevation) makes the piece undecided until split:
    both crossings are found, each within the tolerance."""
    def path(t):
        t = np.asarray(t, float)
        return 30.0 * np.sin(W * (t - 300.0)), np.degrees(W * t) % 360.0

    sp = exact.SunSpline(path, 0.0, 86400.0, 0.0)
    assert 21600.0 in sp.t0 + sp.h * np.arange(len(sp.s)) and 22200.0 in sp.t0 + sp.h * np.arange(len(sp.s))
    k, lo, hi, simple = exact._min_altitude_roots(sp, path, np.array([0.0]), np.array([86400.0]), 29.999, 1e-3)
    d = np.arccos(29.999 / 30.0) / W
    want = [21900.0 - d, 21900.0 + d]
    order = np.argsort(lo)
    assert len(lo) == 2 and simple.all()
    assert np.all(lo[order] <= np.array(want) + 1e-9) and np.all(hi[order] >= np.array(want) - 1e-9)
    assert np.all(hi - lo <= 1e-3)


def test_seen_takes_the_spas_elevation_near_the_minimum_altitude_low_down():
    """_seen decides 'up' from the spline's elevation, except where that is under SPLINE_MIN_ELEVATION_DEG
    (10) and within 1 deg of the minimum altitude: there from the SPA itself. A stand-in spline at a constant
    elevation and a stand-in SPA that says otherwise (elevation 10.5, azimuth 5 deg) show which is used."""
    from types import SimpleNamespace

    one = SimpleNamespace(seen_along=lambda d, up: up.copy())  # seen wherever up

    def spa(t):
        return np.full(len(t), 10.5), np.full(len(t), 5.0)

    tm = np.array([3600.0, 7200.0])
    for elev, min_alt, want in ((9.5, 10.0, True),    # near: the SPA's 10.5 >= 10
                                (8.5, 10.0, False),   # 1.5 deg under: the spline's 8.5
                                (9.5, 9.0, True),     # the spline's 9.5 >= 9, the SPA's too
                                (10.5, 10.4, True),   # at or over 10 deg: the spline's own
                                (10.2, 10.6, False)):
        def path(t, e=elev):
            t = np.asarray(t, float)
            return np.full(len(t), e), np.degrees(W * t) % 360.0

        sp = exact.SunSpline(path, 0.0, 86400.0, 0.0)
        assert exact._seen(one, sp, spa, tm, min_alt).tolist() == [want, want], (elev, min_alt)


def test_root_brackets_keep_a_piece_whose_dip_the_curvature_bound_allows():
    """f = K/2 (t - 5)^2 - (K w^2 / 8 - m) on one piece [0, 10] (w = 10), |f''| = K: f(0) = f(w) = m > 0
    with m = K w^2 / 8.5, under the bound's K w^2 / 8, so the piece may hold roots and is split; it does,
    at 5 +- sqrt(2 (K w^2 / 8 - m) / K)."""
    k_, w = 0.02, 10.0
    m = k_ * w * w / 8.5
    dip = k_ * w * w / 8 - m

    def values(key, t, pc):
        return 0.5 * k_ * (t - 5.0) ** 2 - dip

    key, lo, hi, simple = exact.root_brackets(values, lambda kk, pc: np.full(len(kk), k_), np.array([0]), np.array([0.0]),
                                              np.array([w]), 1e-6, w)
    r = np.sqrt(2 * dip / k_)
    assert len(lo) == 2 and simple.all()
    assert np.sort(0.5 * (lo + hi)) == pytest.approx([5.0 - r, 5.0 + r], abs=1e-6)


def test_union_of_no_points():
    iv, err = exact.union_intervals([], [], 3)
    assert [x.shape for x in iv] == [(0, 2)] * 3 and err.tolist() == [0.0, 0.0, 0.0]
