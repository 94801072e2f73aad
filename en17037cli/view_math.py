"""Maths behind the view engine: viewpoint grids, window frames, clipped solid angles, weighted statistics.

No ray is traced here; :mod:`en17037cli.view` calls these functions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.geometry import triangle_solid_angle, window_axes


def grid_points(utilised, spacing_m: float) -> np.ndarray:
    """Grid of points over a polygon, aligned with its minimum-area bounding rectangle.

    The grid is centred on the rectangle and symmetric, so rotating or mirroring the model
    moves the grid with it. If no grid point falls inside (spacing larger than the area), the
    polygon's centroid (or a point surely inside it) is used.

    Parameters
    ----------
    utilised : shapely Polygon, local xy [m]
    spacing_m : float [m]

    Returns
    -------
    (n, 2) float [m]
    """
    import shapely

    if utilised.is_empty or utilised.area <= 0:
        return np.zeros((0, 2))
    rect = np.asarray(shapely.minimum_rotated_rectangle(utilised).exterior.coords)[:4]
    centre = rect.mean(axis=0)
    e1, e2 = rect[1] - rect[0], rect[2] - rect[1]
    l1, l2 = np.linalg.norm(e1), np.linalg.norm(e2)
    e1, e2 = e1 / max(l1, 1e-12), e2 / max(l2, 1e-12)
    n1, n2 = int(np.floor(l1 / spacing_m + 1e-9)) + 1, int(np.floor(l2 / spacing_m + 1e-9)) + 1
    a = (np.arange(n1) - (n1 - 1) / 2) * spacing_m
    b = (np.arange(n2) - (n2 - 1) / 2) * spacing_m
    A, B = np.meshgrid(a, b, indexing="ij")
    pts = centre + A.reshape(-1, 1) * e1 + B.reshape(-1, 1) * e2
    inside = shapely.contains_xy(utilised.buffer(1e-9), pts[:, 0], pts[:, 1])
    pts = pts[inside]
    if len(pts) == 0:
        c = utilised.centroid
        p = c if utilised.contains(c) else utilised.representative_point()
        pts = np.array([[p.x, p.y]])
    order = np.lexsort((np.round(pts[:, 1], 9), np.round(pts[:, 0], 9)))
    return pts[order]


def weighted_statistic(values: np.ndarray, weights: np.ndarray, statistic: str):
    """Weighted statistic per row, ignoring zero weights; +inf values are allowed.

    ``median`` and ``pNN`` are lower weighted percentiles: the smallest value v such that the
    weight of values <= v reaches the fraction. ``min`` is the smallest value with positive weight.

    Parameters
    ----------
    values : (p, k) float [m] (NaN allowed where the weight is 0)
    weights : (p, k) float >= 0 (e.g. [deg] or [sr])
    statistic : str, ``median`` | ``min`` | ``mean`` | ``pNN``

    Returns
    -------
    value : (p,) float, NaN where a row has no weight
    gap : (p,) float, largest gap from the value to its neighbouring finite samples (a
        resolution estimate), 0 where the neighbours are equal
    """
    v = np.where(weights > 0, values, np.nan)
    w = np.where(weights > 0, weights, 0.0)
    total = w.sum(axis=1)
    empty = total <= 0
    if statistic == "mean":
        with np.errstate(invalid="ignore", divide="ignore"):
            vv = np.where(w > 0, v, 0.0)
            has_inf = np.any(np.isinf(vv) & (w > 0), axis=1)
            mean = np.where(has_inf, np.inf, (np.where(np.isinf(vv), 0, vv) * w).sum(axis=1) / np.where(empty, 1, total))
        return np.where(empty, np.nan, mean), np.zeros(len(v))
    q = 0.0 if statistic == "min" else (0.5 if statistic == "median" else int(statistic[1:]) / 100.0)
    order = np.argsort(np.where(np.isnan(v), np.inf, v), axis=1, kind="stable")
    vs = np.take_along_axis(v, order, axis=1)
    ws = np.take_along_axis(w, order, axis=1)
    cum = np.cumsum(ws, axis=1)
    target = q * total
    reach = (cum >= target[:, None] * (1 - 1e-12)) & (ws > 0)
    idx = np.argmax(reach, axis=1)
    rows = np.arange(len(v))
    value = np.where(empty, np.nan, vs[rows, idx])
    # neighbouring distinct samples with weight, for a resolution estimate
    pos = np.where(ws > 0, np.arange(vs.shape[1])[None, :], -1)
    prev_idx = np.max(np.where(pos < idx[:, None], pos, -1), axis=1)
    nxt = np.where((pos > idx[:, None]) & (pos >= 0), pos, vs.shape[1])
    next_idx = np.min(nxt, axis=1)
    with np.errstate(invalid="ignore"):
        lo = np.where(prev_idx >= 0, value - vs[rows, np.maximum(prev_idx, 0)], 0.0)
        hi = np.where(next_idx < vs.shape[1], vs[rows, np.minimum(next_idx, vs.shape[1] - 1)] - value, 0.0)
    lo = np.where(np.isfinite(lo), lo, 0.0)
    hi = np.where(np.isfinite(hi), hi, 0.0)
    return value, np.where(empty, np.nan, np.maximum(lo, hi))


@dataclass
class WindowFrame:
    """A planar window in its own 2D frame, for sampling it from viewpoints.

    ``u`` and ``v`` span the glazing plane: ``u`` runs along a side of the window's minimum-area
    bounding rectangle (the side nearest the horizontal), so the frame moves with the model and a
    rectangular window is ``[xmin, xmax] x [ymin, ymax]`` exactly. ``n`` is the outward normal.

    tri2 : (k, 3, 2) float [m], the window's triangles in (u, v) coordinates about ``origin``
    """

    index: int
    name: str
    origin: np.ndarray
    u: np.ndarray
    v: np.ndarray
    n: np.ndarray
    tri2: np.ndarray
    xmin: float
    xmax: float
    ymin: float
    ymax: float
    is_rectangle: bool
    face_ids: np.ndarray
    #: (e, 3) float [m]: vertices (x, y, s) of the window's frame, s along the outward normal
    frame_xys: np.ndarray = None


def window_frame(window, index: int) -> WindowFrame:
    """The :class:`WindowFrame` of a :class:`~en17037cli.scene.Window` (triangles projected on its mean plane)."""
    import shapely

    n = np.asarray(window.normal, float)
    origin = window.centroid
    a, up = window_axes(n)
    rel = window.triangles - origin
    flat = np.stack([rel @ a, rel @ up], axis=-1)
    poly = shapely.union_all([shapely.Polygon(t) for t in flat if _area2(t) > 0])
    rect = np.asarray(shapely.minimum_rotated_rectangle(poly).exterior.coords)[:4]
    sides = [rect[1] - rect[0], rect[2] - rect[1]]
    phis = [np.arctan2(s[1], s[0]) for s in sides]
    phis = [(ph + np.pi / 2) % np.pi - np.pi / 2 for ph in phis]  # a side direction, folded to [-90, 90) deg
    phi = min(phis, key=abs)
    if abs(phi) < 1e-12:
        phi = 0.0
    u = np.cos(phi) * a + np.sin(phi) * up
    v = -np.sin(phi) * a + np.cos(phi) * up
    tri2 = np.stack([rel @ u, rel @ v], axis=-1)
    xmin, xmax = float(tri2[..., 0].min()), float(tri2[..., 0].max())
    ymin, ymax = float(tri2[..., 1].min()), float(tri2[..., 1].max())
    box = (xmax - xmin) * (ymax - ymin)
    return WindowFrame(index, window.name, origin, u, v, n, tri2, xmin, xmax, ymin, ymax,
                       bool(abs(poly.area - box) <= 1e-9 * box), np.asarray(window.face_ids))


def frame_vertices(frame: WindowFrame, vertices: np.ndarray, triangles: np.ndarray, depth_m: float) -> np.ndarray:
    """Vertices of the opaque faces that frame a window: mullions, transoms, frames, reveals.

    A face is part of the frame when all its vertices lie within ``depth_m`` of the glazing
    plane and its extent over the plane overlaps the window's. The view engine draws a grid
    line through the image of each of these vertices.

    Parameters
    ----------
    frame : WindowFrame
    vertices : (n, 3) float [m], local frame
    triangles : (m, 3) int, the opaque faces
    depth_m : float [m]

    Returns
    -------
    (e, 3) float [m], unique (x, y, s) in the window's (u, v, n) frame
    """
    s_v = (vertices - frame.origin) @ frame.n  # per vertex first: no (m, 3, 3) copy of a large scene
    tri = triangles[np.all(np.abs(s_v[triangles]) <= depth_m, axis=1)]
    rel = vertices[tri] - frame.origin
    s, x, y = rel @ frame.n, rel @ frame.u, rel @ frame.v
    over = (x.min(axis=1) < frame.xmax) & (x.max(axis=1) > frame.xmin) & (y.min(axis=1) < frame.ymax) & (y.max(axis=1) > frame.ymin)
    xys = np.stack([x[over], y[over], s[over]], axis=-1).reshape(-1, 3)
    return np.unique(np.round(xys, 9), axis=0)


def _area2(t: np.ndarray) -> float:
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


def _clip_halfplane(poly: np.ndarray, count: np.ndarray, axis: int, bound: np.ndarray, sign: float):
    """Sutherland-Hodgman step: keep the part of each convex polygon where sign * (x[axis] - bound) >= 0."""
    m, k, _ = poly.shape
    out = np.zeros((m, k + 1, 2))
    n_out = np.zeros(m, dtype=int)
    rows = np.arange(m)
    s = sign * (poly[..., axis] - bound[:, None])
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
        poly, count = _clip_halfplane(poly, count, axis, rect[:, col], sign)
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
