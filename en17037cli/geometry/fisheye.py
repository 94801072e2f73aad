"""The equidistant fisheye projection of the report's pictures, looking horizontally out of a
window: directions to picture coordinates (:func:`fisheye_xy`) and picture pixels back to
directions (:func:`fisheye_directions`), which the sunlight criterion traces.

Reference: the equidistant (f-theta) projection, r = f theta (e.g. Kingslake, Optics in
Photography, 1992); the verification of EN 17037 clause 5.3 (Annex A) draws the sun's paths over
the obstructions seen from point P in a view of this kind.
"""
from __future__ import annotations

import math

import numpy as np


def fisheye_xy(azimuth_deg, altitude_deg, view_azimuth_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Equidistant fisheye coordinates of directions, looking horizontally at ``view_azimuth_deg``.

    The radius is proportional to the angle from the optical axis (1 at 90 deg, the rim of the
    180 deg field); x is to the right when looking out, y up (the zenith is at (0, 1)).
    Directions behind the viewer get radii above 1.

    Parameters
    ----------
    azimuth_deg : array_like [deg], clockwise from true north
    altitude_deg : array_like [deg], above the horizon
    view_azimuth_deg : float [deg], azimuth of the optical axis (the window's outward normal)

    Returns
    -------
    x, y : arrays of the broadcast shape, in [-1, 1] within the field
    """
    a = np.radians(np.asarray(azimuth_deg, dtype=float) - view_azimuth_deg)
    h = np.radians(np.asarray(altitude_deg, dtype=float))
    fwd = np.cos(h) * np.cos(a)
    right = np.cos(h) * np.sin(a)
    up = np.sin(h)
    side = np.hypot(right, up)
    rho = np.arctan2(side, fwd) / (0.5 * np.pi)  # angle off axis / 90 deg
    with np.errstate(invalid="ignore", divide="ignore"):
        x = np.where(side > 0, rho * right / side, np.where(fwd >= 0, 0.0, rho))  # straight behind: off the field
        y = np.where(side > 0, rho * up / side, 0.0)
    return x, y


def fisheye_pixel_xy(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Fisheye coordinates (x, y) of the pixel centres of an (n, n) raster, row 0 at the top.

    Returns
    -------
    x, y : (n, n) float, x[i, j] = (2 j + 1) / n - 1 and y[i, j] = 1 - (2 i + 1) / n
    """
    c = (2.0 * np.arange(n) + 1.0) / n - 1.0
    return np.broadcast_to(c[None, :], (n, n)), np.broadcast_to(-c[:, None], (n, n))


def fisheye_directions(n: int, view_azimuth_deg: float, true_north_deg: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors in the model frame through the pixel centres of an (n, n) equidistant fisheye.

    The inverse of :func:`fisheye_xy` on the raster of :func:`fisheye_pixel_xy`. A direction of
    azimuth A (clockwise from true north) and altitude h is the model-frame vector
    (sin(A + tn) cos h, cos(A + tn) cos h, sin h), tn = ``true_north_deg``, as
    :func:`en17037cli.criteria.sunlight.solar_position.direction_vectors` has it.

    Parameters
    ----------
    n : int, pixels per side
    view_azimuth_deg : float [deg], azimuth of the optical axis clockwise from true north
    true_north_deg : float [deg], azimuth of true north clockwise from model +Y

    Returns
    -------
    dirs : (n, n, 3) float, unit vectors; pixels outside the circle get the continuation of the
        projection (directions behind the viewer), to be ignored
    inside : (n, n) bool, pixel centre within the 180 deg circle (radius <= 1)
    """
    x, y = fisheye_pixel_xy(n)
    rho = np.hypot(x, y)
    theta = 0.5 * np.pi * rho
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(rho > 0, np.sin(theta) / rho, 0.5 * np.pi)
    fwd, right, up = np.cos(theta), s * x, s * y
    v = math.radians(view_azimuth_deg + true_north_deg)
    f = np.array([math.sin(v), math.cos(v), 0.0])
    r = np.array([math.cos(v), -math.sin(v), 0.0])
    # unit by construction: cos^2 + sin^2 (x^2 + y^2) / rho^2 = 1
    dirs = np.stack([fwd * f[0] + right * r[0], fwd * f[1] + right * r[1], up], axis=-1)
    return dirs, rho <= 1.0
