"""Sun position against published reference values."""
from __future__ import annotations

import datetime as dt

import numpy as np

from en17037cli.criteria.sunlight import solar_position as sp


def test_spa_reference_example():
    # Reda and Andreas (2004), Table A5.1: 2003-10-17 12:30:30 local time UTC-7, lat 39.742476,
    # lon -105.1786, elevation 1830.14 m, 820 mbar, 11 degC, delta T 67 s:
    # topocentric zenith 50.11162 deg, azimuth 194.34024 deg (published to 1e-5 deg).
    t = dt.datetime(2003, 10, 17, 12, 30, 30, tzinfo=dt.timezone(dt.timedelta(hours=-7))).timestamp()
    e, a = sp.solar_position([t], 39.742476, -105.1786, 1830.14, 820.0, 11.0, delta_t_s=67.0)
    assert abs((90 - e[0]) - 50.11162) < 1e-5
    assert abs(a[0] - 194.34024) < 1e-5


def test_spa_intermediate_values():
    # Same example, intermediate quantities of Table A5.1 (L, B, R, delta psi, delta epsilon, epsilon).
    t = dt.datetime(2003, 10, 17, 19, 30, 30, tzinfo=dt.UTC).timestamp()
    jd = sp.julian_day(t)
    assert abs(jd - 2452930.312847) < 1e-6
    jme = sp.julian_ephemeris_millennium(sp.julian_ephemeris_century(sp.julian_ephemeris_day(jd, 67.0)))
    jme = np.atleast_1d(jme)
    assert abs(sp.heliocentric_longitude(jme)[0] - 24.0182616917) < 1e-6
    assert abs(sp.heliocentric_latitude(jme)[0] - (-0.0001011219)) < 1e-9
    assert abs(sp.heliocentric_radius_vector(jme)[0] - 0.9965422974) < 1e-9
    jce = jme * 10
    dpsi, deps = sp.nutation(jce)
    assert abs(dpsi[0] - (-0.00399840)) < 1e-7
    assert abs(deps[0] - 0.00166657) < 1e-7
    assert abs(sp.true_obliquity(jme, deps)[0] - 23.440465) < 1e-6


def test_delta_t_matches_published_values():
    # Espenak and Meeus (2006): delta T was 63.8 s in 2000 and about 69 s in 2020 (observed 69.4 s);
    # the polynomial is within a couple of seconds, i.e. < 0.01 deg of hour angle.
    assert abs(sp.delta_t(2000.0) - 63.86) < 0.01
    assert abs(sp.delta_t(2020.0) - 71.6) < 3.0


def test_direction_vectors_follow_true_north():
    # sun due south at the horizon; north rotated 90 deg clockwise from +Y means north is +X,
    # so south is -X
    d = sp.direction_vectors(np.array([0.0]), np.array([180.0]), 0.0)
    assert np.allclose(d, [[0, -1, 0]], atol=1e-12)
    d = sp.direction_vectors(np.array([0.0]), np.array([180.0]), 90.0)
    assert np.allclose(d, [[-1, 0, 0]], atol=1e-12)


def test_sun_position_matches_pvlib_spa_at_many_places_and_times():
    """An independent SPA implementation (pvlib.spa, its own delta T): elevation and azimuth agree to
    1e-5 deg, the SPA example's published precision, every 37 minutes of three days at five places
    from the equator to 78 N and both hemispheres (with and without refraction)."""
    from oracles import sun_position

    t = dt.datetime(2026, 2, 1, tzinfo=dt.UTC).timestamp() + np.arange(0, 3 * 86400, 37 * 60.0)
    for lat, lon in ((52.0, 4.36), (0.0, 0.0), (-34.0, 18.4), (78.0, 15.6), (40.7, -74.0)):
        for refraction in (False, True):
            e, a = sp.solar_position(t, lat, lon, refraction=refraction)
            e0, a0 = sun_position(t, lat, lon, refraction=refraction)
            assert np.max(np.abs(e - e0)) < 1e-5, (lat, lon, refraction)
            up = e0 > -1  # azimuth is defined everywhere, but compare it where the sun matters
            assert np.max(np.abs((a - a0 + 180) % 360 - 180)[up], initial=0.0) < 1e-5, (lat, lon, refraction)
