"""The CIE standard overcast sky and the sky component of openings, by a solid-angle integral of our
own (no Radiance): a second code path that checks the Radiance runs and bounds what they can give.

The sky component of a point is the part of its daylight factor that comes straight from the sky
through the openings, unobstructed and before the glazing's transmittance.
"""
from __future__ import annotations

import functools

import numpy as np

from en17037cli.geometry.solid_angle import triangle_solid_angle


def cie_overcast_luminance(altitude_rad) -> np.ndarray:
    """Relative luminance of the CIE standard overcast sky, L(γ) / L_z = (1 + 2 sin γ) / 3.

    Parameters
    ----------
    altitude_rad : array [rad], altitude γ of the sky element above the horizon

    Returns
    -------
    array [-], 1 at the zenith, 1/3 at the horizon

    References
    ----------
    CIE S 011/E:2003 (ISO 15469:2004), sky type 16 (the CIE standard overcast sky); Moon and
    Spencer (1942).
    """
    return (1.0 + 2.0 * np.sin(altitude_rad)) / 3.0


def overcast_horizontal_illuminance(zenith_luminance) -> np.ndarray:
    """Illuminance of an unobstructed horizontal plane under the CIE overcast sky: 7 π L_z / 9.

    Parameters
    ----------
    zenith_luminance : [cd/m²]

    Returns
    -------
    [lx]; the integral of L(γ) sin γ over the upper hemisphere (Hopkinson et al., Daylighting, 1966)
    """
    return 7.0 * np.pi * np.asarray(zenith_luminance, dtype=float) / 9.0


def subdivide(triangles: np.ndarray, n: int) -> np.ndarray:
    """Each triangle (k, 3, 3) cut into n² similar triangles (k n², 3, 3), the areas equal."""
    tris = np.asarray(triangles, dtype=float).reshape(-1, 3, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    up = i + j < n  # upward triangles (i, j), (i+1, j), (i, j+1); downward where i + j < n - 1
    a = np.stack([i[up], j[up]], 1)
    bary_up = np.stack([a, a + [1, 0], a + [0, 1]], 1)  # (u, 3, 2)
    dn = i + j < n - 1
    b = np.stack([i[dn], j[dn]], 1)
    bary_dn = np.stack([b + [1, 0], b + [1, 1], b + [0, 1]], 1)
    bary = np.concatenate([bary_up, bary_dn]) / n  # (n², 3, 2) in units of the two edges
    p0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    out = p0[:, None, None] + bary[None, :, :, :1] * e1[:, None, None] + bary[None, :, :, 1:] * e2[:, None, None]
    return out.reshape(-1, 3, 3)


def sky_component(points, triangles, subdivisions: int = 24, normal=(0.0, 0.0, 1.0)) -> np.ndarray:
    """Sky component of openings under the CIE overcast sky, as a share of the unobstructed
    horizontal illuminance: ∫ L(γ) cos θ dω / (7 π L_z / 9) over the openings' solid angle.

    Each opening triangle is cut into ``subdivisions``² triangles whose exact solid angle
    (Van Oosterom and Strackee 1983) is weighted by L(γ) cos θ at its centroid's direction
    (directions below the horizon, or behind the plane of ``normal``, add nothing): the midpoint
    rule, error O(h²) in the size of the pieces. Nothing obstructs: the openings are assumed seen
    whole (a black room with no obstruction outside).

    Parameters
    ----------
    points : (n, 3) float [m]
    triangles : (k, 3, 3) float [m], the openings
    subdivisions : pieces along each edge of a triangle
    normal : (3,) the receiving plane's unit normal (horizontal plane: +z)

    Returns
    -------
    (n,) float [-], 1 for a point that sees the whole sky hemisphere

    References
    ----------
    CIE 171:2006, Test cases to assess the accuracy of lighting computer programs, 5.x (sky
    component for openings under the CIE overcast sky); A. van Oosterom and J. Strackee (1983),
    The solid angle of a plane triangle, IEEE Trans. Biomed. Eng. 30(2), 125-126.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    pieces = subdivide(triangles, subdivisions)
    nrm = np.asarray(normal, dtype=float)
    out = np.zeros(len(pts))
    for a in range(0, len(pts), 16):  # blocks of points bound memory; each block vectorised
        p = pts[a:a + 16]
        pp = np.repeat(p, len(pieces), axis=0)
        omega = triangle_solid_angle(pp, np.tile(pieces, (len(p), 1, 1))).reshape(len(p), len(pieces))  # [sr]
        d = pieces.mean(axis=1)[None] - p[:, None]
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        sin_alt = d[..., 2]
        cos_t = d @ nrm
        w = np.where((sin_alt > 0) & (cos_t > 0), cie_overcast_luminance(np.arcsin(np.clip(sin_alt, -1, 1))) * cos_t, 0.0)
        out[a:a + 16] = (omega * w).sum(axis=1) / (7.0 * np.pi / 9.0)
    return out


#: Refractive index of Radiance's ``glass`` (its default; the manual's 1.52).
GLASS_INDEX = 1.52
#: Glazing whose normal-hemispherical transmittance is at least this is an open opening (no glass).
OPEN_TV = 0.999


def glass_transmittance(cos_i, tv) -> np.ndarray:
    """Transmittance of Radiance's ``glass`` at incidence cos i, given its normal transmittance tv.

    A thin pane of index n = 1.52 with transmissivity tn (:func:`~.radiance.glass_transmissivity`
    of tv) and its internal reflections, averaged over the two polarisations (Radiance's
    ``m_glass``): cos t = sqrt(1 - (1 - cos² i) / n²), d = tn^(1 / cos t),
    r_s = ((cos i - n cos t) / (cos i + n cos t))², r_p = ((1/cos i - n/cos t) / (1/cos i + n/cos t))²,
    τ = ½ (1 - r_s)² d / (1 - r_s² d²) + ½ (1 - r_p)² d / (1 - r_p² d²). τ(1) = tv; 1 where tv is
    at least :data:`OPEN_TV` (an open opening).

    Parameters
    ----------
    cos_i : array, cosine of the angle between the ray and the pane's normal, in (0, 1]
    tv : array broadcast against it, normal-hemispherical transmittance in [0, 1]

    Returns
    -------
    array [-]

    References
    ----------
    Radiance ``src/rt/glass.c`` (G. Ward, LBNL) and the reference manual, "Glass".
    """
    from en17037cli.criteria.daylight.radiance import glass_transmissivity

    c = np.clip(np.asarray(cos_i, dtype=float), 1e-9, 1.0)
    tv = np.asarray(tv, dtype=float)
    n = GLASS_INDEX
    tn = np.clip(glass_transmissivity(np.where(tv >= OPEN_TV, 0.5, tv)), 1e-15, 1.0)
    cos_t = np.sqrt((1.0 - 1.0 / (n * n)) + c * c / (n * n))
    d = tn ** (1.0 / cos_t)
    rs = ((c - n * cos_t) / (c + n * cos_t)) ** 2
    rp = ((1.0 / c - n / cos_t) / (1.0 / c + n / cos_t)) ** 2
    tau = 0.5 * (1 - rs) ** 2 * d / (1 - rs * rs * d * d) + 0.5 * (1 - rp) ** 2 * d / (1 - rp * rp * d * d)
    return np.where(tv >= OPEN_TV, 1.0, np.where(tv > 0, tau, 0.0))


#: Knots of :func:`transmittance_table` in cos i (uniform on [0, 1]).
TABLE_KNOTS = 4097


@functools.lru_cache(maxsize=64)
def transmittance_table(tv: float) -> tuple[np.ndarray, np.ndarray, float]:
    """:func:`glass_transmittance` of ``tv`` tabulated on :data:`TABLE_KNOTS` uniform knots of cos i,
    for linear interpolation (``np.interp``), and the largest error of that interpolation [-]: the
    largest difference from the formula at the midpoints between knots (where linear interpolation
    errs most, by h² |τ''| / 8), doubled. Returns (knots, values, error)."""
    c = np.linspace(0.0, 1.0, TABLE_KNOTS)
    t = glass_transmittance(c, tv)
    mid = 0.5 * (c[1:] + c[:-1])
    err = 2.0 * float(np.max(np.abs(glass_transmittance(mid, tv) - 0.5 * (t[1:] + t[:-1]))))
    return c, t, err


def glass_reflectance(cos_i, tv) -> np.ndarray:
    """Reflectance of Radiance's ``glass`` at incidence cos i, given its normal transmittance tv (the
    same pane as :func:`glass_transmittance`): with d = tn^(1 / cos t),
    ρ = ½ r_s (1 + (1 - 2 r_s) d²) / (1 - r_s² d²) + ½ r_p (1 + (1 - 2 r_p) d²) / (1 - r_p² d²);
    0 for an open opening (tv at least :data:`OPEN_TV`).

    References
    ----------
    Radiance ``src/rt/glass.c`` (``m_glass``: the reflected ray's coefficient).
    """
    from en17037cli.criteria.daylight.radiance import glass_transmissivity

    c = np.clip(np.asarray(cos_i, dtype=float), 1e-9, 1.0)
    tv = np.asarray(tv, dtype=float)
    n = GLASS_INDEX
    tn = np.clip(glass_transmissivity(np.where(tv >= OPEN_TV, 0.5, tv)), 1e-15, 1.0)
    cos_t = np.sqrt((1.0 - 1.0 / (n * n)) + c * c / (n * n))
    d2 = (tn ** (1.0 / cos_t)) ** 2
    rs = ((c - n * cos_t) / (c + n * cos_t)) ** 2
    rp = ((1.0 / c - n / cos_t) / (1.0 / c + n / cos_t)) ** 2
    rho = 0.5 * rs * (1 + (1 - 2 * rs) * d2) / (1 - rs * rs * d2) + 0.5 * rp * (1 + (1 - 2 * rp) * d2) / (1 - rp * rp * d2)
    return np.where(tv >= OPEN_TV, 0.0, rho)
