"""Small geometric functions on numpy arrays: normals, areas, triangulation, solid angles.

Lengths are in metres, angles in radians unless a name says ``_deg``.
"""
from __future__ import annotations

import numpy as np


def check_shape(name: str, array, shape: tuple) -> np.ndarray:
    """Return ``array`` as an ndarray, raising ``ValueError`` unless it has ``shape``.

    ``None`` in ``shape`` matches any length. The message states the expected and actual shape.
    """
    a = np.asarray(array)
    if a.ndim != len(shape) or any(s is not None and s != t for s, t in zip(shape, a.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise ValueError(f"{name}: expected shape {want}, got {a.shape}")
    return a


def triangulate_polygon(polygon: np.ndarray) -> np.ndarray:
    """Triangulate one simple polygon, concave or slightly non-planar, in its best-fit plane.

    Uses ear clipping (mapbox-earcut) on the projection onto the plane of the Newell normal,
    so no triangle covers area outside a concave polygon (a fan would).

    Parameters
    ----------
    polygon : (k, 3) float [m], k >= 3

    Returns
    -------
    (k - 2, 3) int
        Indices into ``polygon``; fewer rows if the polygon is degenerate or self-intersecting.
    """
    polygon = np.asarray(polygon, dtype=float)
    if len(polygon) == 3:
        return np.array([[0, 1, 2]])
    return triangulate_polygons(polygon[None])[0]


def triangulate_polygons(polygons: np.ndarray) -> list:
    """Triangulate many simple polygons with the same vertex count; see :func:`triangulate_polygon`.

    The best-fit planes (Newell normals) and 2D projections are computed for all polygons at
    once; only the ear clipping itself runs per polygon (mapbox-earcut's API takes one polygon).

    Parameters
    ----------
    polygons : (n, k, 3) float [m], k >= 4

    Returns
    -------
    list of n (t, 3) int arrays, indices into each polygon (t < k - 2 if it is degenerate)

    References
    ----------
    Sutherland, Sproull, Schumacker (1974), "A characterization of ten hidden-surface
    algorithms", ACM Computing Surveys 6(1), p. 15 (Newell's method for the plane normal).
    """
    import mapbox_earcut

    p = np.asarray(polygons, dtype=float)
    q = np.roll(p, -1, axis=1)
    n = np.stack([np.sum((p[..., 1] - q[..., 1]) * (p[..., 2] + q[..., 2]), axis=1),
                  np.sum((p[..., 2] - q[..., 2]) * (p[..., 0] + q[..., 0]), axis=1),
                  np.sum((p[..., 0] - q[..., 0]) * (p[..., 1] + q[..., 1]), axis=1)], axis=1)
    norm = np.linalg.norm(n, axis=1)
    good = np.isfinite(norm) & (norm > 0)
    n = np.where(good[:, None], n / np.where(good, norm, 1.0)[:, None], [0.0, 0.0, 1.0])
    helper = np.where((np.abs(n[:, 2]) < 0.9)[:, None], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    u = np.cross(helper, n)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(n, u)
    centred = p - p.mean(axis=1, keepdims=True)
    flat = np.stack([np.einsum("nkj,nj->nk", centred, u), np.einsum("nkj,nj->nk", centred, v)], axis=-1)
    ring = np.array([p.shape[1]], dtype=np.uint32)
    empty = np.zeros((0, 3), dtype=int)
    return [mapbox_earcut.triangulate_float64(f, ring).reshape(-1, 3).astype(int) if g else empty
            for f, g in zip(flat, good)]  # one ear clipping per polygon


def triangle_normals(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals and areas of triangles.

    Parameters
    ----------
    triangles : (n, 3, 3) float [m]

    Returns
    -------
    normals : (n, 3) float (zero rows for degenerate triangles)
    areas : (n,) float [m^2]
    """
    cross = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    norm = np.linalg.norm(cross, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        normals = np.where(norm[:, None] > 0, cross / norm[:, None], 0.0)
    return normals, 0.5 * norm


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


def window_axes(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal width axis and in-plane 'up' axis of a window with unit ``normal`` (3,).

    For a horizontal window (skylight) the width axis is the local x axis.
    """
    a = np.cross([0.0, 0.0, 1.0], normal)
    if np.linalg.norm(a) < 1e-9:
        a = np.array([1.0, 0.0, 0.0])
    a /= np.linalg.norm(a)
    up = np.cross(normal, a)
    return a, up / np.linalg.norm(up)


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
    def f(x, y):
        return np.arctan(x * y / np.sqrt(1.0 + x * x + y * y))

    return f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0)


def unit(vectors: np.ndarray) -> np.ndarray:
    """Rows of ``vectors`` (n, 3) scaled to unit length."""
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)
