"""Mutation tests (issue 39): the glare criterion's numeric core (``criteria/glare/``: dgp, usage,
positions, annual, assess) against hand values, closed forms and brute force.

Tolerances: 1e-12 on sums of a few terms (round-off); 1e-9 where an arccos or a log is taken of a
worked value; the brute forces of the annual method repeat its sums in another order (1e-9 relative).
"""
from __future__ import annotations

import datetime as dt
import math
from types import SimpleNamespace

import numpy as np
import pytest
import shapely

from en17037cli.criteria.glare import annual, assess, dgp, positions, usage
from en17037cli.errors import InputError, NotAssessable

# --- dgp.py ---------------------------------------------------------------------------------------


def test_dgp_terms_by_hand():
    # c1 E_v + c2 log10(1 + S / E_v^1.87) + c3, with c1 5.87e-5, c2 0.092, c3 0.159
    s = 2.0e7
    want = 5.87e-5 * 1000.0 + 0.092 * math.log10(1.0 + s / 1000.0 ** 1.87) + 0.159
    assert float(dgp.dgp(1000.0, s)) == pytest.approx(want, abs=1e-12)
    # the low-light factor applies below 1000 lx only (not at it); at 500 lx it is e^8 / (1 + e^8)
    assert float(dgp.dgp(1000.0, s, low_light_correction=True)) == pytest.approx(want, abs=1e-12)
    raw = 5.87e-5 * 500.0 + 0.092 * math.log10(1.0 + s / 500.0 ** 1.87) + 0.159
    assert float(dgp.dgp(500.0, s, low_light_correction=True)) == pytest.approx(raw * math.exp(8.0) / (1 + math.exp(8.0)), abs=1e-12)
    # vectorised: 0 where E_v is 0 whatever the sources, the values clipped to [0, 1]
    got = dgp.dgp(np.array([0.0, 1000.0, 2.0e4]), np.array([1e9, s, 0.0]))
    assert got.tolist() == pytest.approx([0.0, want, 1.0], abs=1e-12)
    # far in the dark the correction takes the DGP to 0 (the exponent's floor), never below
    assert float(dgp.dgp(1.0, 0.0, low_light_correction=True)) == pytest.approx(
        (5.87e-5 + 0.159) * math.exp(0.024 - 4.0) / (1 + math.exp(0.024 - 4.0)), abs=1e-12)


def test_view_frame_by_hand():
    f, r, u = dgp.view_frame([0.0, 2.0, 0.0])
    assert f.tolist() == [0.0, 1.0, 0.0] and r.tolist() == [1.0, 0.0, 0.0] and u.tolist() == [0.0, 0.0, 1.0]
    f, r, u = dgp.view_frame([3.0, 0.0, 4.0])  # right = f x z, up = r x f
    assert np.allclose(f, [0.6, 0.0, 0.8]) and np.allclose(r, [0.0, -1.0, 0.0]) and np.allclose(u, [-0.8, 0.0, 0.6])
    f, r, u = dgp.view_frame([0.0, 0.0, 2.0])  # straight up: right from +y instead, f x y = -x
    assert np.allclose(r, [-1.0, 0.0, 0.0]) and np.allclose(u, [0.0, 1.0, 0.0])


def _guth(sigma, tau):
    return math.exp((35.2 - 0.31889 * tau - 1.22 * math.exp(-2 * tau / 9)) * sigma / 1000
                    + (21 + 0.26667 * tau - 0.002963 * tau * tau) * sigma * sigma / 1e5)


def test_position_index_off_the_vertical_and_below_by_hand():
    f = [0.0, 1.0, 0.0]  # right +x, up +z
    s = math.radians(40.0)
    # to the side in the horizontal plane: tau = 90 deg
    assert dgp.position_index([[math.sin(s), math.cos(s), 0.0]], f)[0] == pytest.approx(_guth(40.0, 90.0), rel=1e-9)
    # up and to the left at 45 deg from the vertical: tau = 45 deg
    d = np.array([-math.sin(s) * math.sqrt(0.5), math.cos(s), math.sin(s) * math.sqrt(0.5)])
    assert dgp.position_index([d], f)[0] == pytest.approx(_guth(40.0, 45.0), rel=1e-9)
    # the line of sight itself: 1
    assert dgp.position_index([[0.0, 1.0, 0.0]], f)[0] == pytest.approx(1.0, abs=1e-12)
    # Guth far up (sigma 80, tau 0) is 58: capped at 16
    up = math.radians(80.0)
    assert dgp.position_index([[0.0, math.cos(up), math.sin(up)]], f)[0] == 16.0
    # below by 40 deg: Iwata, R = tan 40 deg = 0.84 > 0.6, factor 1.2
    b = math.radians(40.0)
    assert dgp.position_index([[0.0, math.cos(b), -math.sin(b)]], f)[0] == pytest.approx(1 + 1.2 * math.tan(b), rel=1e-6)
    # below and to the side: R = sqrt(tan^2 phi + tan^2 theta), phi, theta the angles of y and x
    x, y = -0.3, -0.2
    d = [x, math.sqrt(1 - x * x - y * y), y]
    r_ = math.hypot(math.tan(math.asin(y)), math.tan(math.asin(x)))
    assert dgp.position_index([d], f)[0] == pytest.approx(1 + 0.8 * r_, rel=1e-12)
    # below by 80 deg: R = 5.7, capped at 3
    b = math.radians(80.0)
    assert dgp.position_index([[0.0, math.cos(b), -math.sin(b)]], f)[0] == pytest.approx(1 + 1.2 * 3.0, rel=1e-12)
    # at 90 deg and behind: NaN
    assert np.isnan(dgp.position_index([[1.0, 0.0, 0.0], [0.0, -0.6, -0.8]], f)).all()


def _glass(tn, cos_i):
    """Radiance's glass by Snell's and Fresnel's laws written out: sin t = sin i / 1.52."""
    n = 1.52
    ci = abs(cos_i)
    ct = math.sqrt(1 - (1 - ci * ci) / (n * n))
    d = tn ** (1 / ct)
    out = 0.0
    for r in (((ci - n * ct) / (ci + n * ct)) ** 2, ((ct - n * ci) / (ct + n * ci)) ** 2):
        out += 0.5 * (1 - r) ** 2 * d / (1 - r * r * d * d)
    return out


@pytest.mark.parametrize("tn, c", [(0.9, 1.0), (0.9, 0.5), (0.6, -0.3), (0.95, 0.05)])
def test_glass_transmission_by_snell_and_fresnel(tn, c):
    assert float(dgp.glass_transmission(tn, c)) == pytest.approx(_glass(tn, c), rel=1e-12)


def test_glass_transmission_at_grazing_incidence_is_clipped():
    assert float(dgp.glass_transmission(0.9, 0.0)) == pytest.approx(_glass(0.9, 1e-9), abs=1e-12)
    assert float(dgp.glass_transmission(0.9, 0.0)) < 1e-8


def test_sphere_directions_fibonacci_by_hand():
    d = dgp.sphere_directions(4)
    golden = math.pi * (1 + math.sqrt(5))
    for k in range(4):
        i = k + 0.5
        z = 1 - 2 * i / 4
        r = math.sqrt(1 - z * z)
        assert d[k].tolist() == pytest.approx([r * math.cos(golden * i), r * math.sin(golden * i), z], abs=1e-12)


def _dir(alt, az):
    a, z = math.radians(alt), math.radians(az)
    return [math.sin(z) * math.cos(a), math.cos(z) * math.cos(a), math.sin(a)]


@pytest.mark.parametrize("alt, az, mf, row", [
    (6.0, 0.0, 1, 1), (6.0, 5.9, 1, 1), (6.0, 6.1, 1, 2), (6.0, 353.9, 1, 30), (6.0, 354.1, 1, 1), (18.0, 0.0, 1, 31),
    (78.0, 60.0, 1, 139 + 1), (78.0, 29.0, 1, 139), (85.0, 200.0, 1, 145), (90.0, 0.0, 1, 145), (-5.0, 10.0, 1, 0),
    (0.0, 0.0, 1, 1), (3.0, 3.1, 2, 2), (3.0, 0.0, 2, 1), (7.0, 0.0, 2, 61), (87.0, 100.0, 2, 577)])
def test_reinhart_bin_by_hand(alt, az, mf, row):
    # rows of 12 deg (MF 1: 30, 30, 24, 24, 18, 12, 6 patches and the cap) or 90 / 14.5 deg (MF 2), each
    # patch centred on a multiple of 360 / n from north clockwise; gendaymtx's rows: 0 the ground
    assert int(dgp.reinhart_bin([_dir(alt, az)], mf)[0]) == row
    assert dgp.reinhart_bins(mf) == 144 * mf * mf + 2


# --- usage.py -------------------------------------------------------------------------------------


def _unix(y, m, d, h=0):
    return dt.datetime(y, m, d, h, tzinfo=dt.UTC).timestamp()


def test_row_starts_by_calendar():
    rows, t = usage.row_starts([1, 2, 2, 3, 2, 12, 1], [1, 28, 29, 1, 30, 31, 0], 2026)
    # 29 February does not exist in 2026, nor 30 February, nor a day 0
    assert rows.tolist() == [0, 1, 3, 5]
    assert t.tolist() == [_unix(2026, 1, 1), _unix(2026, 2, 28), _unix(2026, 3, 1), _unix(2026, 12, 31)]
    rows, t = usage.row_starts([2], [29], 2024)
    assert rows.tolist() == [0] and t.tolist() == [_unix(2024, 2, 29)]


def _day(month, day):
    return np.full(24, month), np.full(24, day), np.arange(1, 25)


def test_usage_hours_of_one_winter_and_one_summer_day_by_hand():
    # Monday 5 January and Monday 6 July 2026, Amsterdam (standard time UTC+1, summer time UTC+2)
    m = np.concatenate([_day(1, 5)[0], _day(7, 6)[0], _day(1, 10)[0]])  # and Saturday 10 January
    d = np.concatenate([_day(1, 5)[1], _day(7, 6)[1], _day(1, 10)[1]])
    h = np.concatenate([_day(1, 5)[2], _day(7, 6)[2], _day(1, 10)[2]])
    u = usage.usage_hours(m, d, h, 1.0, "Europe/Amsterdam", 2026, 8.0, 18.0, (0, 1, 2, 3, 4))
    # winter: clock = standard time, rows of hours 9..18 (08:00-09:00 ... 17:00-18:00); July: hours 8..17
    assert u.rows.tolist() == list(range(8, 18)) + list(range(24 + 7, 24 + 17))
    assert len(u) == 20
    # the middle of the first: 08:30 clock = 07:30 UTC in January, 06:30 UTC in July
    assert u.unix_mid[0] == _unix(2026, 1, 5, 7) + 1800 and u.unix_mid[10] == _unix(2026, 7, 6, 6) + 1800
    assert str(u.local_start[0]) == "2026-01-05T08:00" and str(u.local_start[19]) == "2026-07-06T17:00"
    # from 08:30 and on Saturdays only: the rows starting 09:00 .. 17:00 of the Saturday
    u = usage.usage_hours(m, d, h, 1.0, "Europe/Amsterdam", 2026, 8.5, 18.0, (5,))
    assert u.rows.tolist() == list(range(48 + 9, 48 + 18))


def test_usage_hours_west_of_greenwich():
    # New York, 5 January 2026 (Monday): standard time UTC-5; row hour 9 starts 08:00 local = 13:00 UTC
    m, d, h = _day(1, 5)
    u = usage.usage_hours(m, d, h, -5.0, "America/New_York", 2026, 8.0, 9.0, (0,))
    assert u.rows.tolist() == [8] and u.unix_mid.tolist() == [_unix(2026, 1, 5, 13) + 1800]


def test_usage_hours_on_the_days_the_clocks_change():
    # Amsterdam 2026: summer time from Sunday 29 March 02:00 to Sunday 25 October 03:00; a day's clock offset
    # is the one at its noon. Winter days: rows 9..18 (08:00-18:00 on the clock); summer days: rows 8..17.
    days = [(3, 27), (3, 28), (3, 29), (10, 24), (10, 25), (10, 26)]
    m = np.concatenate([_day(*x)[0] for x in days])
    d = np.concatenate([_day(*x)[1] for x in days])
    h = np.concatenate([_day(*x)[2] for x in days])
    u = usage.usage_hours(m, d, h, 1.0, "Europe/Amsterdam", 2026, 8.0, 18.0, tuple(range(7)))
    first = [int(h[r]) for r in u.rows[::10]]
    assert len(u) == 60 and first == [9, 9, 8, 8, 9, 9]
    # whole days: every row is a usage hour, early mornings included
    u = usage.usage_hours(m, d, h, 1.0, "Europe/Amsterdam", 2026, 0.0, 24.0, tuple(range(7)))
    assert len(u) == 6 * 24
    assert usage.count_usage_hours(2026, 0.0, 24.0, (0,)) == 52 * 24


def test_count_usage_hours_on_the_calendar():
    # 2026 starts on a Thursday: 52 weeks and a Thursday; 2024 (leap) on a Monday: 52 weeks, a Monday and a Tuesday
    assert usage.count_usage_hours(2026, 8.0, 18.0, (5, 6)) == 104 * 10
    assert usage.count_usage_hours(2026, 9.0, 12.0, (3,)) == 53 * 3
    assert usage.count_usage_hours(2024, 8.0, 18.0, (0,)) == 53 * 10
    assert usage.count_usage_hours(2024, 8.0, 18.0, (2,)) == 52 * 10


def test_moments_and_standard_time_by_hand():
    t, local = usage.parse_moment("2026-12-21T12:00", "Europe/Amsterdam")
    assert t == _unix(2026, 12, 21, 11) and local.hour == 12
    t, local = usage.parse_moment("2026-06-21T12:00", "Europe/Amsterdam")
    assert t == _unix(2026, 6, 21, 10)
    assert usage.standard_time(local) == (6, 21, 11.0)  # summer time taken off
    _, local = usage.parse_moment("2026-07-01T00:30:36", "Europe/Amsterdam")
    assert usage.standard_time(local) == (6, 30, 23 + 30 / 60 + 36 / 3600)
    _, local = usage.parse_moment("2026-01-10T14:45", "Europe/Amsterdam")
    assert usage.standard_time(local) == (1, 10, 14.75)
    assert usage.standard_offset_h("Europe/Amsterdam", 2026) == 1.0
    assert usage.standard_offset_h("America/New_York", 2026) == -5.0
    assert usage.standard_offset_h("Australia/Sydney", 2026) == 10.0  # summer time in January there
    assert usage.standard_offset_h("UTC", 2026) == 0.0


# --- positions.py ---------------------------------------------------------------------------------


def _window(name, centroid, normal):
    c = np.asarray(centroid, float)
    return SimpleNamespace(name=name, centroid=c, normal=np.asarray(normal, float))


def _room(windows, floor=((0, 0), (4, 0), (4, 5), (0, 5)), floor_z=0.0, ceiling_z=3.0, name="R", problem=None):
    return SimpleNamespace(name=name, windows=windows, floor=shapely.Polygon(floor), floor_z=floor_z, ceiling_z=ceiling_z,
                           problem=problem)


def test_auto_views_by_hand():
    scene = SimpleNamespace(true_north_deg=0.0)
    room = _room([_window("S", (2.0, 0.0, 1.5), (0.0, -1.0, 0.0)), _window("E", (4.0, 2.5, 1.5), (0.6, 0.0, 0.8))],
                 floor_z=0.5)
    v = positions.auto_views(scene, room, 1.2, 1.0, ("towards", "parallel"))
    assert [x.label for x in v] == ["window 'S', towards", "window 'S', parallel, left", "window 'S', parallel, right",
                                    "window 'E', towards", "window 'E', parallel, left", "window 'E', parallel, right"]
    assert np.allclose(v[0].eye, [2.0, 1.0, 1.7]) and v[0].position == 0 and v[3].position == 1
    assert np.allclose(v[0].direction, [0, -1, 0]) and v[0].bearing_deg == pytest.approx(180.0)
    assert np.allclose(v[1].direction, [1, 0, 0]) and np.allclose(v[2].direction, [-1, 0, 0])
    assert [x.bearing_deg for x in v[1:3]] == pytest.approx([90.0, 270.0])
    # the tilted window looks along its horizontal part, +x, from 1 m in
    assert np.allclose(v[3].eye, [3.0, 2.5, 1.7]) and np.allclose(v[3].direction, [1, 0, 0])
    v = positions.auto_views(SimpleNamespace(true_north_deg=30.0), room, 1.2, 1.0, ("parallel",))
    assert len(v) == 4 and v[0].bearing_deg == pytest.approx(60.0)


def test_auto_eye_the_floor_does_not_hold_moves_inside():
    scene = SimpleNamespace(true_north_deg=0.0)
    shallow = _room([_window("S", (2.0, 0.0, 1.5), (0.0, -1.0, 0.0))], floor=((0, 0), (4, 0), (4, 0.5), (0, 0.5)))
    v = positions.auto_views(scene, shallow, 1.2, 1.0, ("towards",))
    assert len(v) == 1 and np.allclose(v[0].eye, [2.0, 0.4, 1.2])  # 0.1 m inside the floor's far edge
    v = positions.auto_views(scene, shallow, 1.2, 0.05, ("towards",))
    assert np.allclose(v[0].eye, [2.0, 0.05, 1.2])  # inside the floor, if within 0.1 m of its edge: where it is
    roof = _room([_window("R", (2.0, 2.0, 3.0), (0.0, 0.0, 1.0))])  # a roof light looks along +y
    v = positions.auto_views(scene, roof, 1.2, 1.0, ("towards",))
    assert np.allclose(v[0].eye, [2.0, 1.0, 1.2]) and np.allclose(v[0].direction, [0, 1, 0])


def test_listed_views_by_room():
    r1 = _room([], name="A", floor_z=0.0, ceiling_z=3.0)
    r2 = _room([], name="B", floor=((5, 0), (9, 0), (9, 5), (5, 5)), floor_z=0.0, ceiling_z=float("inf"))
    bad = _room([], name="C", floor=((0, 0), (9, 0), (9, 5), (0, 5)), problem="no floor")
    scene = SimpleNamespace(rooms=[bad, r1, r2], true_north_deg=10.0, to_local=lambda p: np.asarray(p, float) - [0.0, 0.0, 0.0])
    out = positions.listed_views(scene, np.array([[1.0, 1.0, 0.0, 370.0], [6.0, 1.0, 9.9, 90.0], [2.0, 2.0, 3.0, 0.0]]))
    assert sorted(out) == ["A", "B"]
    a, b = out["A"], out["B"]
    assert [v.position for v in a] == [0, 1] and [v.label for v in a] == ["listed position 1", "listed position 3"]
    assert a[0].bearing_deg == 10.0 and np.allclose(a[0].direction, [math.sin(math.radians(20)), math.cos(math.radians(20)), 0])
    assert a[0].eye.tolist() == [1.0, 1.0, 0.0] and a[1].eye.tolist() == [2.0, 2.0, 3.0] and b[0].eye.tolist() == [6.0, 1.0, 9.9]
    assert b[0].label == "listed position 2" and b[0].bearing_deg == 90.0
    for p in ([1.5, 2.5, -0.01], [1.5, 2.5, 3.01], [6.0, 1.0, 10.01], [20.0, 1.0, 1.0], [4.5, 1.0, 1.0]):
        with pytest.raises(InputError) as e:
            positions.listed_views(scene, np.array([[1.0, 1.0, 1.0, 0.0], p + [0.0]]))
        assert str(e.value) == (f"glare.positions[1]: ({p[0]:g}, {p[1]:g}, {p[2]:g}) stands over no room's floor between floor "
                                "and ceiling; give a point inside a room (model frame, metres)")


def test_room_views_listed_auto_and_none():
    room = _room([_window("S", (2.0, 0.0, 1.5), (0.0, -1.0, 0.0))])
    scene = SimpleNamespace(rooms=[room], true_north_deg=0.0, to_local=lambda p: np.asarray(p, float))
    auto = SimpleNamespace(positions=None, eye_height_m=1.0, facade_distance_m=0.5, directions=("towards",))
    v = positions.room_views(scene, room, auto, {})
    assert len(v) == 1 and np.allclose(v[0].eye, [2.0, 0.5, 1.0])
    with pytest.raises(NotAssessable, match="^the room has no window$"):
        positions.room_views(scene, _room([]), auto, {})
    listed = SimpleNamespace(positions=np.array([[1.0, 1.0, 1.2, 0.0]]))
    cache: dict = {}
    assert positions.room_views(scene, room, listed, cache)[0].label == "listed position 1" and "glare_listed" in cache
    with pytest.raises(NotAssessable, match=r"^no listed glare position stands in the room \(glare.positions\)$"):
        positions.room_views(scene, _room([], name="other"), listed, cache)
    # the listed views are worked out once per run: what the cache holds is used
    assert positions.room_views(scene, room, listed, {"glare_listed": {"R": ["mine"]}}) == ["mine"]


# --- assess.py ------------------------------------------------------------------------------------


def test_mean_and_error_by_hand():
    assert assess.mean_and_error(np.array([1.0, 2.0, 3.0])) == pytest.approx((2.0, 4.303 / math.sqrt(3)), rel=1e-12)
    v = np.arange(12.0)  # 11 degrees of freedom: beyond the table, t = 2.0
    assert assess.mean_and_error(v) == pytest.approx((5.5, 2.0 * np.std(v, ddof=1) / math.sqrt(12)), rel=1e-12)
    assert assess.deployed(np.array([0.3, 0.45, 0.5]), 0.45, "glare").tolist() == [False, False, True]
    assert assess.deployed(np.array([0.3, 0.45]), 0.45, "always").tolist() == [True, True]
    assert assess.deployed(np.array([0.3, 0.45]), 0.45, "always").dtype == bool  # hours down: a mask


class _Model:
    """A stand-in view: DGP base + sun part per hour; a device passing t of the light and s of the sun."""

    def __init__(self, base, sun):
        self.base, self.sun = np.asarray(base, float), np.asarray(sun, float)

    def dgp(self, hours=None, scale=1.0, sun_scale=None):
        h = np.arange(len(self.base)) if hours is None else hours
        s = scale if sun_scale is None else sun_scale
        return (self.base[h] * scale + self.sun[h] * s)[None, :]


def test_series_deploys_the_device_where_the_unshaded_dgp_exceeds_the_limit():
    m = _Model([0.2, 0.3, 0.5], [0.0, 0.2, 0.2])
    out, raw, down = assess.series(m, None, 0.45)
    assert out.tolist() == raw.tolist() == [[0.2, 0.5, 0.7]] and down.tolist() == [False, False, False] and down.dtype == bool
    out, raw, down = assess.series(m, SimpleNamespace(control="glare", transmittance=0.5, sun_transmittance=0.1), 0.45)
    assert down.tolist() == [False, True, True] and raw.tolist() == [[0.2, 0.5, 0.7]]
    assert out[0].tolist() == pytest.approx([0.2, 0.15 + 0.02, 0.25 + 0.02], abs=1e-12)
    out, _, down = assess.series(m, SimpleNamespace(control="always", transmittance=0.5, sun_transmittance=0.5), 0.45)
    assert down.all() and out[0].tolist() == pytest.approx([0.1, 0.25, 0.35], abs=1e-12)
    out, _, down = assess.series(_Model([0.1], [0.0]), SimpleNamespace(control="glare", transmittance=0.5,
                                                                        sun_transmittance=0.1), 0.45)
    assert not down.any() and out.tolist() == [[0.1]]


def test_needed_transmittance_by_hand():
    # 100 hours, 10 of them at DGP 0.5 + 0.4 (sky, sun): 5 % may exceed, so those 10 must come to the limit 0.45
    base, sun = np.full(100, 0.3), np.zeros(100)
    base[:10], sun[:10] = 0.5, 0.4
    m = _Model(base, sun)
    assert assess.needed_transmittance([m], 0.45) == 0.5  # 0.9 t <= 0.45
    assert assess.needed_transmittance([m], 0.45, sun_hidden=True) == 0.7  # 0.5 t <= 0.45
    assert assess.needed_transmittance([m, _Model(base * 1.5, sun)], 0.45, sun_hidden=True) == 0.5  # 0.75 t <= 0.45
    assert assess.needed_transmittance([_Model(base * 1.5, sun), m], 0.45, sun_hidden=True) == 0.5
    assert assess.needed_transmittance([m], 0.3) == 0.25  # 0.9 t <= 0.3; the other hours at 0.3 are within
    assert assess.needed_transmittance([m], 0.004) is None  # 0.9 x 0.005 > 0.004
    # at most 5 hours over the limit: no device needed beyond the first step
    few = _Model(np.r_[np.full(5, 0.9), np.full(95, 0.1)], np.zeros(100))
    assert assess.needed_transmittance([few], 0.45) == 0.7


# --- annual.py ------------------------------------------------------------------------------------

K = 179.0
F = np.array([0.0, 1.0, 0.0])  # the view: right +x, up +z


def _rays(window):
    d = np.array([[0.0, 1.0, 0.0], [0.2, 0.9, 0.1], [-0.3, 0.8, 0.4], [0.1, 0.7, -0.6], [0.5, 0.5, 0.5],
                  [0.0, -1.0, 0.1], [0.7, 0.1, 0.6], [-0.6, 0.6, 0.2], [0.3, 0.9, -0.1], [0.0, 0.3, 0.9]])
    d /= np.linalg.norm(d, axis=1)[:, None]
    t = np.array([0.8, 0.6, 0.7, 0.5, 0.9, 0.8, 0.4, 0.75, 0.65, 0.55])
    b = np.array([1, 1, 2, 0, 2, 1, 3, 2, 1, 3])
    w = np.array([0, 0, 1, 0, 1, 0, 1, 1, 0, 1]) if window else None
    return annual.EyeRays(d, t, b, 4 * np.pi / 1000, w)


def _climate():
    sky = np.array([[5.0, 0.0, 30.0], [20.0, 8.0, 0.0], [15.0, 30.0, 2.0], [40.0, 1.0, 25.0]])  # W/(sr m2): bins x hours
    sun = np.array([[0.0, 0.0, 0.0], [0.0, 3.0, 0.0], [4.0, 0.0, 0.0], [0.0, 0.0, 6.0]])
    s = np.array([[0.3, 0.9, 0.3], [0.2, -0.9, 0.4], [-0.1, 0.8, 0.2]])
    s /= np.linalg.norm(s, axis=1)[:, None]
    return annual.Climate(None, sky, sun, np.array([80000.0, 60000.0, 50000.0]), s, np.array([True, True, True]))


def _brute_glare_sum(rays, clim, h, threshold, scale, sun_scale, share):
    """Per opening, the rays brighter than the threshold as one source (evalglare's merge), by loops."""
    cos = rays.dirs @ F
    groups = np.zeros(len(cos), int) if rays.window is None else rays.window
    total = 0.0
    for g in set(groups.tolist()):
        om = lom = a = c = 0.0
        for i in range(len(cos)):
            lum = K * scale * rays.t[i] * clim.sky[rays.bin[i], h]
            if groups[i] != g or cos[i] <= 1e-9 or lum <= threshold:
                continue
            th = math.acos(cos[i])
            k = th / math.sin(th) if th > 1e-9 else 1.0
            om += rays.omega
            lom += lum * rays.omega
            a += rays.dirs[i, 0] * k * rays.omega  # r = +x
            c += rays.dirs[i, 2] * k * rays.omega  # u = +z
        if om == 0:
            continue
        a, c = a / om, c / om
        rad = math.hypot(a, c)
        d = math.cos(rad) * F + (math.sin(rad) / rad if rad > 0 else 1.0) * np.array([a, 0.0, c])
        p = dgp.position_index([d], F)[0]
        total += lom * lom / om / (16.0 if np.isnan(p) else p) ** 2
    cs = float(clim.sun_dir[h] @ F)
    if share[h] > 0 and cs > 0:
        ls = clim.e_n[h] * share[h] / dgp.SUN_SOLID_ANGLE_SR * sun_scale
        if ls > threshold:
            total += ls * ls * dgp.SUN_SOLID_ANGLE_SR / dgp.position_index([clim.sun_dir[h]], F)[0] ** 2
    return total


@pytest.mark.parametrize("window", [False, True])
def test_view_model_against_a_brute_force(window):
    rays, clim = _rays(window), _climate()
    share = np.array([0.7, 0.6, 0.0])
    dc = np.array([[0.5, 1.0, 2.0, 1.5], [0.6, 0.9, 2.1, 1.4]])
    m = annual.ViewModel(rays, dc, F, clim, share, 2000.0, False)
    # E_v: DC (sky + sun) less the direct coefficients' share of the spread sun, plus the sun's disc
    cos = rays.dirs @ F
    dcd = np.zeros(4)
    for i in np.flatnonzero(cos > 1e-9):
        dcd[rays.bin[i]] += K * rays.t[i] * cos[i] * rays.omega
    e_sun = np.array([clim.e_n[h] * share[h] * max(clim.sun_dir[h] @ F, 0.0) for h in range(3)])
    e_sun[1] = 0.0  # the sun behind the eye is not in view
    ev = np.maximum(dc @ (clim.sky + clim.sun) - dcd @ clim.sun, 0.0) + e_sun
    assert np.allclose(m.ev, ev, rtol=1e-12) and np.allclose(m.e_sun, e_sun, rtol=1e-12)
    assert m.in_view.tolist() == [True, False, False]
    assert m.l_sun.tolist() == pytest.approx([80000 * 0.7 / dgp.SUN_SOLID_ANGLE_SR, 0.0, 0.0], rel=1e-12)
    assert m.p_sun[1:].tolist() == [1.0, 1.0] and m.p_sun[0] == pytest.approx(dgp.position_index([clim.sun_dir[0]], F)[0])
    for hours, scale, ss in ((np.arange(3), 1.0, None), (np.array([2, 0]), 0.5, 0.1), (np.array([1]), 0.3, None)):
        want = [_brute_glare_sum(rays, clim, h, 2000.0, scale, scale if ss is None else ss, share) for h in hours]
        assert m.glare_sum(hours, scale, ss) == pytest.approx(want, rel=1e-9)
        got = m.dgp(hours, scale, ss)
        sun_s = scale if ss is None else ss
        evs = (ev[:, hours] - e_sun[hours]) * scale + e_sun[hours] * sun_s
        assert got.shape == (2, len(hours))
        assert np.allclose(got, dgp.dgp(evs, np.array(want)[None, :]), rtol=1e-9, atol=1e-12)
    assert np.allclose(m.dgp(), m.dgp(np.arange(3)))


def test_view_model_low_light_and_no_sources():
    rays, clim = _rays(False), _climate()
    dc = np.array([[0.01, 0.01, 0.01, 0.01]])
    m = annual.ViewModel(rays, dc, F, clim, np.zeros(3), 1e12, True)  # nothing is a source, E_v well below 1000 lx
    assert m.glare_sum(np.arange(3)).tolist() == [0.0, 0.0, 0.0]
    assert np.allclose(m.dgp(), dgp.dgp(m.ev, np.zeros((1, 3)), True), rtol=1e-12)
    empty = annual.EyeRays(np.zeros((0, 3)), np.zeros(0), np.zeros(0, int), 0.01, None)
    m = annual.ViewModel(empty, dc, F, clim, np.zeros(3), 2000.0, False)
    assert m.glare_sum(np.arange(3)).tolist() == [0.0, 0.0, 0.0]


class _Engine:
    """Two windows of a room: 0 in the plane y = 0 (x in [-1, 1], z in [0.5, 2]), 1 in x = 2 (y in [0, 2],
    z in [0, 3]); rays with a west component below -0.5 are blocked outside."""

    def first_hit(self, group, o, d):
        face = np.full(len(d), -1)
        for k, (axis, val, lo, hi) in enumerate(((1, 0.0, (-1.0, 0.5), (1.0, 2.0)), (0, 2.0, (0.0, 0.0), (2.0, 3.0)))):
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (val - o[:, axis]) / d[:, axis]
                p = o + t[:, None] * d
            other = [i for i in range(3) if i != axis]
            inside = (t > 0) & np.all((p[:, other] >= lo) & (p[:, other] <= hi), axis=1)
            face = np.where((face < 0) & inside, k, face)
        return face, np.zeros(len(d))

    def occluded(self, group, o, d):
        assert group == "sun"
        return d[:, 0] < -0.5


def test_sun_through_glazing_takes_the_first_window_of_the_rooms_order():
    room = SimpleNamespace(index=0, windows=[SimpleNamespace(normal=np.array([0.0, -1.0, 0.0])),
                                             SimpleNamespace(normal=np.array([1.0, 0.0, 0.0]))])
    d = np.array([[0.0, -0.8, 0.6], [0.8, 0.0, 0.6], [-0.6, -0.6, 0.53], [0.0, -0.8, 0.6], [0.0, -0.6, -0.8],
                  [0.3, -0.5, 0.2], [0.0, 0.0, 1.0]])
    d /= np.linalg.norm(d, axis=1)[:, None]
    clim = SimpleNamespace(sun_dir=d, sun_up=np.array([True, True, True, False, True, True, True]))
    out = annual.sun_through_glazing(_Engine(), SimpleNamespace(true_north_deg=0.0), room, np.array([0.0, 1.0, 1.2]), clim,
                                     np.array([0.7, 0.9]))
    want = [float(dgp.glass_transmission(0.7, 0.8)), float(dgp.glass_transmission(0.9, 0.8)), 0.0, 0.0, 0.0,
            float(dgp.glass_transmission(0.7, d[5] @ [0, -1, 0])), 0.0]
    # 0: window 0; 1: window 1 (behind window 0's plane); 2: blocked; 3: sun down; 4: into the floor, below the
    # window; 5: crosses both planes, window 0 first; 6: straight up, through no window
    assert out.tolist() == pytest.approx(want, abs=1e-12)
    out = annual.sun_through_glazing(_Engine(), SimpleNamespace(true_north_deg=0.0), room, np.array([0.0, 1.0, 1.2]), clim,
                                     np.array([1.0, 0.9]))
    assert out[0] == 1.0 and out[5] == 1.0 and out[1] == pytest.approx(float(dgp.glass_transmission(0.9, 0.8)))


def test_eye_rays_keep_what_sees_the_sky_or_the_ground(monkeypatch):
    def transmission(octrees, octree, o, d):
        assert np.allclose(o[:4], [1.0, 2.0, 3.0]) and np.allclose(o[-1], [4.0, 5.0, 6.0])
        front = d[:, 1] < -0.3
        return np.where(front & (d[:, 2] > 0), 0.8, 0.0), np.where(front & (d[:, 2] <= 0), 0.6, 0.0)

    monkeypatch.setattr(annual.engine, "view_transmission", transmission)
    out = annual.eye_rays(None, "oct", [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]], 400, 1)
    d = dgp.sphere_directions(400)
    seen = d[:, 1] < -0.3
    assert len(out) == 2
    for r in out:
        assert np.array_equal(r.dirs, d[seen]) and r.omega == pytest.approx(4 * np.pi / 400)
        assert r.t.tolist() == np.where(d[seen][:, 2] > 0, 0.8, 0.6).tolist()
        assert r.bin.tolist() == np.where(d[seen][:, 2] > 0, dgp.reinhart_bin(d[seen], 1), 0).tolist()
        assert r.window.tolist() == [0] * int(seen.sum())

    class Eng:  # window A holds faces 3 and 4, window B face 7; rays with x > 0.2 leave through B, x < -0.2 none
        def first_hit(self, group, o, dd):
            assert group == "windows of room 5"
            return np.where(dd[:, 0] > 0.2, 7, np.where(dd[:, 0] < -0.2, -1, 4)), np.ones(len(dd))

    room = SimpleNamespace(index=5, windows=[SimpleNamespace(face_ids=np.array([3, 4])), SimpleNamespace(face_ids=np.array([7]))])
    out = annual.eye_rays(None, "oct", [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]], 400, 1, (Eng(), room))
    x = d[seen][:, 0]
    assert out[0].window.tolist() == np.where(x > 0.2, 1, np.where(x < -0.2, 2, 0)).tolist()
