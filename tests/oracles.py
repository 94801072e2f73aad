"""Independent answers for the tests: closed forms and another implementation of the sun.

Nothing here imports the package under test. The sun comes from pvlib's SPA (a test-only
dependency: pvlib.spa, numpy path, with pvlib's own delta T); solid angles of triangles from
L'Huilier's theorem (spherical excess), not the Van Oosterom-Strackee formula the engine uses;
the box room's answers from the rectangle formula by hand.
"""
from __future__ import annotations

import datetime as dt

import numpy as np

# --- the sun ------------------------------------------------------------------------------------


def _delta_t(unixtime) -> np.ndarray:
    from pvlib import spa

    t = np.atleast_1d(np.asarray(unixtime, dtype=float))
    d = [dt.datetime.fromtimestamp(x, dt.UTC) for x in t[[0, -1]]]
    # pvlib's polynomial by year and month; constant over one test's few days (it moves ~0.03 s a month)
    return spa.calculate_deltat(np.array([d[0].year]), np.array([d[0].month]))[0]


def sun_position(unixtime, lat: float, lon: float, refraction: bool = False, elevation_m: float = 0.0,
                 pressure_mbar: float = 1013.25, temperature_c: float = 12.0) -> tuple[np.ndarray, np.ndarray]:
    """Sun elevation and azimuth [deg] (clockwise from north) by pvlib's SPA (Reda and Andreas 2004).

    Parameters
    ----------
    unixtime : (n,) float [s]; lat, lon : [deg]
    """
    from pvlib import spa

    t = np.atleast_1d(np.asarray(unixtime, dtype=float))
    out = spa.solar_position_numpy(t, lat, lon, elevation_m, pressure_mbar, temperature_c, _delta_t(t), 0.5667,
                                   numthreads=1, sst=False, esd=False)
    # rows: apparent zenith, zenith, apparent elevation, elevation, azimuth, equation of time
    elevation = out[2] if refraction else out[3]
    return np.asarray(elevation, float), np.asarray(out[4], float)


def sun_declination(unixtime) -> np.ndarray:
    """Geocentric declination of the sun [deg], pvlib's SPA chain (eqs. 1-31 of the SPA paper), one
    time at a time (pvlib's nutation step is written per scalar)."""
    from pvlib import spa

    out = []
    for t in np.atleast_1d(np.asarray(unixtime, dtype=float)):  # a handful of times per test
        jd = spa.julian_day(t)
        jce = spa.julian_ephemeris_century(spa.julian_ephemeris_day(jd, _delta_t(t)))
        jme = spa.julian_ephemeris_millennium(jce)
        nut = np.empty(2)
        spa.longitude_obliquity_nutation(jce, spa.mean_elongation(jce), spa.mean_anomaly_sun(jce),
                                         spa.mean_anomaly_moon(jce), spa.moon_argument_latitude(jce),
                                         spa.moon_ascending_longitude(jce), nut)
        eps = spa.true_ecliptic_obliquity(spa.mean_ecliptic_obliquity(jme), nut[1])
        lam = spa.apparent_sun_longitude(spa.geocentric_longitude(spa.heliocentric_longitude(jme)), nut[0],
                                         spa.aberration_correction(spa.heliocentric_radius_vector(jme)))
        out.append(spa.geocentric_sun_declination(lam, eps, spa.geocentric_latitude(spa.heliocentric_latitude(jme))))
    return np.array(out, dtype=float)


def sun_vectors(elevation_deg, azimuth_deg, true_north_deg: float = 0.0) -> np.ndarray:
    """Unit vectors towards the sun, x east, y north (z up), with true north at ``true_north_deg``
    clockwise from +y."""
    e, a = np.radians(elevation_deg), np.radians(np.asarray(azimuth_deg) + true_north_deg)
    return np.column_stack([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), np.sin(e)])


def hour_angle_hours(lat: float, dec: float, gamma: float) -> float:
    """Hours of the sun above altitude ``gamma`` [deg] on a day of declination ``dec`` [deg] at
    latitude ``lat`` [deg]: 2 H / 15 with cos H = (sin gamma - sin phi sin delta) / (cos phi cos delta);
    24 h when the sun never goes below, 0 h when it never rises above."""
    phi, d, g = np.radians(lat), np.radians(dec), np.radians(gamma)
    c = (np.sin(g) - np.sin(phi) * np.sin(d)) / (np.cos(phi) * np.cos(d))
    return float(2 * np.degrees(np.arccos(np.clip(c, -1.0, 1.0))) / 15)


def local_midnight(date: str, utc_offset_h: float = 0.0, year: int = 2026) -> float:
    """Unix time [s] of 00:00 local time on ``date`` (MM-DD) at a fixed UTC offset [h]."""
    return dt.datetime.fromisoformat(f"{year}-{date}T00:00:00+00:00").timestamp() - utc_offset_h * 3600


# --- solid angles and sight angles --------------------------------------------------------------


def triangle_solid_angle_lhuilier(p, tri) -> float:
    """Solid angle [sr] of a triangle (3, 3) [m] seen from p (3,), by L'Huilier's theorem: the
    spherical excess E of the triangle's central projection, tan(E/4) = sqrt(tan(s/2) tan((s-a)/2)
    tan((s-b)/2) tan((s-c)/2)), a, b, c its arc lengths and s half their sum."""
    u = np.asarray(tri, float) - np.asarray(p, float)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    arc = lambda i, j: np.arccos(np.clip(u[i] @ u[j], -1.0, 1.0))  # noqa: E731
    a, b, c = arc(1, 2), arc(0, 2), arc(0, 1)
    s = 0.5 * (a + b + c)
    t = np.tan(s / 2) * np.tan((s - a) / 2) * np.tan((s - b) / 2) * np.tan((s - c) / 2)
    return float(4 * np.arctan(np.sqrt(max(t, 0.0))))


def polygon_solid_angle_y0(p, polygon) -> float:
    """Solid angle [sr] of a shapely polygon in the plane y = 0 (coordinates x, z) seen from p: a
    sum of L'Huilier triangles over a constrained triangulation of the polygon."""
    import shapely

    if polygon.is_empty or polygon.area == 0:
        return 0.0
    total = 0.0
    for tri in shapely.delaunay_triangles(polygon).geoms:
        if not tri.representative_point().within(polygon):
            continue
        xz = np.asarray(tri.exterior.coords)[:3]
        total += triangle_solid_angle_lhuilier(p, np.column_stack([xz[:, 0], np.zeros(3), xz[:, 1]]))
    return total


def rect_solid_angle_y0(x1: float, x2: float, z1: float, z2: float, point) -> float:
    """Exact solid angle [sr] of the rectangle x in [x1, x2], z in [z1, z2] of the plane y = 0 seen
    from ``point`` (x0, y0, z0), y0 != 0, by adding and subtracting corner rectangles.

    The corner term F(a, b) = atan(a b / (d sqrt(a^2 + b^2 + d^2))) is the solid angle of an
    a x b rectangle seen from distance d above one corner (signed in a and b).
    """
    x0, y0, z0 = point
    d = abs(y0)

    def F(a, b):
        return np.arctan(a * b / (d * np.sqrt(a * a + b * b + d * d)))

    if x2 <= x1 or z2 <= z1:
        return 0.0
    return float(F(x2 - x0, z2 - z0) - F(x1 - x0, z2 - z0) - F(x2 - x0, z1 - z0) + F(x1 - x0, z1 - z0))


def sight_angle_deg(x0: float, y0: float, half: float = 1.0, reveal: float = 0.0) -> float:
    """Horizontal sight angle [deg] of the box room's window (x in [-half, half] at y = 0) from
    (x0, y0); with reveals of depth r the inner edge (y = r) or the outer edge (y = 0) limits each
    side, whichever is tighter."""
    right = min(np.arctan2(half - x0, y0), np.arctan2(half - x0, y0 - reveal))
    left = min(np.arctan2(half + x0, y0), np.arctan2(half + x0, y0 - reveal))
    return float(np.degrees(max(right + left, 0.0)))


def layer_solid_angles(p, window_x=(-1.0, 1.0), window_z=(0.8, 2.2), street=25.0, building_height=10.0):
    """Sky, landscape and ground solid angles [sr] seen through the box room's window from p: the
    building's top and base lines, projected from p onto the window plane, cut the window into
    three rectangles (zero-thickness wall)."""
    x0, y0, z0 = p
    D, H = street, building_height
    z_top = z0 + (H - z0) * y0 / (y0 + D)
    z_base = z0 - z0 * y0 / (y0 + D)
    (a, b), (lo, hi) = window_x, window_z
    sky = rect_solid_angle_y0(a, b, max(z_top, lo), hi, p)
    land = rect_solid_angle_y0(a, b, max(z_base, lo), min(z_top, hi), p)
    ground = rect_solid_angle_y0(a, b, lo, min(z_base, hi), p)
    return sky, land, ground


def sun_hours_exact(t0: float, t1: float, lat: float, lon: float, margins, refraction: bool = False,
                    step_s: float = 60.0, tol_s: float = 1e-3) -> tuple[float, np.ndarray]:
    """Hours between unix times ``t0`` and ``t1`` [s] during which every margin of the sun is >= 0,
    and the times where visibility changes [s], located to ``tol_s`` on pvlib's sun.

    ``margins`` are callables (elevation [deg] (n,), unit sun vectors (n, 3)) -> (n,) continuous
    margins (e.g. elevation - 11, the sun vector . a window's outward normal). Sampled every
    ``step_s``; each sign change of a margin is refined by bisection on that margin alone, so a
    change is exact whatever the step, as long as a margin changes sign at most once per step
    (smooth over a minute: the sun moves 0.25 deg).
    """
    def values(t):
        e, a = sun_position(t, lat, lon, refraction=refraction)
        v = sun_vectors(e, a)
        return np.array([m(e, v) for m in margins])  # (margins, n)

    t = np.append(np.arange(t0, t1, step_s), t1)
    m = values(t)
    cuts = []
    for k in range(len(margins)):  # refine each margin's sign changes
        i = np.flatnonzero((m[k, 1:] >= 0) != (m[k, :-1] >= 0))
        lo, hi, s_lo = t[i], t[i + 1], m[k, i] >= 0
        while len(lo) and np.max(hi - lo) > tol_s:
            mid = 0.5 * (lo + hi)
            same = (values(mid)[k] >= 0) == s_lo
            lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
        cuts.append(0.5 * (lo + hi))
    cuts = np.sort(np.concatenate([np.array([t0, t1]), *cuts]))
    mids = 0.5 * (cuts[1:] + cuts[:-1])
    seen = np.all(values(mids) >= 0, axis=0)
    return float(np.sum(np.diff(cuts)[seen]) / 3600.0), cuts[1:-1]
