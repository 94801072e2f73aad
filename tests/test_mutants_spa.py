"""The SPA of en17037cli step by step against pvlib's independent implementation (mutation testing,
docs/mutation.md).

pvlib.spa implements the same NREL SPA (Reda and Andreas 2004) in plain numpy: the two share the
published equations, not code, so each step must agree to float64 round-off. pvlib is not a test
dependency (its pandas and scipy would change what the memory test in test_robustness measures):
``make mutation`` installs it without dependencies, and these tests are skipped without it.
"""
from __future__ import annotations

import datetime as dt

import numpy as np
import pytest

from en17037cli.criteria.sunlight import solar_position as sp


def _pvlib_spa():
    """pvlib's spa.py on its own (numpy only): importing the pvlib package would load pandas and
    scipy (~100 MB), which a later test that measures a child process's peak memory inherits."""
    import importlib.util

    found = importlib.util.find_spec("pvlib")
    if found is None or not found.submodule_search_locations:
        pytest.skip("pvlib is not installed (pip install -e '.[test]')", allow_module_level=True)
    spec = importlib.util.spec_from_file_location("_pvlib_spa", f"{found.submodule_search_locations[0]}/spa.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


spa = _pvlib_spa()

RNG = np.random.default_rng(17037)
# 400 instants between 1950 and 2100 (the range of the delta T polynomials used here)
T = np.sort(RNG.uniform(dt.datetime(1950, 1, 1, tzinfo=dt.UTC).timestamp(), dt.datetime(2100, 1, 1, tzinfo=dt.UTC).timestamp(), 400))
PLACES = [(52.0, 4.36, 0.0), (-33.9, 18.4, 1500.0), (78.2, 15.6, 30.0), (0.0, -179.0, 0.0), (39.742476, -105.1786, 1830.14)]


def wrap(a):
    """Angle difference folded into [-180, 180) [deg]."""
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


def pv_steps(t, lat, lon, elev, pressure, temp, delta_t):
    """Every intermediate quantity of the SPA from pvlib, keyed like en17037cli's steps."""
    jd = spa.julian_day(t)
    jde = spa.julian_ephemeris_day(jd, delta_t)
    jc, jce = spa.julian_century(jd), spa.julian_ephemeris_century(jde)
    jme = spa.julian_ephemeris_millennium(jce)
    L, B, R = spa.heliocentric_longitude(jme), spa.heliocentric_latitude(jme), spa.heliocentric_radius_vector(jme)
    theta, beta = spa.geocentric_longitude(L), spa.geocentric_latitude(B)
    x = [f(jce) for f in (spa.mean_elongation, spa.mean_anomaly_sun, spa.mean_anomaly_moon, spa.moon_argument_latitude,
                          spa.moon_ascending_longitude)]
    nut = np.empty((2, len(t)))
    spa.longitude_obliquity_nutation(jce, *x, nut)
    eps = spa.true_ecliptic_obliquity(spa.mean_ecliptic_obliquity(jme), nut[1])
    lam = spa.apparent_sun_longitude(theta, nut[0], spa.aberration_correction(R))
    nu = spa.apparent_sidereal_time(spa.mean_sidereal_time(jd, jc), nut[0], eps)
    alpha, delta = spa.geocentric_sun_right_ascension(lam, eps, beta), spa.geocentric_sun_declination(lam, eps, beta)
    H = spa.local_hour_angle(nu, lon, alpha)
    xi = spa.equatorial_horizontal_parallax(R)
    u = spa.uterm(lat)
    xt, yt = spa.xterm(u, lat, elev), spa.yterm(u, lat, elev)
    dalpha = spa.parallax_sun_right_ascension(xt, xi, H, delta)
    delta_p = spa.topocentric_sun_declination(delta, xt, yt, xi, dalpha, H)
    H_p = spa.topocentric_local_hour_angle(H, dalpha)
    e0 = spa.topocentric_elevation_angle_without_atmosphere(lat, delta_p, H_p)
    de = spa.atmospheric_refraction_correction(pressure, temp, e0, 0.5667)
    az = spa.topocentric_azimuth_angle(spa.topocentric_astronomers_azimuth(H_p, delta_p, lat))
    return dict(jd=jd, jde=jde, jc=jc, jce=jce, jme=jme, L=L, B=B, R=R, theta=theta, beta=beta, dpsi=nut[0], deps=nut[1],
                eps=eps, lam=lam, nu=nu, alpha=alpha, delta=delta, H_p=H_p, delta_p=delta_p, e0=e0, de=de, az=az)


def test_delta_t_polynomials_match_pvlib_every_month_and_at_the_boundaries():
    """Espenak and Meeus (2006) as pvlib.spa.calculate_deltat writes them: the same polynomials,
    so equal to round-off (1e-9 s); at y = 1961, 1986, 2005, 2050 exactly the later piece applies."""
    year, month = np.meshgrid(np.arange(1941, 2150), np.arange(1, 13))
    y = year + (month - 0.5) / 12
    assert np.allclose(sp.delta_t(y.ravel()), spa.calculate_deltat(year.ravel(), month.ravel()), rtol=0, atol=1e-9)
    edges = np.array([1961, 1986, 2005, 2050])
    assert np.allclose(sp.delta_t(edges.astype(float)), spa.calculate_deltat(edges, np.full(4, 0.5)), rtol=0, atol=1e-9)


@pytest.mark.parametrize("lat, lon, elev", PLACES)
def test_every_spa_step_matches_pvlib(lat, lon, elev):
    dT = 69.2
    pv = pv_steps(T, lat, lon, elev, 1013.25, 12.0, dT)
    jd = sp.julian_day(T)
    jde = sp.julian_ephemeris_day(jd, dT)
    jc, jce = sp.julian_century(jd), sp.julian_ephemeris_century(jde)
    jme = sp.julian_ephemeris_millennium(jce)
    # Julian days ~2.4e6: float64 round-off 5e-10 d; the centuries and millennia scale it down
    for key, ours in (("jd", jd), ("jde", jde), ("jc", jc), ("jce", jce), ("jme", jme)):
        assert np.allclose(ours, pv[key], rtol=0, atol=1e-9), key
    L, B, R = sp.heliocentric_longitude(jme), sp.heliocentric_latitude(jme), sp.heliocentric_radius_vector(jme)
    theta, beta = sp.geocentric_longitude(L), sp.geocentric_latitude(B)
    dpsi, deps = sp.nutation(jce)
    eps = sp.true_obliquity(jme, deps)
    lam = sp.apparent_sun_longitude(theta, dpsi, R)
    nu = sp.apparent_sidereal_time(jd, jc, dpsi, eps)
    alpha, delta = sp.sun_right_ascension_declination(lam, eps, beta)
    H_p, delta_p = sp.topocentric_position(nu, alpha, delta, R, lat, lon, elev)
    e0 = sp.elevation_without_refraction(lat, H_p, delta_p)
    de = sp.refraction_correction(e0, 1013.25, 12.0)
    az = sp.azimuth(lat, H_p, delta_p)
    # Angles: sums of up to ~60 periodic terms and products with 36525-day rates; the two
    # implementations add them in different orders, so they agree to ~1e-9 deg, not bit for bit.
    # 1e-8 deg is still 30 000 times finer than the aberration term (20.5" = 5.7e-3 deg).
    for key, ours in (("L", L), ("theta", theta), ("lam", lam), ("nu", nu), ("alpha", alpha), ("H_p", H_p), ("az", az)):
        assert np.max(np.abs(wrap(ours - pv[key]))) < 1e-8, key
    for key, ours in (("B", B), ("beta", beta), ("dpsi", dpsi), ("deps", deps), ("eps", eps), ("delta", delta),
                      ("delta_p", delta_p), ("e0", e0), ("de", de)):
        assert np.max(np.abs(ours - pv[key])) < 1e-8, key
    assert np.max(np.abs(R - pv["R"])) < 1e-12  # AU, ~1


@pytest.mark.parametrize("lat, lon, elev", PLACES)
@pytest.mark.parametrize("refraction", [True, False])
def test_solar_position_matches_pvlib(lat, lon, elev, refraction):
    dT = 67.0
    for pressure, temp in ((1013.25, 12.0), (820.0, -20.0)):
        e, a = sp.solar_position(T, lat, lon, elev, pressure, temp, delta_t_s=dT, refraction=refraction)
        _, _, pe, pe0, pa, _ = spa.solar_position_numpy(T, lat, lon, elev, pressure, temp, dT, 0.5667, 1)
        assert np.max(np.abs(e - (pe if refraction else pe0))) < 1e-8  # round-off of the summed terms, as above
        assert np.max(np.abs(wrap(a - pa))) < 1e-8


def test_default_delta_t_is_that_of_the_date():
    """Without delta_t_s the SPA uses the Espenak-Meeus delta T of the decimal year of each instant:
    equal to giving that delta T explicitly. Mid-year instants are mid-year to 0.002 yr, i.e. delta T
    to 0.002 s (< 0.7 s/yr here): 1e-7 deg of elevation, 1e-5 deg of azimuth (which turns up to
    0.006 deg/s near noon); a year fraction off by 0.1 yr moves delta T by ~0.06 s (3e-4 deg)."""
    t = np.array([dt.datetime(y, 7, 2, 12, tzinfo=dt.UTC).timestamp() for y in (1960, 1980, 2000, 2026, 2080)])
    year_fraction = np.array([1960.5, 1980.5, 2000.5, 2026.5, 2080.5])  # 2 July noon is mid-year to 0.002 yr
    for i in range(len(t)):
        dts = float(sp.delta_t(year_fraction[i]))
        e1, a1 = sp.solar_position(t[i:i + 1], 52.0, 4.36)
        e2, a2 = sp.solar_position(t[i:i + 1], 52.0, 4.36, delta_t_s=dts)
        assert abs(e1[0] - e2[0]) < 1e-7 and abs(wrap(a1[0] - a2[0])) < 1e-5
        d1 = sp.declination(t[i:i + 1])
        d2 = sp.declination(t[i:i + 1], delta_t_s=dts)
        assert abs(d1[0] - d2[0]) < 1e-8  # declination moves 0.4 deg/day at most: 0.01 s is 5e-8 deg
        pv = pv_steps(t[i:i + 1], 0.0, 0.0, 0.0, 1013.25, 12.0, dts)
        assert abs(d2[0] - pv["delta"][0]) < 1e-8
    # integer input (unix seconds as int) is converted, not truncated
    assert np.allclose(sp.declination(np.array([1_700_000_000])), sp.declination(np.array([1_700_000_000.0])), atol=0)
