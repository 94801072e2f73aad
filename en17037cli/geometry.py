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


def newell_normal(polygon: np.ndarray) -> np.ndarray:
    """Unnormalised normal of a (possibly non-planar) polygon by Newell's method.

    Parameters
    ----------
    polygon : (k, 3) float [m]

    Returns
    -------
    (3,) float [m^2]; its length is twice the area of the polygon projected on its best-fit plane.

    References
    ----------
    Sutherland, Sproull, Schumacker (1974), "A characterization of ten hidden-surface
    algorithms", ACM Computing Surveys 6(1), p. 15 (Newell's method).
    """
    p = np.asarray(polygon, dtype=float)
    q = np.roll(p, -1, axis=0)
    return np.array([
        np.sum((p[:, 1] - q[:, 1]) * (p[:, 2] + q[:, 2])),
        np.sum((p[:, 2] - q[:, 2]) * (p[:, 0] + q[:, 0])),
        np.sum((p[:, 0] - q[:, 0]) * (p[:, 1] + q[:, 1])),
    ])


def plane_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two orthonormal vectors spanning the plane normal to ``normal`` (3,)."""
    n = normal / np.linalg.norm(normal)
    helper = np.array([0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(helper, n)
    u /= np.linalg.norm(u)
    return u, np.cross(n, u)


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
    import mapbox_earcut

    k = len(polygon)
    if k == 3:
        return np.array([[0, 1, 2]])
    n = newell_normal(polygon)
    if not np.all(np.isfinite(n)) or np.linalg.norm(n) == 0:
        return np.zeros((0, 3), dtype=int)
    u, v = plane_basis(n)
    centred = polygon - polygon.mean(axis=0)
    flat = np.column_stack([centred @ u, centred @ v])
    idx = mapbox_earcut.triangulate_float64(flat, np.array([k], dtype=np.uint32))
    return idx.reshape(-1, 3).astype(int)


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
    return float(np.arctan(a * b / (d * np.sqrt(a * a + b * b + d * d))))


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
