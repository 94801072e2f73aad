"""The daylight glare probability and what it is made of: pure numerics, vectorised, no Radiance.

DGP = c1 E_v + c2 log10(1 + Σ_i L_i² ω_i / (E_v^1.87 P_i²)) + c3 (Wienold and Christoffersen 2006),
with evalglare's constants c1 = 5.87e-5, c2 = 0.092, c3 = 0.159 (its source; the paper rounds them to
9.18e-2 and 0.16: at most 0.002 apart), so that this tool's DGP and the reference (evalglare on a
fisheye) share one formula. E_v is the vertical illuminance at the eye [lx], L_i, ω_i the luminance
[cd/m²] and solid angle [sr] of each glare source (a direction brighter than a fixed threshold,
evalglare's default of 2000 cd/m² since its version 2.05), P_i Guth's position index (Iwata's
below the line of sight), as evalglare computes them (``pictool.c``: ``pict_get_tau``,
``get_posindex``).
"""
from __future__ import annotations

import numpy as np

#: evalglare's DGP constants (``evalglare.c``: c1, c2, c3, and the exponents a1 = 2, a3 = 1.87, a4 = 2).
C1, C2, C3 = 5.87e-5, 0.092, 0.159
EV_EXPONENT = 1.87
#: The position index is capped here (evalglare).
MAX_POSITION_INDEX = 16.0
#: Refractive index of Radiance's ``glass`` (``m_glass.c``).
GLASS_INDEX = 1.52
#: Angular diameter of the sun [deg] and its solid angle [sr].
SUN_DIAMETER_DEG = 0.533
SUN_SOLID_ANGLE_SR = 2.0 * np.pi * (1.0 - np.cos(np.radians(SUN_DIAMETER_DEG / 2.0)))


def dgp(ev_lx, glare_sum, low_light_correction: bool = False) -> np.ndarray:
    """Daylight glare probability from the vertical illuminance and the sources' sum.

    Parameters
    ----------
    ev_lx : array [lx], vertical illuminance at the eye
    glare_sum : array, same shape, Σ L² ω / P² over the glare sources [cd² sr / m⁴]
    low_light_correction : multiply by exp(0.024 E_v - 4) / (1 + exp(0.024 E_v - 4)) below 1000 lx
        (Wienold 2009; evalglare's option, off by default since its version 3)

    Returns
    -------
    array in [0, 1]; 0 where E_v is 0

    References
    ----------
    J. Wienold, J. Christoffersen (2006), Evaluation methods and development of a new glare
    prediction model for daylight environments with the use of CCD cameras, Energy and Buildings
    38(7); evalglare.c (``get_dgp``).
    """
    ev = np.asarray(ev_lx, dtype=float)
    s = np.asarray(glare_sum, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = C1 * ev + C2 * np.log10(1.0 + np.where(ev > 0, s / np.maximum(ev, 1e-300) ** EV_EXPONENT, 0.0)) + C3
        if low_light_correction:
            x = np.exp(np.minimum(0.024 * ev - 4.0, 700.0))
            out = np.where(ev < 1000.0, out * x / (1.0 + x), out)
    return np.clip(np.where(ev > 0, out, 0.0), 0.0, 1.0)


def view_frame(view_dir) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(forward, right, up) unit vectors of a view looking along ``view_dir`` (3,) with z up, as
    evalglare sets them (-vu 0 0 1: right = forward x up, up = right x forward)."""
    f = np.asarray(view_dir, dtype=float)
    f = f / np.linalg.norm(f)
    r = np.cross(f, [0.0, 0.0, 1.0])
    if np.linalg.norm(r) < 1e-9:
        r = np.cross(f, [0.0, 1.0, 0.0])
    r /= np.linalg.norm(r)
    return f, r, np.cross(r, f)


def position_index(directions, view_dir) -> np.ndarray:
    """Position index of directions seen by an eye looking along ``view_dir`` (z up).

    Above the line of sight Guth's, P = exp((35.2 - 0.31889 τ - 1.22 exp(-2 τ / 9)) σ / 1000 +
    (21 + 0.26667 τ - 0.002963 τ²) σ² / 100000), σ the angle between the direction and the line of
    sight [deg], τ the angle from the vertical of the plane through both [deg]; below it Iwata's,
    P = 1 + f R, R = sqrt(tan² φ + tan² θ) (at most 3), f = 0.8 (1.2 where R > 0.6), φ and θ the
    direction's angles above the horizontal and to the side of the view; capped at 16.

    Parameters
    ----------
    directions : (n, 3) unit vectors
    view_dir : (3,) the line of sight

    Returns
    -------
    (n,) float >= 1; NaN behind the eye (the direction at or beyond 90 deg)

    References
    ----------
    IES Lighting Handbook (Guth's position index); M. Iwata, M. Tokura (1998), Position index for
    a glare source located below the line of vision, Lighting Research and Technology 30;
    evalglare.c ``get_posindex`` and pictool.c ``pict_get_tau``, ``pict_get_vangle``,
    ``pict_get_hangle``.
    """
    d = np.asarray(directions, dtype=float).reshape(-1, 3)
    f, r, u = view_frame(view_dir)
    x, y, z = d @ r, d @ u, d @ f
    front = z > 1e-12
    with np.errstate(invalid="ignore", divide="ignore"):
        sigma = np.degrees(np.arccos(np.clip(z, -1.0, 1.0)))
        lateral = np.hypot(x, y)
        tau = np.degrees(np.arccos(np.clip(np.where(lateral > 0, y / np.where(lateral > 0, lateral, 1.0), 1.0), -1.0, 1.0)))
        guth = np.exp((35.2 - 0.31889 * tau - 1.22 * np.exp(-2.0 * tau / 9.0)) / 1000.0 * sigma
                      + (21.0 + 0.26667 * tau - 0.002963 * tau**2) / 100000.0 * sigma**2)
        phi = np.arcsin(np.clip(y, -1.0, 1.0))
        teta = np.arcsin(np.clip(x, -1.0, 1.0))
        teta = np.where(teta == 0.0, 1e-4, teta)
        rr = np.sqrt(np.tan(phi) ** 2 + np.tan(teta) ** 2)
        iwata = 1.0 + np.where(rr > 0.6, 1.2, 0.8) * np.minimum(rr, 3.0)
    p = np.minimum(np.where(phi < 0, iwata, guth), MAX_POSITION_INDEX)
    return np.where(front, p, np.nan)


def glass_transmission(tn, cos_incidence) -> np.ndarray:
    """Transmittance of Radiance's ``glass`` at an angle of incidence: the Fresnel reflectances of a
    pane of index 1.52 for both polarisations, the transmissivity ``tn`` raised to the path length
    1 / cos of the refracted angle, internal reflections summed (Radiance reference manual, glass;
    ``m_glass.c``). At normal incidence it is the tv whose :func:`~en17037cli.criteria.daylight.
    radiance.glass_transmissivity` is ``tn``.

    Parameters
    ----------
    tn : array, transmissivity in (0, 1]
    cos_incidence : array, cos of the angle between the ray and the pane's normal (sign ignored)

    Returns
    -------
    array in [0, 1)
    """
    c1 = np.clip(np.abs(np.asarray(cos_incidence, dtype=float)), 1e-9, 1.0)
    n = GLASS_INDEX
    c2 = np.sqrt((1.0 - 1.0 / n**2) + c1**2 / n**2)
    d = np.asarray(tn, dtype=float) ** (1.0 / c2)
    re = ((c1 - n * c2) / (c1 + n * c2)) ** 2
    rm = ((1.0 / c1 - n / c2) / (1.0 / c1 + n / c2)) ** 2
    return 0.5 * (1 - re) ** 2 * d / (1 - re**2 * d**2) + 0.5 * (1 - rm) ** 2 * d / (1 - rm**2 * d**2)


def sphere_directions(n: int) -> np.ndarray:
    """``n`` unit vectors spread evenly over the sphere (a Fibonacci lattice), each standing for the
    same solid angle 4 π / n [sr] (Swinbank and Purser 2006; González 2010).

    Returns
    -------
    (n, 3) float
    """
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    phi = np.pi * (1.0 + np.sqrt(5.0)) * i
    r = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def reinhart_bins(mf: int) -> int:
    """Bins of the Reinhart sky MF with the ground: 144 MF² + 2 (146 for MF 1)."""
    return 144 * mf * mf + 2


def reinhart_bin(directions, mf: int) -> np.ndarray:
    """Reinhart patch (gendaymtx's row: 0 the ground, 1.. the sky from due north clockwise, row by
    row upwards, the zenith cap last) of each direction, as ``reinhartb.cal``'s ``rbin`` bins a
    ray; directions in the sky's frame (x east, y north, z up).

    Parameters
    ----------
    directions : (n, 3) unit vectors
    mf : Reinhart subdivision

    Returns
    -------
    (n,) int in [0, 144 MF² + 1]
    """
    d = np.asarray(directions, dtype=float).reshape(-1, 3)
    rings = np.repeat(np.array([30, 30, 24, 24, 18, 12, 6]) * mf, mf)
    rowalt = 90.0 / (7 * mf + 0.5)
    alt = np.degrees(np.arcsin(np.clip(d[:, 2], -1.0, 1.0)))
    row = np.floor(alt / rowalt).astype(int)
    first = np.concatenate([[1], 1 + np.cumsum(rings)])  # first patch of each row; the cap after the last
    az = np.degrees(np.arctan2(d[:, 0], d[:, 1])) % 360.0
    nrow = len(rings)
    inrow = np.minimum(row, nrow - 1).clip(0)
    k = np.floor((az + 0.5 * 360.0 / rings[inrow]) / (360.0 / rings[inrow])).astype(int) % rings[inrow]
    out = first[inrow] + k
    out = np.where(row >= nrow, first[-1], out)
    return np.where(d[:, 2] < 0, 0, out)
