"""The horizontal sight angle in plan: exact by construction for the windows and what frames them.

The horizontal plane at eye height cuts every triangle into a segment (or nothing). From a point,
a window's cut is seen under an azimuth interval, and an opaque segment casts an angular shadow.
A horizontal ray leaves the room through window ``k`` (the rule of
:meth:`~en17037cli.criteria.view.rays.ViewRays.through_windows`) when it meets the glazing before
any opaque face and the first opaque face beyond the glazing is not ``interior``. In plan the
glazing of window ``k`` lies on one line, and a ray crosses a line once, so along that ray:

- an opaque segment on the room's side of the line (or on it) lies before the glazing: it blocks,
  whatever its layer;
- an ``interior`` segment beyond the line lies beyond the glazing: it blocks (outer reveals,
  frames, sills);
- a ``landscape`` or ``ground`` segment beyond the line is the view.

So the directions that leave through window ``k`` are its intervals minus the union of those
shadows, and the sight angle is the measure of the union over the windows: 1D interval
operations, done for all points at once by sorting interval ends and counting +1 / -1 events
(:func:`sweep`). Only the opaque faces near the windows and points take part
(:func:`near_faces`): those within ``frame_depth_m`` of the box around the room's windows and
viewpoints. What lies further beyond the glazing is left to rays (the sight-angle engine
confirms every interval with a fan and bisects where a far ``interior`` face blocks).

Angles are computed in float64 from the scene's local coordinates; :func:`float_bound` is the
bound on their round-off.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import MIN_PLANE_DISTANCE_M
from en17037cli.criteria.view.wedge import in_wedge, may_shadow, window_cut
from en17037cli.geometry import cut_triangles, turn
from en17037cli.scene.model import INTERIOR, WINDOW, Scene

TWO_PI = 2.0 * np.pi
#: Unit round-off of float64 (half the machine epsilon), for :func:`float_bound`.
UNIT_ROUNDOFF = float(np.finfo(np.float64).eps) / 2
#: A face's projection on a window's plane lies inside its opening when it meets the outline
#: shrunk by this much [m]: reveals and frames on the outline's edge stay out.
INSIDE_OPENING_M = 1e-3
#: At most this many (plane, triangle) cuts at once: viewpoints at many heights go in blocks.
MAX_CUTS = 2_000_000
#: Rooms with more (point, face) pairs than this go in blocks of :data:`POINT_BLOCK` points, in
#: their grid order (rows of nearby points: the box of :func:`~.wedge.may_shadow` stays small).
MAX_PAIRS = 100_000
POINT_BLOCK = 64
#: Distances from the eye below this count as this in the round-off bound [m] (an eye on a face).
MIN_EYE_DISTANCE_M = 1e-6


def arcs(points: np.ndarray, a: np.ndarray, b: np.ndarray):
    """Azimuth interval under which each segment is seen from its point.

    Both ends are the azimuths of the segment's ends themselves (not a start plus a width), so two
    segments that share an end share that azimuth to the last bit.

    Parameters
    ----------
    points : (n, 2) float [m]; a, b : (n, 2) float [m], the segments' ends

    Returns
    -------
    start, end : (n,) float [rad] in [0, 2 pi), counter-clockwise from start to end (end < start:
        the interval crosses azimuth 0; end == start: seen edge-on)
    r : (n,) float [m], the distance from the point to the nearer end (for :func:`float_bound`)
    """
    e1, e2 = a - points, b - points
    t1, t2 = np.arctan2(e1[:, 1], e1[:, 0]), np.arctan2(e2[:, 1], e2[:, 0])
    delta = turn(t1, t2)  # exact for a short turn: an edge-on segment stays a (near-)empty interval
    start, end = np.where(delta >= 0, t1, t2) % TWO_PI, np.where(delta >= 0, t2, t1) % TWO_PI
    r = np.minimum(np.hypot(e1[:, 0], e1[:, 1]), np.hypot(e2[:, 0], e2[:, 1]))
    return np.where(start >= TWO_PI, 0.0, start), np.where(end >= TWO_PI, 0.0, end), r


def split_wrap(pt: np.ndarray, start: np.ndarray, end: np.ndarray, *extra: np.ndarray):
    """Intervals from start to end (counter-clockwise, :func:`arcs`) as pieces within [0, 2 pi]:
    one crossing azimuth 0 becomes two; empty ones are dropped.

    Returns
    -------
    pt, lo, hi and each of ``extra`` (per-interval arrays), repeated for the second pieces
    """
    keep = end != start
    pt, start, end = pt[keep], start[keep], end[keep]
    extra = tuple(x[keep] for x in extra)
    wrap = end < start
    lo = np.concatenate([start, np.zeros(int(wrap.sum()))])
    hi = np.concatenate([np.where(wrap, TWO_PI, end), end[wrap]])
    keep2 = hi > lo  # a piece [0, 0] of an interval ending at azimuth 0
    return tuple(x[keep2] for x in (np.concatenate([pt, pt[wrap]]), lo, hi)
                 + tuple(np.concatenate([x, x[wrap]]) for x in extra))


def sweep(pt: np.ndarray, lo: np.ndarray, hi: np.ndarray, kind: np.ndarray):
    """Per point, where some interval of kind 0 covers and none of kind 1 does: pieces [lo, hi].

    Sorts the interval ends by (point, angle) and counts +1 at each start and -1 at each end;
    every point's events add up to zero, so one running sum over all points keeps the counts
    exact (integers) and no loop over points is needed.

    Parameters
    ----------
    pt : (n,) int; lo, hi : (n,) float [rad] within [0, 2 pi]; kind : (n,) int, 0 (cover) or 1 (cut)

    Returns
    -------
    pt, lo, hi : the maximal pieces, sorted by point then angle
    """
    if len(pt) == 0:
        return np.zeros(0, np.int64), np.zeros(0), np.zeros(0)
    ept = np.concatenate([pt, pt])
    ang = np.concatenate([lo, hi])
    step = np.concatenate([np.ones(len(pt), np.int64), -np.ones(len(pt), np.int64)])
    knd = np.concatenate([kind, kind])
    order = np.lexsort((ang, ept))
    ept, ang, step, knd = ept[order], ang[order], step[order], knd[order]
    cover = np.cumsum(np.where(knd == 0, step, 0))
    cut = np.cumsum(np.where(knd == 1, step, 0))
    on = (cover > 0) & (cut == 0)  # the state after each event, up to the next one
    same = np.r_[ept[1:] == ept[:-1], False]
    on &= same
    # maximal runs of "on" between events of one point
    begin = on & ~np.r_[False, on[:-1]]
    stop = np.flatnonzero(~on & np.r_[False, on[:-1]])  # the event that ends a run
    b = np.flatnonzero(begin)
    out_pt, out_lo, out_hi = ept[b], ang[b], ang[stop]
    pos = out_hi > out_lo
    return out_pt[pos], out_lo[pos], out_hi[pos]


def union(pt: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Per point, the union of intervals [lo, hi] as maximal pieces sorted by point then angle."""
    return sweep(pt, lo, hi, np.zeros(len(pt), np.int64))


def window_arcs(rg: RoomGeometry, points: np.ndarray):
    """Azimuth intervals of each window triangle's cut at the points' heights, from points in front of its window.

    Returns
    -------
    pt, window : (q,) int; lo, hi : (q,) float [rad], pieces within [0, 2 pi]; r : (q,) float [m],
    distance to the nearer end
    """
    zs, gi = np.unique(points[:, 2], return_inverse=True)
    ok, a, b = cut_triangles(rg.triangles, zs)
    pi, ki = np.nonzero(ok[gi])
    gk = gi[pi]
    tw = rg.triangle_window[ki]
    n = rg.frame_array("n")[tw]
    front = np.einsum("ij,ij->i", rg.frame_array("origin")[tw] - points[pi], n) > MIN_PLANE_DISTANCE_M
    pi, ki, gk, tw = pi[front], ki[front], gk[front], tw[front]
    start, end, r = arcs(points[pi, :2], a[gk, ki], b[gk, ki])
    pt, lo, hi, win, r = split_wrap(pi, start, end, tw, r)
    return pt, win, lo, hi, r


#: Per scene (by id, checked by a weak reference): the opaque faces and their bounding boxes.
_FACE_BOXES: dict = {}


def face_boxes(scene: Scene):
    """The opaque faces of ``scene`` and their bounding boxes, computed once per scene.

    Returns
    -------
    faces : (f,) int; lo, hi : (3, f) float32 [m], rounded outwards (one contiguous row per axis)
    """
    import weakref

    hit = _FACE_BOXES.get(id(scene))
    if hit is not None and hit[0]() is scene:
        return hit[1]
    faces = np.flatnonzero(scene.layer != WINDOW)
    down = np.nextafter(scene.vertices.astype(np.float32), np.float32(-np.inf)).T.copy()  # (3, n), rounded outwards
    up = np.nextafter(scene.vertices.astype(np.float32), np.float32(np.inf)).T.copy()
    t = scene.triangles[faces].T  # (3, f)
    lo = np.minimum(np.minimum(down[:, t[0]], down[:, t[1]]), down[:, t[2]])
    hi = np.maximum(np.maximum(up[:, t[0]], up[:, t[1]]), up[:, t[2]])
    out = (faces, lo, hi)
    for key in [k for k, v in _FACE_BOXES.items() if v[0]() is None]:  # scenes gone
        del _FACE_BOXES[key]
    try:
        _FACE_BOXES[id(scene)] = (weakref.ref(scene), out)
    except TypeError:  # not weakly referable: not cached
        pass
    return out


def near_faces(scene: Scene, rg: RoomGeometry, points: np.ndarray, margin_m: float) -> np.ndarray:
    """Opaque faces that may bound the windows' intervals in plan: those whose bounding box meets
    the box around the room's windows and the points, widened by ``margin_m`` [m] horizontally,
    and the points' heights. Returns (f,) int face indices."""
    xy = np.concatenate([rg.triangles.reshape(-1, 3)[:, :2], points[:, :2]])
    lo = np.r_[xy.min(axis=0) - margin_m, points[:, 2].min()]
    hi = np.r_[xy.max(axis=0) + margin_m, points[:, 2].max()]
    faces, flo, fhi = face_boxes(scene)
    ok = flo[0] <= hi[0]
    for axis in range(3):  # six comparisons of contiguous rows
        if axis:
            ok &= flo[axis] <= hi[axis]
        ok &= fhi[axis] >= lo[axis]
    return faces[ok]


def opening_members(scene: Scene, rg: RoomGeometry, faces: np.ndarray, depth_m: float) -> np.ndarray:
    """Which of ``faces`` are members inside an opening (mullions, transoms, glazing bars): within
    ``depth_m`` [m] of a window's plane, with a projection on it that meets the window's outline
    shrunk by :data:`INSIDE_OPENING_M` (reveals and frames on the outline's edge do not).
    Returns (f,) bool."""
    import shapely

    out = np.zeros(len(faces), bool)
    if len(faces) == 0:
        return out
    corners = scene.vertices[scene.triangles[faces]]  # (f, 3, 3)
    for f in rg.frames:  # one pass per window
        rel = corners - f.origin
        s, x, y = rel @ f.n, rel @ f.u, rel @ f.v
        near = np.all(np.abs(s) <= depth_m, axis=1)
        if not near.any():
            continue
        inner = shapely.buffer(f._outline_index()[0], -INSIDE_OPENING_M)
        idx = np.flatnonzero(near)
        ring = np.stack([x[idx], y[idx]], axis=-1)
        lines = shapely.linestrings(np.concatenate([ring, ring[:, :1]], axis=1))
        out[idx] |= shapely.intersects(inner, lines) | shapely.intersects_xy(inner, ring[:, :, 0].mean(1), ring[:, :, 1].mean(1))
    return out


def shadow_arcs(rg: RoomGeometry, points: np.ndarray, tri: np.ndarray, layer: np.ndarray):
    """Angular shadows of opaque triangles that block the view through each window, from each point.

    For window ``k`` the cut of each triangle is split by the line of the window's plane at the
    point's height: the part on the room's side (or on the line) blocks whatever its layer, the
    part beyond blocks when the face is ``interior``.

    Parameters
    ----------
    tri : (f, 3, 3) float [m]; layer : (f,) int layer codes

    Returns
    -------
    pt, window : (q,) int; lo, hi : (q,) float [rad], pieces within [0, 2 pi]; r : (q,) float [m],
    distance to the nearer end
    """
    out: tuple[list, ...] = [], [], [], [], []
    zs, gi = np.unique(points[:, 2], return_inverse=True)
    ok, a, b = cut_triangles(tri, zs)
    for k, f in enumerate(rg.frames):  # a loop over the room's windows, vectorised over points and faces
        cut = window_cut(rg, k, zs)  # only the pairs that may shadow this window (:mod:`.wedge`)
        pi, ki = np.nonzero((ok & may_shadow(rg, k, zs, points, a, b, cut))[gi])
        pa, pb = a[gi[pi], ki], b[gi[pi], ki]
        keep = in_wedge(rg, k, cut, gi[pi], points[pi], pa, pb)
        pi, ki, pa, pb = pi[keep], ki[keep], pa[keep], pb[keep]
        z = points[pi, 2]
        # signed distance of each end from the window's plane (outwards positive)
        sa, sb = ((e[:, 0] - f.origin[0]) * f.n[0] + (e[:, 1] - f.origin[1]) * f.n[1] + (z - f.origin[2]) * f.n[2]
                  for e in (pa, pb))
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.clip(sa / (sa - sb), 0.0, 1.0)
        m = pa + t[:, None] * (pb - pa)  # where the segment crosses the line (used only where it does)
        in_a, in_b = sa <= 0, sb <= 0
        # the part on the room's side: whole, none, or from the inner end to the crossing
        inner_ok = in_a | in_b
        ia = np.where(in_a[:, None], pa, m)
        ib = np.where(in_b[:, None], pb, m)
        outer_ok = (~in_a | ~in_b) & (layer[ki] == INTERIOR)
        oa = np.where(~in_a[:, None], pa, m)
        ob = np.where(~in_b[:, None], pb, m)
        for sel, ea, eb in ((inner_ok, ia, ib), (outer_ok, oa, ob)):
            idx = np.flatnonzero(sel)
            start, end, r = arcs(points[pi[idx], :2], ea[idx], eb[idx])
            p_, lo, hi, w_, r_ = split_wrap(pi[idx], start, end, np.full(len(idx), k), r)
            for acc, x in zip(out, (p_, w_, lo, hi, r_)):
                acc.append(x)
    if not out[0]:
        return tuple(np.zeros(0, t) for t in (np.int64, np.int64, float, float, float))
    return tuple(np.concatenate(x) for x in out)


def visible_intervals(scene: Scene, rg: RoomGeometry, points: np.ndarray, depth_m: float, members_block: bool = True,
                      faces: np.ndarray | None = None):
    """The azimuths from each point that leave through a window in plan, as maximal pieces.

    Parameters
    ----------
    points : (p, 3) float [m], local frame
    depth_m : float [m], ``view.frame_depth_m``: how far around the windows and points opaque faces
        take part, and how far from a window's plane a member inside its opening may lie
    members_block : bool, ``view.mullions_block``: False leaves members inside an opening
        (:func:`opening_members`) out
    faces : the opaque faces that take part (:func:`near_faces` of all the points), given to the
        blocks of points a large room is split into, so that plan and rays agree on them

    Returns
    -------
    pt : (q,) int; lo, hi : (q,) float [rad] within [0, 2 pi], sorted by point then angle
    faces : (f,) int, the opaque faces that took part, members left out included (rays that meet
        them are left to plan)
    bound : (p,) float [rad], :func:`float_bound` of each point's total
    """
    p = len(points)
    faces = near_faces(scene, rg, points, depth_m) if faces is None else faces
    heights = len(np.unique(points[:, 2]))
    step = p
    if heights > 1 and heights * max(len(faces), len(rg.triangles)) > MAX_CUTS:  # viewpoints at many heights: blocks
        step = max(1, MAX_CUTS // max(len(faces), len(rg.triangles), 1))
    if p * len(faces) > MAX_PAIRS:  # a large room: blocks of nearby points (:mod:`.wedge` keeps their pairs few)
        step = min(step, POINT_BLOCK)
    if step < p:
        parts = [visible_intervals(scene, rg, points[a:a + step], depth_m, members_block, faces) for a in range(0, p, step)]
        return (np.concatenate([x[0] + a for x, a in zip(parts, range(0, p, step))]),
                *(np.concatenate([x[i] for x in parts]) for i in (1, 2)), faces, np.concatenate([x[4] for x in parts]))
    wpt, wwin, wlo, whi, wr = window_arcs(rg, points)
    cutting = faces if members_block else faces[~opening_members(scene, rg, faces, depth_m)]
    tri = scene.vertices[scene.triangles[cutting]]
    spt, swin, slo, shi, sr = shadow_arcs(rg, points, tri, scene.layer[cutting])
    pieces = []
    for k in range(len(rg.frames)):  # a loop over the room's windows
        w, s = wwin == k, swin == k
        pieces.append(sweep(np.concatenate([wpt[w], spt[s]]), np.concatenate([wlo[w], slo[s]]),
                            np.concatenate([whi[w], shi[s]]), np.r_[np.zeros(w.sum(), np.int64), np.ones(s.sum(), np.int64)]))
    pt, lo, hi = union(*(np.concatenate(x) for x in zip(*pieces)))
    r = np.full(p, np.inf)
    np.minimum.at(r, np.concatenate([wpt, spt]), np.concatenate([wr, sr]))
    scale = max(float(np.abs(points[:, :2]).max(initial=0.0)), float(np.abs(tri[..., :2]).max(initial=0.0)),
                float(np.abs(rg.triangles[..., :2]).max(initial=0.0)))
    return pt, lo, hi, faces, float_bound(np.bincount(pt, minlength=p), r, scale)


def float_bound(n: np.ndarray, r: np.ndarray, scale: float) -> np.ndarray:
    """Bound on the round-off of a point's total angle [rad].

    Each end of a piece is the azimuth of a cut point v_lo + t (v_hi - v_lo) of an edge: t carries
    3 u of relative error, the difference (at most 2 s, s = ``scale`` [m] the largest coordinate)
    1 u, the product and the sum 2 more roundings, so the point is off by at most 10 u s, and its
    offset from the eye by 11 u s; that turns the azimuth by at most 11 u s / r, r the distance
    from the eye to the nearest end of any interval. atan2, the wrap to [0, 2 pi) and the
    difference hi - lo add at most 4 u 2 pi. Summed over both ends of the point's n pieces, with a
    margin: 2 n (16 u s / r + 8 u pi), u the unit round-off of float64 (1.1e-16); about 2e-13 rad
    for a room 20 m across seen from 0.5 m. Where a window's line splits a segment, the split
    point is as exact unless the segment crosses that line at a grazing angle: an ``interior``
    face blocks on both sides, so only a ``landscape`` or ``ground`` face lying almost in a
    window's plane, across it, is outside the bound.

    Parameters
    ----------
    n : (p,) int, pieces per point; r : (p,) float [m]; scale : float [m]
    """
    with np.errstate(divide="ignore"):
        per_end = 16 * UNIT_ROUNDOFF * scale / np.where(np.isfinite(r), np.maximum(r, MIN_EYE_DISTANCE_M), 1.0) \
            + 8 * UNIT_ROUNDOFF * np.pi
    return 2 * n * per_end
