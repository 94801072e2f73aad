"""Planar geometry on arrays of 2D triangles and convex polygons: containment and clipping."""
from __future__ import annotations

import numpy as np


def turn(t1, t2) -> np.ndarray:
    """Signed shortest turn from azimuth ``t1`` to ``t2`` [rad], in [-pi, pi].

    Both in [-pi, pi] (``arctan2``'s range). The difference t2 - t1 is exact in float64 when the
    two are within a factor of two of each other (Sterbenz's lemma), so the sign of a small turn is
    the sign of the azimuths' own order: an interval seen edge-on, whose two ends are one unit of
    round-off apart, is a tiny interval, never the whole circle less a tiny one. (The form
    ``(t2 - t1 + pi) % 2 pi - pi`` rounds t2 - t1 + pi, which can turn -1 ulp into 0, and the
    interval from t1 to t2 into 2 pi minus an ulp.) Only a turn across the branch cut at +-pi is
    shifted by 2 pi, where its size is far from zero.

    Parameters
    ----------
    t1, t2 : float or (n,) float [rad], within [-pi, pi]

    Returns
    -------
    (n,) float [rad]; +-pi where the two are opposite (the direction of turn is then undefined)
    """
    d = np.asarray(t2, dtype=float) - np.asarray(t1, dtype=float)
    two_pi = 2.0 * np.pi
    return np.where(d > np.pi, d - two_pi, np.where(d < -np.pi, d + two_pi, d))


def area2(t: np.ndarray) -> float:
    """Twice the unsigned area of one 2D triangle (3, 2)."""
    return abs((t[1, 0] - t[0, 0]) * (t[2, 1] - t[0, 1]) - (t[1, 1] - t[0, 1]) * (t[2, 0] - t[0, 0]))


def in_triangle(pts: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Whether point i lies in (or on the edge of) triangle i, row by row.

    Parameters
    ----------
    pts : (..., 2) float; tri : (..., 3, 2) float, broadcastable, same units

    Returns
    -------
    (...) bool; edges are included with a tolerance of 1e-12 of the triangle's doubled area
    """
    a, b, c = tri[..., 0, :], tri[..., 1, :], tri[..., 2, :]

    def cross(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    s1, s2, s3 = cross(a, b, pts), cross(b, c, pts), cross(c, a, pts)
    tol = np.abs(cross(a, b, c)) * 1e-12
    return ((s1 >= -tol) & (s2 >= -tol) & (s3 >= -tol)) | ((s1 <= tol) & (s2 <= tol) & (s3 <= tol))


def points_in_triangles(xy: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Whether each point (m, 2) lies in (or on the edge of) any of the triangles (k, 3, 2).

    Returns
    -------
    (m,) bool
    """
    return np.any(in_triangle(xy[:, None, :], tri[None, :, :, :]), axis=1)


def clip_halfplane(poly: np.ndarray, count: np.ndarray, axis: int, bound: np.ndarray, sign: float):
    """Sutherland-Hodgman step: keep the part of each convex polygon where sign * (x[axis] - bound) >= 0."""
    return _clip_by(poly, count, sign * (poly[..., axis] - bound[:, None]))


def clip_line(poly: np.ndarray, count: np.ndarray, hp: np.ndarray):
    """Sutherland-Hodgman step: keep the part of each convex polygon (m, k, 2) with ``count``
    vertices where a x + b y + c >= 0, ``hp`` (m, 3) its half-plane's (a, b, c)."""
    return _clip_by(poly, count, hp[:, 0, None] * poly[..., 0] + hp[:, 1, None] * poly[..., 1] + hp[:, 2, None])


def _clip_by(poly: np.ndarray, count: np.ndarray, s: np.ndarray):
    """Keep the part of each convex polygon where the affine function with values ``s`` (m, k) at
    its vertices is >= 0 (it is linear along every edge, so each crossing is interpolated)."""
    m, k, _ = poly.shape
    out = np.zeros((m, k + 1, 2))
    n_out = np.zeros(m, dtype=int)
    rows = np.arange(m)
    for i in range(k):  # over the (at most 7) vertex slots of a polygon, not over data
        j = np.where(i + 1 < count, i + 1, 0)
        active = i < count
        pa, pb = poly[:, i], poly[rows, j]
        sa, sb = s[:, i], s[rows, j]
        keep = active & (sa >= 0)
        out[rows[keep], n_out[keep]] = pa[keep]
        n_out += keep
        cross = active & ((sa >= 0) != (sb >= 0))
        t = sa / np.where(cross, sa - sb, 1.0)
        pc = pa + t[:, None] * (pb - pa)
        out[rows[cross], n_out[cross]] = pc[cross]
        n_out += cross
    return out, n_out


def cut_triangles(tri: np.ndarray, z: np.ndarray):
    """Segments cut from triangles by horizontal planes, vectorised over planes and triangles.

    Half-open rule (a vertex on the plane counts as below): an edge lying in the plane is cut once,
    from the triangle above it.

    Parameters
    ----------
    tri : (k, 3, 3) float [m]
    z : (g,) float [m], heights of the planes

    Returns
    -------
    ok : (g, k) bool, the plane cuts the triangle in a segment
    a, b : (g, k, 2) float [m], the segment's ends (x, y); meaningless where not ``ok``
    """
    s = tri[None, :, :, 2] - np.asarray(z, float)[:, None, None]  # (g, k, 3) height above each plane
    ends = []
    for i, j in ((0, 1), (1, 2), (2, 0)):  # the three edges of every triangle
        si, sj = s[..., i], s[..., j]
        below = si <= 0
        cross = below != (sj <= 0)
        # from the end below the plane to the one above: an edge shared by two triangles is cut
        # at the same point to the last bit in both, so no crack opens between their shadows
        s_lo, s_hi = np.where(below, si, sj), np.where(below, sj, si)
        v_lo = np.where(below[..., None], tri[None, :, i, :2], tri[None, :, j, :2])
        v_hi = np.where(below[..., None], tri[None, :, j, :2], tri[None, :, i, :2])
        t = s_lo / np.where(cross, s_lo - s_hi, 1.0)
        xy = v_lo + t[..., None] * (v_hi - v_lo)
        ends.append((cross, xy))
    flags = np.stack([e[0] for e in ends], axis=-1)  # (g, k, 3)
    xy = np.stack([e[1] for e in ends], axis=-2)  # (g, k, 3, 2)
    ok = flags.sum(axis=-1) == 2
    first = np.argmax(flags, axis=-1)
    second = 2 - np.argmax(flags[..., ::-1], axis=-1)
    a = np.take_along_axis(xy, first[..., None, None], axis=-2)[..., 0, :]
    b = np.take_along_axis(xy, second[..., None, None], axis=-2)[..., 0, :]
    return ok, a, b


def convex_halfplanes(ring: np.ndarray) -> np.ndarray:
    """Half-planes of a convex polygon: (e, 3) rows (a, b, c), a x + b y + c >= 0 inside, (a, b)
    a unit vector, so a x + b y + c is the signed distance from the edge's line [same unit as
    ``ring``].

    Parameters
    ----------
    ring : (n, 2) float, the polygon's vertices counterclockwise, not closed
    """
    p, q = ring, np.roll(ring, -1, axis=0)
    d = q - p
    length = np.hypot(d[:, 0], d[:, 1])
    keep = length > 0
    p, d, length = p[keep], d[keep], length[keep]
    a, b = -d[:, 1] / length, d[:, 0] / length  # the inward normal of a counterclockwise ring
    return np.column_stack([a, b, -(a * p[:, 0] + b * p[:, 1])])


def points_in_convex(hp: np.ndarray, x, y, tol: float) -> np.ndarray:
    """Whether points lie in a convex polygon given by :func:`convex_halfplanes` (its edges, and
    ``tol`` beyond them, included). x, y: (m,) float; returns (m,) bool."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    inside = np.ones(x.shape, dtype=bool)
    for a, b, c in hp:  # over the polygon's edges, vectorised over points
        inside &= a * x + b * y + c >= -tol
    return inside


def boxes_vs_convex(hp: np.ndarray, extent, x0, x1, y0, y1, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Where axis-aligned boxes lie against a convex polygon (:func:`convex_halfplanes`).

    A box lies inside a convex polygon exactly when its four corners do; it is disjoint from it
    exactly when one of the two shapes' edge normals separates them (the separating axis theorem):
    the box's own axes against the polygon's extent, or an edge of the polygon with all four
    corners beyond it.

    Parameters
    ----------
    hp : (e, 3) float, :func:`convex_halfplanes`
    extent : (xmin, xmax, ymin, ymax) of the polygon
    x0, x1, y0, y1 : (m,) float, the boxes' bounds (x0 <= x1, y0 <= y1)
    tol : float, in the polygon's unit

    Returns
    -------
    inside : (m,) bool, all four corners within ``tol`` of the polygon; disjoint : (m,) bool, the
    box lies more than ``tol`` away from it along a separating axis
    """
    x0, x1, y0, y1 = (np.asarray(v, float) for v in (x0, x1, y0, y1))
    inside = np.ones(x0.shape, dtype=bool)
    apart = np.zeros(x0.shape, dtype=bool)
    for a, b, c in hp:  # the largest value over the box's corners, and the smallest
        hi = np.maximum(a * x0, a * x1) + np.maximum(b * y0, b * y1) + c
        lo = np.minimum(a * x0, a * x1) + np.minimum(b * y0, b * y1) + c
        inside &= lo >= -tol
        apart |= hi < -tol
    xmin, xmax, ymin, ymax = extent
    apart |= (x0 > xmax + tol) | (x1 < xmin - tol) | (y0 > ymax + tol) | (y1 < ymin - tol)  # the box's own axes
    return inside, apart
