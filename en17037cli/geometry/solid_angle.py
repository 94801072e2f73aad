"""Exact solid angles: triangles, rectangles in gnomonic coordinates, and triangles clipped to rectangles.

Angles in steradians; lengths in metres or, in the gnomonic plane at unit distance, dimensionless.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry.planar import clip_halfplane


def triangle_solid_angle(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Solid angle subtended by triangles as seen from points, unsigned.

    Parameters
    ----------
    points : (n, 3) float [m]
    triangles : (n, 3, 3) float [m]
        Vertices of triangle i, seen from point i.

    Returns
    -------
    (n,) float [sr]

    References
    ----------
    Van Oosterom, A. and Strackee, J. (1983). The solid angle of a plane triangle.
    IEEE Transactions on Biomedical Engineering BME-30(2), 125-126. doi:10.1109/TBME.1983.325207
    """
    r = triangles - points[:, None, :]
    r1, r2, r3 = r[:, 0], r[:, 1], r[:, 2]
    l1, l2, l3 = (np.linalg.norm(x, axis=1) for x in (r1, r2, r3))
    numerator = np.einsum("ij,ij->i", r1, np.cross(r2, r3))
    denominator = (
        l1 * l2 * l3
        + np.einsum("ij,ij->i", r1, r2) * l3
        + np.einsum("ij,ij->i", r1, r3) * l2
        + np.einsum("ij,ij->i", r2, r3) * l1
    )
    return np.abs(2.0 * np.arctan2(numerator, denominator))


def rectangle_solid_angle(a: float, b: float, d: float) -> float:
    """Solid angle of an a x b rectangle seen from a point at distance d on the normal through a corner.

    Parameters
    ----------
    a, b, d : float [m]

    Returns
    -------
    float [sr]

    References
    ----------
    Omega = atan(a b / (d sqrt(a^2 + b^2 + d^2))), the corner case of the rectangular-plate
    formula; see e.g. Mathar, R. J. (2015), "Solid angle of a rectangular plate",
    Max-Planck Institute for Astronomy, Heidelberg.
    """
    return float(offset_rectangle_solid_angle(0.0, a / d, 0.0, b / d))


def offset_rectangle_solid_angle(x0, x1, y0, y1) -> np.ndarray:
    """Solid angle of rectangles [x0, x1] x [y0, y1] on the plane at unit distance from the viewpoint.

    Coordinates are measured in that plane from the foot of the perpendicular through the
    viewpoint (gnomonic coordinates), so a rectangle [x0, x1] x [y0, y1] on a plane at distance
    d is the same as [x0/d, x1/d] x [y0/d, y1/d] here. Exact, by inclusion-exclusion over the
    corner formula F(x, y) = atan(x y / sqrt(1 + x^2 + y^2)), which is odd in x and in y.

    Parameters
    ----------
    x0, x1, y0, y1 : array_like [-] (lengths divided by the distance), x0 <= x1, y0 <= y1

    Returns
    -------
    ndarray [sr]

    References
    ----------
    Mathar, R. J. (2015), "Solid angle of a rectangular plate", Max-Planck Institute for
    Astronomy, Heidelberg, eq. (23) (the corner case) and its sums over sub-rectangles.
    """
    f = corner_solid_angle
    return f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0)


def corner_solid_angle(x, y) -> np.ndarray:
    """Signed solid angle of the rectangle [0, x] x [0, y] on the plane at unit distance from the
    viewpoint, one corner at the foot of the perpendicular: F(x, y) = atan(x y / sqrt(1 + x^2 + y^2)).

    :func:`offset_rectangle_solid_angle` sums it over a rectangle's corners; a grid of rectangles
    that share corners needs it once per corner (the same numbers, bit for bit).

    Parameters
    ----------
    x, y : array_like [-] (lengths divided by the distance)

    Returns
    -------
    ndarray [sr]

    References
    ----------
    Mathar, R. J. (2015), "Solid angle of a rectangular plate", Max-Planck Institute for
    Astronomy, Heidelberg, eq. (23).
    """
    return np.arctan(x * y / np.sqrt(1.0 + x * x + y * y))


def clipped_solid_angle(tri: np.ndarray, rect: np.ndarray):
    """Solid angle and centroid of triangles clipped to rectangles, in gnomonic coordinates.

    Parameters
    ----------
    tri : (m, 3, 2) float, triangles on the plane at unit distance (see
        :func:`~en17037cli.geometry.offset_rectangle_solid_angle`)
    rect : (m, 4) float, (x0, x1, y0, y1)

    Returns
    -------
    omega : (m,) float [sr], exact (sum of Van Oosterom-Strackee fan triangles of the convex clip)
    centroid : (m, 2) float, area centroid of the clipped polygon (NaN where it is empty)
    """
    poly, count = tri.astype(float), np.full(len(tri), 3)
    for axis, col, sign in ((0, 0, 1.0), (0, 1, -1.0), (1, 2, 1.0), (1, 3, -1.0)):
        poly, count = clip_halfplane(poly, count, axis, rect[:, col], sign)
    return polygon_solid_angle(poly, count)


def polygon_solid_angle(poly: np.ndarray, count: np.ndarray):
    """Solid angle and centroid of convex polygons on the plane at unit distance, in gnomonic coordinates.

    Parameters
    ----------
    poly : (m, k, 2) float, the vertices in order (the first ``count`` of each row)
    count : (m,) int

    Returns
    -------
    omega : (m,) float [sr], exact (sum of Van Oosterom-Strackee fan triangles)
    centroid : (m, 2) float, area centroid (NaN where the polygon is empty)
    """
    m, k, _ = poly.shape
    omega = np.zeros(m)
    area = np.zeros(m)
    moment = np.zeros((m, 2))
    p3 = np.concatenate([poly, np.ones((m, k, 1))], axis=2)
    zero = np.zeros((m, 3))
    for i in range(1, k - 1):  # fan triangles (0, i, i + 1) over the vertex slots
        ok = i + 1 < count
        t3 = np.stack([p3[:, 0], p3[:, i], p3[:, i + 1]], axis=1)
        omega += np.where(ok, triangle_solid_angle(zero, t3), 0.0)
        e1, e2 = poly[:, i] - poly[:, 0], poly[:, i + 1] - poly[:, 0]
        a2 = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
        a2 = np.where(ok, a2, 0.0)
        area += a2
        moment += a2[:, None] * (poly[:, 0] + poly[:, i] + poly[:, i + 1]) / 3.0
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = moment / area[:, None]
    return omega, np.where(area[:, None] > 0, centroid, np.nan)
