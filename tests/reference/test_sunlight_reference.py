"""Sunlight engine against the hour-angle formula and independent brute-force computations."""
from __future__ import annotations

import datetime as dt

import numpy as np
import pytest

from en17037cli.criteria.sunlight import intervals as sun_intervals
from en17037cli.criteria.sunlight import solar_position as sp
from en17037cli.errors import NotAssessable
from en17037cli.samples import BoxRoom


def sun_cfg(date, **kw):
    cfg = {"date": date, "period": {"start": date, "end": date}, "refraction": False, "tolerance_s": 1}
    cfg.update(kw)
    return cfg


def assess(b):
    return b.sunlight()


def hour_angle_deg(lat, dec, gamma):
    """cos H = (sin gamma - sin phi sin delta) / (cos phi cos delta) [deg]."""
    phi, d, g = np.radians(lat), np.radians(dec), np.radians(gamma)
    return np.degrees(np.arccos((np.sin(g) - np.sin(phi) * np.sin(d)) / (np.cos(phi) * np.cos(d))))


@pytest.mark.parametrize("lat", [40.0, 52.0, 60.0])
@pytest.mark.parametrize("gamma", [0.0, 11.0])
@pytest.mark.parametrize("date", ["02-01", "03-01"])
def test_unobstructed_south_window_matches_hour_angle_formula(build, lat, gamma, date):
    b = build(BoxRoom(building_height=0), location={"latitude": lat, "longitude": 0.0, "timezone": "UTC"},
              sunlight=sun_cfg(date, min_altitude_deg=gamma), view=None)
    r = assess(b)
    hours = r.hours[0]
    noon = dt.datetime.fromisoformat(f"2026-{date}T12:00:00+00:00").timestamp()
    dec = sp.declination([noon - 6 * 3600, noon, noon + 6 * 3600])
    H = hour_angle_deg(lat, dec[1], gamma)
    expected = 2 * H / 15
    # Tolerance: the formula holds the declination fixed, while it drifts by |d delta| over the
    # ~6 h from noon to sunrise or sunset (about 0.1 deg in February and March); each end of the
    # day moves by dH/d delta * |d delta| / 15 h. Add 40 s for the drift of the equation of time
    # over half a day and the engine's own bisection error.
    d_dec = np.max(np.abs(dec[[0, 2]] - dec[1]))
    dH = abs(hour_angle_deg(lat, dec[1] + d_dec, gamma) - H)
    tol = 2 * dH / 15 + 40 / 3600 + r.error_h[0]
    assert abs(hours - expected) <= tol, (hours, expected, tol)
    # the check stays tight: under 6 minutes even at 60 N with gamma = 11 deg on 1 February, where
    # the sun barely clears 11 deg (noon altitude about 13 deg) and dH/d delta is large
    assert tol < 0.1


def brute_force_hours(date, lat, lon, p, box: BoxRoom, min_alt, tz_offset_h=0.0):
    """Hours of sun at 1 s steps with the visibility worked out analytically (no ray tracing):
    the ray from P must cross the glazing rectangle at y = 0 and pass above (or beside) the
    building face at y = -street."""
    t0 = dt.datetime.fromisoformat(f"2026-{date}T00:00:00+00:00").timestamp() - tz_offset_h * 3600
    t = t0 + np.arange(86400) + 0.5
    e, a = sp.solar_position(t, lat, lon, refraction=False)
    d = sp.direction_vectors(e, a)
    with np.errstate(divide="ignore", invalid="ignore"):
        s0 = (0 - p[1]) / d[:, 1]  # to the glazing plane
        x0, z0 = p[0] + s0 * d[:, 0], p[2] + s0 * d[:, 2]
        through = (d[:, 1] < 0) & (np.abs(x0) <= box.window_x[1]) & (z0 >= box.window_z[0]) & (z0 <= box.window_z[1])
        s1 = (-box.street - p[1]) / d[:, 1]
        x1, z1 = p[0] + s1 * d[:, 0], p[2] + s1 * d[:, 2]
        blocked = (box.building_height > 0) & (z1 <= box.building_height) & (np.abs(x1) <= box.building_length / 2)
    return np.count_nonzero((e >= min_alt) & through & ~blocked) / 3600.0


@pytest.mark.parametrize("reveal", [0.0, 0.5])
@pytest.mark.parametrize("date", ["02-01", "03-21"])
def test_window_behind_a_wall_matches_brute_force(build, reveal, date):
    box = BoxRoom(street=20.0, building_height=6.0, wall_thickness=reveal)  # blocks the sun below ~13.5 deg
    b = build(box, location={"latitude": 52.0, "longitude": 0.0, "timezone": "UTC"},
              sunlight=sun_cfg(date, min_altitude_deg=5.0), view=None)
    r = assess(b)
    p = b.scene.to_world(r.points_local[0])
    # P: horizontal centre, max(floor + 1.2, sill + 0.3) = 1.2 m, on the room-side plane of the opening
    expected_y = reveal if reveal > 0 else 1e-3
    assert np.allclose(p, [0.0, expected_y, 1.2], atol=1e-4), p
    assert abs(r.reveal_depths_m[0] - reveal) < 1e-4
    expected = brute_force_hours(date, 52.0, 0.0, p, box, 5.0)
    # brute force counts 1 s samples: at most 1 s per visibility change (4 per day here);
    # the engine is exact to its bisection error
    assert abs(r.hours[0] - expected) <= (4.0 + 1.0) / 3600 + r.error_h[0], (r.hours[0], expected)
    assert r.hours[0] > 0.5  # the wall does not hide the whole day


def test_polar_night_gives_zero_hours_and_level_none(build, recwarn):
    b = build(BoxRoom(), location={"latitude": 78.0, "longitude": 15.0, "timezone": "Arctic/Longyearbyen"},
              sunlight=sun_cfg("02-01", refraction=True, min_altitude_deg=11.0), view=None)
    r = assess(b)
    assert r.hours.tolist() == [0.0]
    assert r.level == 0
    assert np.all(np.isfinite(r.error_h))
    assert len(recwarn) == 0


def test_results_do_not_depend_on_the_timestep(build):
    results = []
    for step in (1, 5, 15, 60):
        b = build(BoxRoom(), sub=f"s{step}", location={"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
                  sunlight={"date": "worst", "period": {"start": "02-01", "end": "02-07"}, "timestep_min": step}, view=None)
        r = assess(b)
        results.append((r.hours, r.error_h))
    base_h, base_e = results[0]
    for h, e in results[1:]:
        assert np.all(np.abs(h - base_h) <= base_e + e + 1e-9), (h, base_h)
    assert np.all(base_e <= 4 * 1.0 / 3600)  # at most four changes a day, each to 1 s


def test_point_p_above_the_window_head_makes_the_window_not_assessable(build):
    b = build(BoxRoom(window_z=(0.2, 1.0)), sunlight=sun_cfg("02-01"), view=None)
    with pytest.raises(NotAssessable, match="window 'glazing'.*above the window head"):
        assess(b)


def test_explicit_sun_point_overrides_the_rule(build):
    b = build(BoxRoom(window_z=(0.2, 1.0)), sunlight=sun_cfg("02-01"), view=None)
    r = b.sunlight(sun_points=[[0.0, 0.001, 0.6]])
    assert np.allclose(b.scene.to_world(r.points_local[0]), [0.0, 0.001, 0.6])
    assert r.hours[0] > 0


def test_interval_union_and_bisection_on_a_known_function():
    # visible between 08:00:00.0 and 10:30:00.0 and between 10:45 and 16:00 (seconds after t0)
    def visible(t):
        s = np.asarray(t) % 86400
        return ((s >= 8 * 3600) & (s < 10.5 * 3600)) | ((s >= 10.75 * 3600) & (s < 16 * 3600))

    t0 = np.array([0.0, 86400.0])
    iv, err = sun_intervals.visible_intervals(visible, t0, t0 + 86400, 300.0, 0.5)
    for day in iv:
        hours = float(np.sum(day[:, 1] - day[:, 0])) / 3600
        assert abs(hours - (2.5 + 5.25)) <= 4 * 0.5 / 3600
        assert len(day) == 2
    assert np.all(err <= 4 * 0.5)
    # the documented limit: a 15 min gap between two hourly samples that both see the sun is missed
    iv, _ = sun_intervals.visible_intervals(visible, t0, t0 + 86400, 3600.0, 0.5)
    assert abs(float(np.sum(iv[0][:, 1] - iv[0][:, 0])) / 3600 - 8.0) <= 2 * 0.5 / 3600
