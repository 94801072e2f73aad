"""What lies on each side of a gbXML glazing: which space's closed shell, if any, a point just off it falls in.

The file's surface types are a strong hint, not the truth: Revit writes exterior walls as
``InteriorWall`` with the same space on both sides, and glazing between two rooms as a window of
an ``ExteriorWall``. The geometry decides: from the centroid of each glazed opening, points at
:data:`PROBE_M` on both sides along its normal are tested against every space's closed shell
(ray parity: a ray crossing a closed surface an odd number of times starts inside it). A side is
the first space that contains one of its points, nearest first; a side with no space within
1 m has nothing but shading or the outdoors on it.
"""
from __future__ import annotations

import numpy as np

#: Distances from the glazing at which each side is probed [m]: past a wall's half thickness to 1 m.
PROBE_M = (0.15, 0.3, 0.5, 0.75, 1.0)
#: A generic direction for the parity rays (not parallel to walls, floors or common roof slopes).
_RAY = np.array([0.5773, 0.3321, 0.7459])
_RAY = _RAY / np.linalg.norm(_RAY)
#: Almost straight up (off vertical by about 1.4 deg, so that it runs along no vertical face and
#: through no common edge).
UP = np.array([0.0123, 0.0211, 1.0])
UP = UP / np.linalg.norm(UP)


def crossings(points: np.ndarray, tri: np.ndarray, ray: np.ndarray = _RAY) -> np.ndarray:
    """(p,) int: how many triangles of ``tri`` ((t, 3, 3) [m]) the ray from each point along the unit
    direction ``ray`` crosses ahead.

    Möller-Trumbore intersection, vectorised over points and triangles (Möller & Trumbore 1997,
    doi:10.1080/10867651.1997.10487468).
    """
    if len(tri) == 0 or len(points) == 0:
        return np.zeros(len(points), dtype=np.int64)
    a, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    pvec = np.cross(ray, e2)  # (t, 3)
    det = np.einsum("ij,ij->i", e1, pvec)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    tvec = points[:, None, :] - a[None]  # (p, t, 3)
    u = np.einsum("ptj,tj->pt", tvec, pvec) * inv
    qvec = np.cross(tvec, e1[None])
    v = np.einsum("j,ptj->pt", ray, qvec) * inv
    t = np.einsum("ptj,tj->pt", qvec, e2) * inv
    return (ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)).sum(axis=1)


def points_in_shells(points: np.ndarray, shells: list[np.ndarray]) -> np.ndarray:
    """(p, s) bool: point p inside closed shell s (triangles (t, 3, 3) [m]), by the parity of the
    crossings of one ray per point along :data:`_RAY` (:func:`crossings`)."""
    out = np.zeros((len(points), len(shells)), dtype=bool)
    for s, tri in enumerate(shells):  # one pass per space
        if len(tri) == 0:
            continue
        lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
        near = np.flatnonzero(np.all((points >= lo) & (points <= hi), axis=1))  # outside its box: outside it
        if len(near):
            out[near, s] = crossings(points[near], tri) % 2 == 1
    return out


def glazing_sides(centres: np.ndarray, normals: np.ndarray, shells: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The space on each side of each glazing: index into ``shells``, or -1 where no space is within 1 m.

    Parameters
    ----------
    centres : (w, 3) float [m], area centroids of the glazings
    normals : (w, 3) float, unit normals (either orientation)
    shells : list of (t, 3, 3) float [m] closed shells, one per space

    Returns
    -------
    front, back : (w,) int, the space on the +normal side and on the -normal side
    """
    w = len(centres)
    if w == 0 or not shells:
        return np.full(w, -1), np.full(w, -1)
    d = np.asarray(PROBE_M)
    sides = []
    for sign in (1.0, -1.0):
        pts = centres[:, None, :] + sign * d[None, :, None] * normals[:, None, :]  # (w, k, 3)
        inside = points_in_shells(pts.reshape(-1, 3), shells).reshape(w, len(d), len(shells))
        any_at = inside.any(axis=2)  # (w, k)
        first = np.argmax(any_at, axis=1)  # nearest probe inside some space
        space = np.argmax(inside[np.arange(w), first], axis=1)
        sides.append(np.where(any_at.any(axis=1), space, -1))
    return sides[0], sides[1]

