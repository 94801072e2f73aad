"""Sun position, sun intervals and bisection against independent answers (mutation testing, docs/mutation.md).

The sun against the published intermediate values of the SPA (Reda and Andreas 2004, Table A5.1);
intervals and bisection on predicates whose transitions are known exactly. The step-by-step
comparison with pvlib's SPA is in test_mutants_spa.py.
"""
from __future__ import annotations

import datetime as dt

import numpy as np
import pytest

from en17037cli.bisection import bisect_transitions
from en17037cli.criteria.sunlight import intervals as iv
from en17037cli.criteria.sunlight import solar_position as sp
from en17037cli.samples import BoxRoom


def test_spa_published_intermediate_values():
    """Reda and Andreas (2004), Table A5.1: 2003-10-17 19:30:30 UTC, 39.742476 N 105.1786 W,
    1830.14 m, 820 mbar, 11 degC, delta T 67 s. Each value to half a unit of its last published digit
    (JCE and JME to one unit: the table rounds them)."""
    t = np.array([dt.datetime(2003, 10, 17, 19, 30, 30, tzinfo=dt.UTC).timestamp()])
    lat, lon, elev = 39.742476, -105.1786, 1830.14
    jd = sp.julian_day(t)
    jc, jce = sp.julian_century(jd), sp.julian_ephemeris_century(sp.julian_ephemeris_day(jd, 67.0))
    jme = sp.julian_ephemeris_millennium(jce)
    assert abs(jc[0] - 0.03792779869) < 5e-12 and abs(jce[0] - 0.0379278200) < 1e-10 and abs(jme[0] - 0.0037927819) < 1e-10
    L, B, R = sp.heliocentric_longitude(jme), sp.heliocentric_latitude(jme), sp.heliocentric_radius_vector(jme)
    theta, beta = sp.geocentric_longitude(L), sp.geocentric_latitude(B)
    assert abs(theta[0] - 204.0182616917) < 5e-11 and abs(beta[0] - 0.0001011219) < 5e-11
    dpsi, deps = sp.nutation(jce)
    eps = sp.true_obliquity(jme, deps)
    lam = sp.apparent_sun_longitude(theta, dpsi, R)
    assert abs((lam - theta - dpsi)[0] - (-0.005711359)) < 5e-10  # the aberration correction delta tau
    assert abs(lam[0] - 204.0085519281) < 5e-11
    nu = sp.apparent_sidereal_time(jd, jc, dpsi, eps)
    assert abs(nu[0] - 318.5119) < 5e-5
    alpha, delta = sp.sun_right_ascension_declination(lam, eps, beta)
    assert abs(alpha[0] - 202.22741) < 5e-6 and abs(delta[0] - (-9.31434)) < 5e-6
    H_p, delta_p = sp.topocentric_position(nu, alpha, delta, R, lat, lon, elev)
    assert abs(delta_p[0] - (-9.316179)) < 5e-7
    e0 = sp.elevation_without_refraction(lat, H_p, delta_p)
    de = sp.refraction_correction(e0, 820.0, 11.0)
    assert abs(e0[0] - 39.872046) < 5e-7 and abs(de[0] - 0.016332) < 5e-7
    assert abs(sp.azimuth(lat, H_p, delta_p)[0] - 194.34024) < 5e-6
    # below -0.8333 deg (sunrise refraction plus the sun's radius) no refraction is added
    assert sp.refraction_correction(np.array([-0.8332, -0.8334]), 1010.0, 10.0)[1] == 0.0
    assert sp.refraction_correction(np.array([-0.8332, -0.8334]), 1010.0, 10.0)[0] > 0.0


def test_declination_is_the_geocentric_one_of_the_full_chain():
    t = np.array([dt.datetime(2003, 10, 17, 19, 30, 30, tzinfo=dt.UTC).timestamp()])
    assert abs(sp.declination(t, delta_t_s=67.0)[0] - (-9.31434)) < 5e-6  # Table A5.1
    # integer unix seconds are converted, not truncated
    assert sp.declination(np.array([1_700_000_000]))[0] == sp.declination(np.array([1_700_000_000.0]))[0]


def test_direction_vectors_by_hand():
    # elevation 30, azimuth 90 (east), north along +Y: (cos 30, 0, sin 30)
    d = sp.direction_vectors(np.array([30.0, 90.0, 0.0]), np.array([90.0, 0.0, 225.0]), 0.0)
    r = np.sqrt(0.5)
    assert np.allclose(d, [[np.sqrt(3) / 2, 0, 0.5], [0, 0, 1], [-r, -r, 0]], atol=1e-12)
    # true north 30 deg clockwise from +Y: a sun due north lies 30 deg clockwise from +Y
    d = sp.direction_vectors(np.array([60.0]), np.array([0.0]), 30.0)
    assert np.allclose(d, [[0.5 * 0.5, 0.5 * np.sqrt(3) / 2, np.sqrt(3) / 2]], atol=1e-12)


# --- intervals of a day -------------------------------------------------------------------------

DAY = 86400.0


def test_day_bounds_are_local_midnights_across_a_dst_change():
    dates, t0, t1 = iv.day_bounds(2026, "03-28", "03-30", "Europe/Amsterdam")
    assert dates == [dt.date(2026, 3, 28), dt.date(2026, 3, 29), dt.date(2026, 3, 30)]
    # CET (UTC+1) until 29 March 02:00, then CEST (UTC+2): the 29th has 23 hours
    expected0 = [dt.datetime(2026, 3, 27, 23, tzinfo=dt.UTC), dt.datetime(2026, 3, 28, 23, tzinfo=dt.UTC),
                 dt.datetime(2026, 3, 29, 22, tzinfo=dt.UTC)]
    assert t0.tolist() == [x.timestamp() for x in expected0]
    assert (t1 - t0).tolist() == [24 * 3600.0, 23 * 3600.0, 24 * 3600.0]
    dates, t0, t1 = iv.day_bounds(2026, "02-01", "02-01", "UTC")
    assert dates == [dt.date(2026, 2, 1)] and t0.tolist() == [dt.datetime(2026, 2, 1, tzinfo=dt.UTC).timestamp()]
    assert t1.tolist() == [t0[0] + DAY]


def _windows(spans):
    """A predicate true on the given [a, b) spans of seconds after midnight (UTC days from 0)."""
    def visible(t):
        s = np.asarray(t) % DAY
        out = np.zeros(len(s), dtype=bool)
        for a, b in spans:
            out |= (s >= a) & (s < b)
        return out
    return visible


def test_an_interval_already_open_at_midnight_is_kept():
    """The midnight sun: seen from 00:00 to 05:00:00.3 and from 20:00:00.7 to the end of the day."""
    vis = _windows([(0.0, 5 * 3600 + 0.3), (20 * 3600 + 0.7, DAY)])
    t0 = np.array([0.0, DAY])
    tol = 0.5
    out, err = iv.visible_intervals(vis, t0, t0 + DAY, 120.0, tol)
    for d in range(2):
        day = out[d] - t0[d]
        assert day.shape == (2, 2)
        assert day[0, 0] == 0.0 and day[1, 1] == DAY  # the day's own bounds, exactly
        # each transition to within its half-bracket, at most the tolerance
        assert abs(day[0, 1] - (5 * 3600 + 0.3)) <= tol and abs(day[1, 0] - (20 * 3600 + 0.7)) <= tol
        assert 0 < err[d] <= 2 * tol
    hours = sum(float(np.sum(o[:, 1] - o[:, 0])) for o in out) / 3600 / 2
    assert abs(hours - (5 + 4)) <= 2 * tol / 3600


def test_a_day_seen_throughout_and_a_day_never_seen():
    t0 = np.array([0.0])
    out, err = iv.visible_intervals(lambda t: np.ones(len(t), bool), t0, t0 + DAY, 600.0, 1.0)
    assert out[0].tolist() == [[0.0, DAY]] and err.tolist() == [0.0]
    out, err = iv.visible_intervals(lambda t: np.zeros(len(t), bool), t0, t0 + DAY, 600.0, 1.0)
    assert out[0].shape == (0, 2) and err.tolist() == [0.0]


def test_uneven_days_and_steps():
    """Days of 23 h and 25 h with a 7-minute step (neither divides the day): the last sample is
    the day's end, and transitions anywhere in a short last step are found."""
    t0 = np.array([0.0, 23 * 3600.0])
    t1 = np.array([23 * 3600.0, 48 * 3600.0])
    a, b = 3 * 3600 + 11.0, 23 * 3600 - 100.0  # the second one in the last, 4-minute step of day 0

    def vis(t):
        t = np.asarray(t)
        return ((t >= a) & (t < b)) | ((t >= t0[1] + 3600.25) & (t < t0[1] + 24 * 3600 + 17.0))
    out, err = iv.visible_intervals(vis, t0, t1, 420.0, 0.25)
    assert np.allclose(out[0], [[a, b]], atol=0.25)
    assert np.allclose(out[1], [[t0[1] + 3600.25, t0[1] + 24 * 3600 + 17.0]], atol=0.25)
    assert np.all(err <= 2 * 0.25) and np.all(err > 0)


def test_north_window_in_the_midnight_sun(build):
    """78 N, 20 May, window facing true north, no obstruction, min altitude 0, no refraction: the
    sun stays up all day (noon-opposite altitude = delta - 12 deg > 0), and a north window sees it
    while it is north of the east-west line, |H| > H0 with cos H0 = tan(delta) / tan(phi), which
    includes local midnight. Hours = 24 - 2 H0 / 15."""
    lat, date = 78.0, "05-20"
    b = build(BoxRoom(building_height=0), location={"latitude": lat, "longitude": 0.0, "timezone": "UTC"},
              sunlight={"date": date, "period": {"start": date, "end": date}, "refraction": False,
                        "min_altitude_deg": 0.0, "tolerance_s": 1}, view=None, true_north_deg=180.0)
    r = b.sunlight()
    noon = dt.datetime.fromisoformat(f"2026-{date}T12:00:00+00:00").timestamp()
    dec = sp.declination([noon - 12 * 3600, noon, noon + 12 * 3600])
    assert dec.min() - (90 - lat) > 5  # up all day, by a margin

    def hours(d):
        return 24 - 2 * np.degrees(np.arccos(np.tan(np.radians(d)) / np.tan(np.radians(lat)))) / 15

    # Tolerance: the formula holds delta fixed while it drifts ~0.3 deg over the day (the ends of
    # the window's time move with it, bounded by the day's extremes of delta), plus 1 minute for
    # rays grazing the window plane near the east-west line (P is 1 mm inside the glazing, so
    # directions within ~0.06 deg of the plane miss the 2 m opening), plus the bisection's error.
    lo, hi = sorted([hours(dec.min()), hours(dec.max())])
    tol = 1 / 60 + r.error_h[0]
    assert lo - tol <= r.hours[0] <= hi + tol, (r.hours[0], lo, hi)
    day = r.intervals[0]
    t_start = dt.datetime.fromisoformat(f"2026-{date}T00:00:00+00:00").timestamp()
    assert day[0, 0] == t_start and day[-1, 1] == t_start + DAY  # open at both midnights


# --- bisection ---------------------------------------------------------------------------------

def test_bisection_halves_to_the_given_width_or_count():
    roots = np.array([0.3, 1.7, 2.25])
    key = np.arange(3)

    def above(k, x):
        return x >= roots[k]
    lo, hi = np.array([0.0, 1.0, 2.0]), np.array([1.0, 2.0, 3.0])
    lo2, hi2 = bisect_transitions(above, key, lo, hi, np.zeros(3, bool), iterations=10)
    assert np.allclose(hi2 - lo2, 2.0 ** -10, rtol=0, atol=1e-15)  # ten halvings of 1, exactly
    assert np.all((lo2 < roots) & (roots <= hi2))
    lo3, hi3 = bisect_transitions(above, key, lo, hi, np.zeros(3, bool), max_width=1e-3)
    assert np.all(hi3 - lo3 <= 1e-3) and np.all(hi3 - lo3 > 5e-4)  # stops at the first width <= 1e-3
    assert np.all((lo3 < roots) & (roots <= hi3))
    # a falling transition (true at lo), and both limits: the first reached wins
    lo4, hi4 = bisect_transitions(lambda k, x: x < 0.3, key[:1], lo[:1], hi[:1], np.ones(1, bool), iterations=3,
                                  max_width=1e-6)
    assert lo4.tolist() == [0.25] and hi4.tolist() == [0.375]
    lo5, hi5 = bisect_transitions(above, key, lo, hi, np.zeros(3, bool), iterations=0)
    assert lo5.tolist() == lo.tolist() and hi5.tolist() == hi.tolist()
    lo6, _ = bisect_transitions(above, key[:0], lo[:0], hi[:0], np.zeros(0, bool), iterations=5)
    assert len(lo6) == 0
    with pytest.raises(ValueError):
        bisect_transitions(above, key, lo, hi, np.zeros(3, bool))


def test_refraction_applies_down_to_the_sunrise_limit_itself():
    """SPA eq. 42: the correction applies where e0 >= -(0.26667 + 0.5667) deg, the limit included."""
    e0 = np.array([-(0.26667 + 0.5667)])
    expected = (1010.0 / 1010.0) * (283.0 / 283.0) * 1.02 / (60.0 * np.tan(np.radians(e0 + 10.3 / (e0 + 5.11))))
    assert sp.refraction_correction(e0, 1010.0, 10.0)[0] == pytest.approx(expected[0], rel=1e-12)
