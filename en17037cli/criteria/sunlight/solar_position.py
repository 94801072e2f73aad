"""Solar position by the NREL Solar Position Algorithm (SPA), vectorised with numpy.

One function per step of the published algorithm, named after the quantity it computes and
called in the paper's order by :func:`solar_position`. Uncertainty of the algorithm: +-0.0003 deg
for years -2000 to 6000 (given delta T).

References
----------
Reda, I. and Andreas, A. (2004). Solar position algorithm for solar radiation applications.
Solar Energy 76(5), 577-589. doi:10.1016/j.solener.2003.12.003 (equation numbers below).

Espenak, F. and Meeus, J. (2006). Five Millennium Canon of Solar Eclipses: -1999 to +3000.
NASA/TP-2006-214141, section 2.6 (polynomial expressions for delta T).
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.sunlight import spa_tables as T

_UNIX_EPOCH_JD = 2440587.5  # Julian day of 1970-01-01T00:00:00 UTC


def delta_t(year_fraction):
    """Delta T = TT - UT [s] by the polynomials of Espenak and Meeus (2006), 1941-2150.

    Parameters
    ----------
    year_fraction : array_like, decimal year y = year + (month - 0.5) / 12
    """
    y = np.asarray(year_fraction, dtype=float)
    t = y - 2000
    out = np.where(
        y < 1961, 29.07 + 0.407 * (y - 1950) - (y - 1950) ** 2 / 233 + (y - 1950) ** 3 / 2547,
        np.where(
            y < 1986, 45.45 + 1.067 * (y - 1975) - (y - 1975) ** 2 / 260 - (y - 1975) ** 3 / 718,
            np.where(
                y < 2005, 63.86 + 0.3345 * t - 0.060374 * t**2 + 0.0017275 * t**3 + 0.000651814 * t**4 + 0.00002373599 * t**5,
                np.where(
                    y < 2050, 62.92 + 0.32217 * t + 0.005589 * t**2,
                    -20 + 32 * ((y - 1820) / 100) ** 2 - 0.5628 * (2150 - y),
                ),
            ),
        ),
    )
    return out


def julian_day(unixtime):
    """Julian day JD from seconds since 1970-01-01 UTC (eq. 4 for the Gregorian calendar)."""
    return np.asarray(unixtime, dtype=float) / 86400.0 + _UNIX_EPOCH_JD


def julian_ephemeris_day(jd, delta_t_s):
    """JDE = JD + delta T / 86400 (eq. 5)."""
    return jd + delta_t_s / 86400.0


def julian_century(jd):
    """JC = (JD - 2451545) / 36525 (eq. 6)."""
    return (jd - 2451545.0) / 36525.0


def julian_ephemeris_century(jde):
    """JCE (eq. 7)."""
    return (jde - 2451545.0) / 36525.0


def julian_ephemeris_millennium(jce):
    """JME = JCE / 10 (eq. 8)."""
    return jce / 10.0


def _periodic_sum(table, jme):
    """Sum of A cos(B + C JME) over the rows of a table (eq. 9)."""
    return np.sum(table[:, 0, None] * np.cos(table[:, 1, None] + table[:, 2, None] * jme[None, :]), axis=0)


def heliocentric_longitude(jme):
    """Earth heliocentric longitude L [deg] (eqs. 9-12)."""
    terms = [_periodic_sum(t, jme) for t in (T.L0, T.L1, T.L2, T.L3, T.L4, T.L5)]
    lrad = sum(term * jme**i for i, term in enumerate(terms)) / 1e8
    return np.degrees(lrad) % 360.0


def heliocentric_latitude(jme):
    """Earth heliocentric latitude B [deg] (eqs. 9-12 with Table A4.2 B terms)."""
    terms = [_periodic_sum(t, jme) for t in (T.B0, T.B1)]
    return np.degrees(sum(term * jme**i for i, term in enumerate(terms)) / 1e8)


def heliocentric_radius_vector(jme):
    """Earth radius vector R [AU] (eqs. 9-12 with Table A4.2 R terms)."""
    terms = [_periodic_sum(t, jme) for t in (T.R0, T.R1, T.R2, T.R3, T.R4)]
    return sum(term * jme**i for i, term in enumerate(terms)) / 1e8


def geocentric_longitude(L):
    """Theta = L + 180 [deg] (eq. 13)."""
    return (L + 180.0) % 360.0


def geocentric_latitude(B):
    """beta = -B [deg] (eq. 14)."""
    return -B


def nutation(jce):
    """Nutation in longitude and obliquity, delta psi and delta epsilon [deg] (eqs. 15-23)."""
    x = np.stack([
        297.85036 + 445267.111480 * jce - 0.0019142 * jce**2 + jce**3 / 189474,  # X0, eq. 15
        357.52772 + 35999.050340 * jce - 0.0001603 * jce**2 - jce**3 / 300000,  # X1, eq. 16
        134.96298 + 477198.867398 * jce + 0.0086972 * jce**2 + jce**3 / 56250,  # X2, eq. 17
        93.27191 + 483202.017538 * jce - 0.0036825 * jce**2 + jce**3 / 327270,  # X3, eq. 18
        125.04452 - 1934.136261 * jce + 0.0020708 * jce**2 + jce**3 / 450000,  # X4, eq. 19
    ])
    arg = np.radians(T.NUTATION_YTERM_ARRAY @ x)  # (63, n)
    abcd = T.NUTATION_ABCD_ARRAY
    dpsi = np.sum((abcd[:, 0, None] + abcd[:, 1, None] * jce) * np.sin(arg), axis=0) / 36e6  # eq. 20, 22
    deps = np.sum((abcd[:, 2, None] + abcd[:, 3, None] * jce) * np.cos(arg), axis=0) / 36e6  # eq. 21, 23
    return dpsi, deps


def true_obliquity(jme, deps):
    """True obliquity of the ecliptic epsilon [deg] (eqs. 24-25)."""
    u = jme / 10.0
    eps0 = (84381.448 - 4680.93 * u - 1.55 * u**2 + 1999.25 * u**3 - 51.38 * u**4 - 249.67 * u**5 - 39.05 * u**6
            + 7.12 * u**7 + 27.87 * u**8 + 5.79 * u**9 + 2.45 * u**10)
    return eps0 / 3600.0 + deps


def apparent_sun_longitude(theta, dpsi, R):
    """lambda = Theta + delta psi + delta tau, with aberration delta tau = -20.4898 / (3600 R) [deg] (eqs. 26-27)."""
    return theta + dpsi - 20.4898 / (3600.0 * R)


def apparent_sidereal_time(jd, jc, dpsi, eps):
    """Apparent sidereal time at Greenwich nu [deg] (eqs. 28-29)."""
    nu0 = (280.46061837 + 360.98564736629 * (jd - 2451545.0) + 0.000387933 * jc**2 - jc**3 / 38710000.0) % 360.0
    return nu0 + dpsi * np.cos(np.radians(eps))


def sun_right_ascension_declination(lam, eps, beta):
    """Geocentric right ascension alpha and declination delta [deg] (eqs. 30-31)."""
    lr, er, br = np.radians(lam), np.radians(eps), np.radians(beta)
    alpha = np.degrees(np.arctan2(np.sin(lr) * np.cos(er) - np.tan(br) * np.sin(er), np.cos(lr))) % 360.0
    delta = np.degrees(np.arcsin(np.sin(br) * np.cos(er) + np.cos(br) * np.sin(er) * np.sin(lr)))
    return alpha, delta


def topocentric_position(nu, alpha, delta, R, latitude, longitude, elevation_m):
    """Topocentric hour angle H' and declination delta' [deg] with parallax (eqs. 32-40)."""
    H = (nu + longitude - alpha) % 360.0  # eq. 32
    xi = 8.794 / (3600.0 * R)  # eq. 33
    phi = np.radians(latitude)
    u = np.arctan(0.99664719 * np.tan(phi))  # eq. 34
    x = np.cos(u) + elevation_m / 6378140.0 * np.cos(phi)  # eq. 35
    y = 0.99664719 * np.sin(u) + elevation_m / 6378140.0 * np.sin(phi)  # eq. 36
    xr, Hr, dr = np.radians(xi), np.radians(H), np.radians(delta)
    dalpha = np.arctan2(-x * np.sin(xr) * np.sin(Hr), np.cos(dr) - x * np.sin(xr) * np.cos(Hr))  # eq. 37
    delta_p = np.arctan2((np.sin(dr) - y * np.sin(xr)) * np.cos(dalpha), np.cos(dr) - x * np.sin(xr) * np.cos(Hr))  # eq. 39
    H_p = Hr - dalpha  # eq. 40
    return np.degrees(H_p), np.degrees(delta_p)


def elevation_without_refraction(latitude, H_p, delta_p):
    """Topocentric elevation angle e0 [deg] (eq. 41)."""
    phi, h, d = np.radians(latitude), np.radians(H_p), np.radians(delta_p)
    return np.degrees(np.arcsin(np.sin(phi) * np.sin(d) + np.cos(phi) * np.cos(d) * np.cos(h)))


def refraction_correction(e0, pressure_mbar, temperature_c):
    """Atmospheric refraction delta e [deg] (eq. 42), applied where the sun is above -0.8333 deg
    (the SPA's sunrise refraction plus the sun's radius), zero below."""
    corr = (pressure_mbar / 1010.0) * (283.0 / (273.0 + temperature_c)) * 1.02 / (
        60.0 * np.tan(np.radians(e0 + 10.3 / (e0 + 5.11))))
    return np.where(e0 >= -(0.26667 + 0.5667), corr, 0.0)


def azimuth(latitude, H_p, delta_p):
    """Topocentric azimuth Phi, eastward from north [deg] (eqs. 44-46)."""
    phi, h, d = np.radians(latitude), np.radians(H_p), np.radians(delta_p)
    gamma = np.degrees(np.arctan2(np.sin(h), np.cos(h) * np.sin(phi) - np.tan(d) * np.cos(phi)))
    return (gamma + 180.0) % 360.0


def solar_position(unixtime, latitude, longitude, elevation_m=0.0, pressure_mbar=1013.25, temperature_c=12.0,
                   delta_t_s=None, refraction=True):
    """Apparent topocentric sun position.

    Parameters
    ----------
    unixtime : array_like [s since 1970-01-01 UTC]
    latitude : float [deg], north positive
    longitude : float [deg], east positive
    elevation_m : float [m]
    pressure_mbar : float [mbar]; temperature_c : float [degC] (refraction only)
    delta_t_s : float [s], optional; default from :func:`delta_t` for the dates given
    refraction : bool

    Returns
    -------
    elevation : ndarray [deg], apparent (refracted unless ``refraction`` is False)
    azimuth : ndarray [deg], clockwise from true north
    """
    t = np.atleast_1d(np.asarray(unixtime, dtype=float))
    jd = julian_day(t)
    if delta_t_s is None:
        year_fraction = 1970.0 + t / (365.2425 * 86400.0)
        delta_t_s = delta_t(year_fraction)
    jde = julian_ephemeris_day(jd, delta_t_s)
    jc, jce = julian_century(jd), julian_ephemeris_century(jde)
    jme = julian_ephemeris_millennium(jce)
    L = heliocentric_longitude(jme)
    B = heliocentric_latitude(jme)
    R = heliocentric_radius_vector(jme)
    theta, beta = geocentric_longitude(L), geocentric_latitude(B)
    dpsi, deps = nutation(jce)
    eps = true_obliquity(jme, deps)
    lam = apparent_sun_longitude(theta, dpsi, R)
    nu = apparent_sidereal_time(jd, jc, dpsi, eps)
    alpha, delta = sun_right_ascension_declination(lam, eps, beta)
    H_p, delta_p = topocentric_position(nu, alpha, delta, R, latitude, longitude, elevation_m)
    e0 = elevation_without_refraction(latitude, H_p, delta_p)
    e = e0 + refraction_correction(e0, pressure_mbar, temperature_c) if refraction else e0
    return e, azimuth(latitude, H_p, delta_p)


def declination(unixtime, delta_t_s=None):
    """Geocentric sun declination [deg] (eqs. 1-31), for checks against the hour-angle formula."""
    t = np.atleast_1d(np.asarray(unixtime, dtype=float))
    jd = julian_day(t)
    dts = delta_t(1970.0 + t / (365.2425 * 86400.0)) if delta_t_s is None else delta_t_s
    jce = julian_ephemeris_century(julian_ephemeris_day(jd, dts))
    jme = julian_ephemeris_millennium(jce)
    dpsi, deps = nutation(jce)
    eps = true_obliquity(jme, deps)
    lam = apparent_sun_longitude(geocentric_longitude(heliocentric_longitude(jme)), dpsi, heliocentric_radius_vector(jme))
    return sun_right_ascension_declination(lam, eps, geocentric_latitude(heliocentric_latitude(jme)))[1]


def direction_vectors(elevation_deg, azimuth_deg, true_north_deg: float = 0.0) -> np.ndarray:
    """Unit vectors towards the sun in the model frame (z up).

    ``true_north_deg`` is the azimuth of true north clockwise from model +Y, so a sun azimuth A
    (clockwise from true north) lies at A + true_north_deg clockwise from +Y.

    Returns
    -------
    (n, 3) float
    """
    e = np.radians(elevation_deg)
    a = np.radians(np.asarray(azimuth_deg) + true_north_deg)
    return np.column_stack([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), np.sin(e)])
