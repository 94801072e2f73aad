"""Triangles and polygons in 3D: shape checks, normals and areas, triangulation, a window's axes.

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
    n, u, v, good = plane_bases(n)
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


def plane_bases(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Orthonormal bases of planes from (unnormalised) normals (m, 3): the unit normal ``n`` (+z
    where a normal is zero or not finite), two unit in-plane axes ``u``, ``v`` with ``u x v = n``
    (dimensionless), and ``good`` (m,) bool: the normal was finite and non-zero."""
    norm = np.linalg.norm(normals, axis=1)
    good = np.isfinite(norm) & (norm > 0)
    n = np.where(good[:, None], normals / np.where(good, norm, 1.0)[:, None], [0.0, 0.0, 1.0])
    helper = np.where((np.abs(n[:, 2]) < 0.9)[:, None], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    u = np.cross(helper, n)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return n, u, np.cross(n, u), good
