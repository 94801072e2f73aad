"""Which opaque segments may shadow a window in plan: the cheap tests that keep the exact interval
arithmetic of :mod:`.plan` to the pairs that can matter.

From a point in front of a window, the directions that reach its glazing at eye height form a
wedge less than pi wide, from the point over the window's cut (the segment where the eye-height
plane cuts its plane). An opaque segment wholly outside that wedge casts its shadow outside the
window's interval, so leaving it out of :func:`~en17037cli.criteria.view.plan.sweep` changes
nothing. Two tests, both conservative (a segment on an edge of the wedge, such as a jamb's line
through the eye, always stays in):

- per face (:func:`may_shadow`): a segment wholly on the room's side of the window's plane lies
  between the point and the glazing only inside the box around the points and the window's cut;
  one with any part beyond the plane is kept (outer reveals, frames, a wing in front);
- per (point, face) pair (:func:`in_wedge`): a segment wholly beyond one of the wedge's two edges,
  or wholly behind the point, is left out.

Both cost a few products per face or pair where the shadows' azimuths, wraps and sorting cost far
more: in a 610 m² open office with 20 windows (Revit's Office_A) most (point, face) pairs lie
beside or behind the point.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import MIN_PLANE_DISTANCE_M
from en17037cli.geometry import convex_halfplanes, cut_triangles

#: A segment is outside a wedge when it lies outside it by more than this angle [rad]: far above
#: the round-off of the azimuths (:func:`~en17037cli.criteria.view.plan.float_bound`, about 1e-13 rad).
WEDGE_MARGIN_RAD = 1e-9
#: The box of :func:`may_shadow` is widened by this much [m] (and 1e-9 of its coordinates).
BOX_MARGIN_M = 1e-6


def window_cut(rg: RoomGeometry, k: int, zs: np.ndarray):
    """The two ends of window ``k``'s cut at each height (the extremes along the window's width).

    Returns
    -------
    e1, e2 : (h, 2) float [m]; has : (h,) bool, the window is cut at that height
    """
    f = rg.frames[k]
    ok, wa, wb = cut_triangles(rg.triangles[rg.triangle_window == k], zs)
    ends = np.concatenate([wa, wb], axis=1)  # (h, 2t, 2)
    okk = np.concatenate([ok, ok], axis=1)
    along = ends @ np.asarray(f.u[:2], float)
    rows = np.arange(len(zs))
    e1 = ends[rows, np.argmin(np.where(okk, along, np.inf), axis=1)]
    e2 = ends[rows, np.argmax(np.where(okk, along, -np.inf), axis=1)]
    return e1, e2, okk.any(axis=1)


def signed_distance(frame, xy: np.ndarray, z) -> np.ndarray:
    """Signed distance [m] of points (xy at height z) from a window's plane, outwards positive: the
    expression :func:`~en17037cli.criteria.view.plan.shadow_arcs` splits segments with."""
    return (xy[..., 0] - frame.origin[0]) * frame.n[0] + (xy[..., 1] - frame.origin[1]) * frame.n[1] + (z - frame.origin[2]) * frame.n[2]


def may_shadow(rg: RoomGeometry, k: int, zs: np.ndarray, points: np.ndarray, a: np.ndarray, b: np.ndarray,
               cut) -> np.ndarray:
    """Per height and face, whether the face's segment may shadow window ``k`` from some point:
    it has a part beyond the window's plane, or its box meets the box around the points and the
    window's cut (widened by :data:`BOX_MARGIN_M`).

    Parameters
    ----------
    zs : (h,) float [m]; points : (p, 3) float [m]; a, b : (h, f, 2) float [m], the faces' cuts;
    cut : :func:`window_cut` of window ``k``

    Returns
    -------
    (h, f) bool
    """
    f = rg.frames[k]
    e1, e2, has = cut
    z = np.asarray(zs, float)[:, None]
    beyond = (signed_distance(f, a, z) > 0) | (signed_distance(f, b, z) > 0)
    xy = np.concatenate([points[:, :2], e1[has], e2[has]])
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = BOX_MARGIN_M + 1e-9 * float(np.abs(xy).max(initial=0.0))
    lo, hi = lo - pad, hi + pad
    meets = ((np.minimum(a[..., 0], b[..., 0]) <= hi[0]) & (np.maximum(a[..., 0], b[..., 0]) >= lo[0])
             & (np.minimum(a[..., 1], b[..., 1]) <= hi[1]) & (np.maximum(a[..., 1], b[..., 1]) >= lo[1]))
    meets &= _meets_hull(xy, a, b, pad)
    return has[:, None] & (beyond | meets)


def _meets_hull(xy: np.ndarray, a: np.ndarray, b: np.ndarray, pad: float) -> np.ndarray:
    """Whether segments (a, b) (..., 2) [m] meet the convex hull of points ``xy`` (n, 2) [m], widened
    by ``pad`` [m]: False only where a separating axis says they are apart (an edge of the hull with
    both ends beyond it, or the segment's line with the whole hull beyond it). The region from a
    room's viewpoints to a window's cut lies in that hull; its box, the test before this one, is
    far larger for a window seen obliquely across a large room (Office_A: 95 % of the (point, face)
    pairs the box let through were then left out one by one by :func:`in_wedge`)."""
    import shapely

    hull = shapely.convex_hull(shapely.multipoints(xy))
    if hull.geom_type != "Polygon":  # the points and the cut on a line: the box has said all
        return np.ones(a.shape[:-1], dtype=bool)
    ring = np.asarray(shapely.orient_polygons(hull).exterior.coords)[:-1]
    hp = convex_halfplanes(ring)
    apart = np.zeros(a.shape[:-1], dtype=bool)
    for u, v, c in hp:  # the hull's edges: both ends of a segment beyond one
        apart |= (u * a[..., 0] + v * a[..., 1] + c < -pad) & (u * b[..., 0] + v * b[..., 1] + c < -pad)
    d = b - a  # the segment's line: every vertex of the hull on one side of it, clear of it
    length = np.hypot(d[..., 0], d[..., 1])
    side = d[..., 0, None] * (ring[:, 1] - a[..., 1, None]) - d[..., 1, None] * (ring[:, 0] - a[..., 0, None])
    margin = pad * length[..., None]
    apart |= np.all(side > margin, axis=-1) | np.all(side < -margin, axis=-1)
    return ~apart


def in_wedge(rg: RoomGeometry, k: int, cut, g: np.ndarray, points: np.ndarray, pa: np.ndarray,
             pb: np.ndarray) -> np.ndarray:
    """Per (point, segment) pair, whether the segment meets the wedge from the point over window
    ``k``'s cut at the point's height, widened by :data:`WEDGE_MARGIN_RAD`; False for a point not in
    front of the window (it has no interval there).

    Parameters
    ----------
    cut : :func:`window_cut` of window ``k``; g : (q,) int, each pair's height index
    points : (q, 3) float [m]; pa, pb : (q, 2) float [m], the segments' ends

    Returns
    -------
    (q,) bool, False only where the segment cannot shadow window ``k`` from its point
    """
    f = rg.frames[k]
    e1, e2, has = cut
    front = np.einsum("ij,j->i", f.origin[None, :] - points, f.n) > MIN_PLANE_DISTANCE_M
    p = points[:, :2]
    u, v, A, B = e1[g] - p, e2[g] - p, pa - p, pb - p

    def cross(x, y):
        return x[:, 0] * y[:, 1] - x[:, 1] * y[:, 0]

    def dot(x, y):
        return x[:, 0] * y[:, 0] + x[:, 1] * y[:, 1]

    nu, nv = np.hypot(u[:, 0], u[:, 1]), np.hypot(v[:, 0], v[:, 1])
    na, nb = np.hypot(A[:, 0], A[:, 1]), np.hypot(B[:, 0], B[:, 1])
    turn_uv = cross(u, v)
    sign = np.sign(turn_uv)  # v lies on this side of u, u on the other side of v
    eps = WEDGE_MARGIN_RAD
    beyond_u = (sign * cross(u, A) < -eps * nu * na) & (sign * cross(u, B) < -eps * nu * nb)
    beyond_v = (sign * cross(v, A) > eps * nv * na) & (sign * cross(v, B) > eps * nv * nb)
    m = np.stack([u[:, 1] - v[:, 1], v[:, 0] - u[:, 0]], axis=1)  # across the cut ...
    m *= np.where(dot(m, u) >= 0, 1.0, -1.0)[:, None]  # ... towards it from the point
    nm = np.hypot(m[:, 0], m[:, 1])
    behind = (dot(m, A) < -eps * nm * na) & (dot(m, B) < -eps * nm * nb)
    wide = turn_uv != 0  # a cut of no width from the point: nothing is left out
    return has[g] & front & ~(wide & (beyond_u | beyond_v | behind))
