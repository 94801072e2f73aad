"""Horizontal sight angle (EN 17037 clause 5.2): the angle of the horizontal fan at eye height that
leaves the room through its windows (the total over all its intervals).

``view.sight_angle_method``:

- ``plan`` (default, :func:`horizontal`): the intervals come from plan geometry
  (:mod:`en17037cli.criteria.view.plan`), exact by construction for the windows, their frames,
  mullions and reveals and everything between the viewpoints and the glazing; a fan of rays over
  those intervals only confirms what lies further beyond the glazing (a far ``interior`` face is
  bisected as below) and samples the outside distance. Error: the round-off bound of
  :func:`~en17037cli.criteria.view.plan.float_bound`, plus the brackets of far transitions.
- ``fan`` (:func:`horizontal_fan`): a fan over the azimuths in which the windows lie
  (:func:`fan_intervals`), ``horizontal_resolution_deg`` apart; every change between "leaves
  through a window" and "blocked" is located by bisection to ``angle_tolerance_deg``. Error
  estimate: the remaining bracket widths plus the end insets, summed; a gap narrower than the fan
  can fall between two rays and is not in it.
"""
from __future__ import annotations

import numpy as np

from en17037cli.bisection import bisect_transitions
from en17037cli.criteria.view.distance import horizontal_distance
from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import MIN_PLANE_DISTANCE_M
from en17037cli.criteria.view.plan import cut_triangles
from en17037cli.criteria.view.rays import BLOCKED, ViewRays
from en17037cli.criteria.view.results import SightAngles
from en17037cli.geometry import turn
from en17037cli.project.settings import ViewSettings


def fan_intervals(rg: RoomGeometry, points: np.ndarray):
    """Azimuth intervals in which horizontal rays from each point meet a window of the room, merged.

    Each window triangle is cut by the horizontal plane through the point (half-open rule, so a
    vertex on the plane is not counted twice); the cut is seen under an azimuth interval, shorter
    than 180 degrees, from points in front of the window. Intervals are merged per point;
    intervals crossing azimuth 2 pi are split there.

    Returns
    -------
    pt : (q,) int; start : (q,) float [rad] in [0, 2 pi); width : (q,) float [rad]
    """
    tri, tw = rg.triangles, rg.triangle_window
    two, a, b = cut_triangles(tri, points[:, 2])  # (p, k): the plane through each eye cuts each window triangle
    pi, ki = np.nonzero(two)
    e1 = a[pi, ki] - points[pi, :2]
    e2 = b[pi, ki] - points[pi, :2]
    n = rg.frame_array("n")[tw[ki]]
    front = np.einsum("ij,ij->i", rg.frame_array("origin")[tw[ki]] - points[pi], n) > MIN_PLANE_DISTANCE_M
    pi, e1, e2 = pi[front], e1[front], e2[front]
    t1, t2 = np.arctan2(e1[:, 1], e1[:, 0]), np.arctan2(e2[:, 1], e2[:, 0])
    delta = turn(t1, t2)
    start = np.where(delta >= 0, t1, t2) % (2 * np.pi)
    width = np.abs(delta)
    keep = width > 0
    pi, start, width = pi[keep], start[keep], width[keep]
    over = start + width - 2 * np.pi
    wrap = over > 0
    pi = np.concatenate([pi, pi[wrap]])
    start, width = np.concatenate([start, np.zeros(wrap.sum())]), np.concatenate([np.where(wrap, 2 * np.pi - start, width), over[wrap]])
    # merge per point: sort by (point, start), cumulative maximum of the ends in 8-rad lanes per point
    key = pi * 8.0 + start
    order = np.argsort(key, kind="stable")
    key, end = key[order], key[order] + width[order]
    if len(key) == 0:  # no window at this eye height from any point: sight angle 0
        return np.zeros(0, np.int64), np.zeros(0), np.zeros(0)
    run_end = np.maximum.accumulate(end)
    new = np.r_[True, key[1:] > run_end[:-1] + 1e-12]
    g0 = np.flatnonzero(new)
    g_end = np.maximum.reduceat(end, g0)
    pt = pi[order][g0]
    return pt, key[g0] - pt * 8.0, g_end - key[g0]


#: An eye this close to the height of a window's sill or head looks along that edge: its fan is
#: taken this far inside the window instead [m], so the result is the limit from inside.
EDGE_HEIGHT_M = 1e-6


def fan_heights(rg: RoomGeometry, points: np.ndarray) -> np.ndarray:
    """Points with the eye moved :data:`EDGE_HEIGHT_M` inside a window whose sill or head lies within that distance."""
    out = points.copy()
    for k in range(len(rg.frames)):  # one pass per window, vectorised over points
        z = rg.triangles[rg.triangle_window == k][..., 2]
        lo, hi = z.min(), z.max()
        if hi - lo <= 2 * EDGE_HEIGHT_M:
            continue
        out[np.abs(out[:, 2] - lo) <= EDGE_HEIGHT_M, 2] = lo + EDGE_HEIGHT_M
        out[np.abs(out[:, 2] - hi) <= EDGE_HEIGHT_M, 2] = hi - EDGE_HEIGHT_M
    return out


def horizontal(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings) -> SightAngles:
    """Horizontal sight angle and horizontal outside distance from each point, by
    ``settings.sight_angle_method`` (:func:`horizontal_plan` or :func:`horizontal_fan`)."""
    if settings.sight_angle_method == "fan":
        return horizontal_fan(view_rays, rg, points, settings)
    return horizontal_plan(view_rays, rg, points, settings)


def horizontal_fan(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings) -> SightAngles:
    """Horizontal sight angle and horizontal outside distance from each point, by a fan of rays.

    Rays are traced only towards the windows: over each merged azimuth interval of
    :func:`fan_intervals`, at most ``horizontal_resolution_deg`` apart, the two end rays moved
    half of ``angle_tolerance_deg`` inwards; every change between "leaves" and "blocked" is then
    located by bisection to ``angle_tolerance_deg``. An eye at a window's sill or head height is
    moved :data:`EDGE_HEIGHT_M` inside the window (:func:`fan_heights`).

    Parameters
    ----------
    points : (p, 3) float [m], local frame

    Returns
    -------
    SightAngles, per point; with the horizontal outside distance
    (:func:`~en17037cli.criteria.view.distance.horizontal_distance`) for that distance method
    """
    p = len(points)
    res = np.radians(settings.horizontal_resolution_deg)
    tol = np.radians(settings.angle_tolerance_deg)
    points = fan_heights(rg, points)
    ipt, start, width = fan_intervals(rg, points)
    ang, iv, base, n, inset = fan_samples(ipt, start, width, res, tol)
    pidx = ipt[iv]

    def trace(pt_idx, angles):
        d = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(len(angles))])
        cls, wface, oface, odist, gdist = view_rays.through_windows(rg.group, points[pt_idx], d)
        return cls != BLOCKED, wface, oface, odist, gdist, d

    leave, wface, oface, odist, gdist, dirs = trace(pidx, ang)
    # consecutive samples of one interval
    a = np.flatnonzero(iv[:-1] == iv[1:]) if len(iv) > 1 else np.zeros(0, int)
    b = a + 1
    seg = ang[b] - ang[a]
    both = leave[a] & leave[b]
    trans = np.flatnonzero(leave[a] != leave[b])
    lo, hi = ang[a][trans], ang[b][trans]
    s_lo = leave[a][trans]
    tp = pidx[a][trans]
    n_iter = int(np.ceil(np.log2(res / tol))) if tol < res else 0
    lo, hi = bisect_transitions(lambda key, x: trace(key, x)[0], tp, lo, hi, s_lo, iterations=n_iter)
    x = 0.5 * (lo + hi)
    part = np.where(s_lo, x - ang[a][trans], ang[b][trans] - x)  # leaving length inside the segment [rad]
    # angular length owned by each sample (for the distance statistic): half of each fully
    # leaving neighbour segment, the leaving part of a transition, the end insets
    weight = np.zeros(len(ang))
    np.add.at(weight, a, 0.5 * seg * both)
    np.add.at(weight, b, 0.5 * seg * both)
    np.add.at(weight, np.where(s_lo, a[trans], b[trans]), part)
    ends = np.concatenate([base, base + n]) if len(base) else np.zeros(0, int)
    weight[ends] += np.concatenate([inset, inset]) * leave[ends]
    angle = np.bincount(pidx, weight, p)
    dist = gap = None
    if settings.distance_method == "horizontal":
        dist, gap = horizontal_distance(view_rays, rg, points, pidx, dirs, leave, (wface, oface, odist, gdist), weight, p,
                                        settings.distance_statistic)
    return SightAngles(
        angle_deg=np.degrees(angle),
        # full bracket widths plus the end insets: a bound even where float32 rays blur the bracket ends
        angle_err_deg=np.degrees(np.bincount(tp, hi - lo, p) + np.bincount(ipt, 2 * inset, p)),
        transitions=np.bincount(tp, minlength=p),
        rays=np.bincount(pidx, minlength=p) + n_iter * np.bincount(tp, minlength=p),
        distance_m=dist, distance_gap_m=gap)


def fan_samples(ipt: np.ndarray, start: np.ndarray, width: np.ndarray, res: float, tol: float):
    """Samples over intervals, at most ``res`` [rad] apart, the two end samples moved
    min(tol / 2, width / 4) [rad] inwards (off the edges that bound them).

    Returns
    -------
    ang : (s,) float [rad]; iv : (s,) int, the interval of each sample; base, n : (m,) int, the
    first sample of each interval and its number of steps; inset : (m,) float [rad]
    """
    inset = np.minimum(0.5 * tol, 0.25 * width)
    n = np.maximum(np.ceil(width / res - 1e-9), 1).astype(np.int64)
    cnt = n + 1
    base = (np.cumsum(cnt) - cnt).astype(np.int64)
    iv = np.repeat(np.arange(len(ipt)), cnt)
    k = np.arange(cnt.sum()) - base[iv]
    lo_edge, hi_edge = start + inset, start + width - inset
    ang = lo_edge[iv] + (hi_edge - lo_edge)[iv] * k / n[iv]
    return ang, iv, base, n, inset


def horizontal_plan(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings) -> SightAngles:
    """Horizontal sight angle from plan geometry, confirmed by rays beyond the glazing, and the
    horizontal outside distance from each point.

    The intervals that leave through a window come from
    :func:`~en17037cli.criteria.view.plan.visible_intervals` (the windows, and the opaque faces
    near them and the points, exactly; members inside an opening left out when
    ``settings.mullions_block`` is False). The rays are the fan's (:func:`horizontal_fan`: over the
    windows' azimuths, at most ``horizontal_resolution_deg`` apart), so the outside distance is
    sampled where it was; each ray looks beyond the glazing. A ray in a visible interval whose
    first opaque face beyond the glazing is an ``interior`` face that did not take part in plan
    (the building's own walls further away) is blocked there, and every change to or from such a
    ray is bisected to ``angle_tolerance_deg``. A ray that meets a face that took part in plan is
    left to plan (it grazes an edge plan has placed exactly, or meets a member left out).
    Each ray's weight for the distance statistic is the visible measure it owns as in the fan
    (half of each neighbouring segment between two leaving rays, the visible part of a segment
    to a blocked one, the end insets), taken from the plan intervals instead of bisection. An eye
    at a window's sill or head height is moved :data:`EDGE_HEIGHT_M` inside the window.

    Parameters
    ----------
    points : (p, 3) float [m], local frame

    Returns
    -------
    SightAngles, per point; ``angle_err_deg`` is a bound for all that takes part in plan: the
    round-off of the plan intervals (:func:`~en17037cli.criteria.view.plan.float_bound`), plus
    the brackets of far transitions and the end insets whose ray is blocked beyond the glazing
    (a far face narrower than the fan can still fall between two rays)
    """
    from en17037cli.criteria.view.plan import visible_intervals

    p = len(points)
    res = np.radians(settings.horizontal_resolution_deg)
    tol = np.radians(settings.angle_tolerance_deg)
    points = fan_heights(rg, points)
    ppt, plo, phi, faces, bound = visible_intervals(view_rays.scene, rg, points, settings.frame_depth_m,
                                                    settings.mullions_block)
    measure = cumulative_measure(ppt, plo, phi, p)
    ipt, start, width = fan_intervals(rg, points)
    ang, iv, base, n, inset = fan_samples(ipt, start, width, res, tol)
    pidx = ipt[iv]
    near = np.zeros(len(view_rays.scene.triangles), bool)
    near[faces] = True
    engine = view_rays.engine

    def trace(pt_idx, angles):
        d = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(len(angles))])
        o = points[pt_idx]
        f_g, t_g = engine.first_hit(rg.group, o, d)
        f_o, t_o = engine.first_hit("opaque", o, d)
        through = (f_g >= 0) & (t_g < t_o)
        cls = view_rays.outside_class(f_o, d)
        far = (f_o >= 0) & ~near[np.maximum(f_o, 0)]
        # in a visible interval, blocked by a face plan did not see: before the glazing, or the
        # first one beyond it and interior (a ray that misses the glazing grazes its edge: plan decides)
        far_blocked = far & (f_g >= 0) & (~through | (cls == BLOCKED))
        idx = np.flatnonzero(far_blocked)
        far_blocked[idx] = measure(pt_idx[idx], angles[idx])[1]
        return far_blocked, through & (cls != BLOCKED), f_g, f_o, t_o, t_g, d

    fb, leaves, f_g, f_o, t_o, t_g, dirs = trace(pidx, ang)
    F, vis = measure(pidx, ang)
    ok = vis & ~fb  # leaves in plan and beyond it
    a = np.flatnonzero(iv[:-1] == iv[1:]) if len(iv) > 1 else np.zeros(0, int)
    b = a + 1
    m = F[b] - F[a]  # visible measure between consecutive rays
    trans = np.flatnonzero(fb[a] != fb[b])
    tp = pidx[a][trans]
    n_iter = int(np.ceil(np.log2(res / tol))) if tol < res else 0
    lo, hi = bisect_transitions(lambda key, x: trace(key, x)[0], tp, ang[a][trans], ang[b][trans], fb[a][trans],
                                iterations=n_iter)
    Fx = measure(tp, 0.5 * (lo + hi))[0]
    # visible measure blocked beyond the plan: between two such rays, on the blocked side of a
    # bisected transition, and the end insets of blocked end rays
    ends = np.concatenate([base, base + n]) if len(base) else np.zeros(0, int)
    end_vis = np.abs(np.concatenate([F[base] - measure(ipt, start)[0], measure(ipt, start + width)[0] - F[base + n]]))
    far_blocked = (np.bincount(pidx[a], m * (fb[a] & fb[b]), p)
                   + np.bincount(tp, np.where(fb[a][trans], Fx - F[a][trans], F[b][trans] - Fx), p)
                   + np.bincount(pidx[ends], end_vis * fb[ends], p))
    angle = np.bincount(ppt, phi - plo, p) - far_blocked
    # the angular length each ray owns for the distance statistic, as in the fan
    weight = np.zeros(len(ang))
    both = ok[a] & ok[b]
    np.add.at(weight, a, 0.5 * m * both)
    np.add.at(weight, b, 0.5 * m * both)
    one = ok[a] != ok[b]
    np.add.at(weight, np.where(ok[a], a, b)[one], m[one])
    weight[ends] += end_vis * ok[ends]
    dist = gap = None
    if settings.distance_method == "horizontal":
        keep = leaves & ok
        traced = (np.where(keep, f_g, -1), np.where(keep, f_o, -1), np.where(keep, t_o, np.inf), np.where(keep, t_g, np.inf))
        dist, gap = horizontal_distance(view_rays, rg, points, pidx, dirs, keep, traced, weight, p, settings.distance_statistic)
    far_err = np.bincount(tp, hi - lo, p) + np.bincount(pidx[ends], np.concatenate([inset, inset]) * fb[ends], p)
    return SightAngles(
        angle_deg=np.degrees(angle),
        angle_err_deg=np.degrees(bound + far_err),
        transitions=2 * np.bincount(ppt, minlength=p) + np.bincount(tp, minlength=p),
        rays=np.bincount(pidx, minlength=p) + n_iter * np.bincount(tp, minlength=p),
        distance_m=dist, distance_gap_m=gap)


def cumulative_measure(pt: np.ndarray, lo: np.ndarray, hi: np.ndarray, p: int):
    """The measure of a point's pieces [lo, hi] below an angle, as a function.

    Parameters
    ----------
    pt : (q,) int; lo, hi : (q,) float [rad], sorted by point then angle, disjoint; p : points

    Returns
    -------
    measure(pt (k,) int, angle (k,) float [rad]) -> (F (k,) float [rad], inside (k,) bool): the
    measure of the point's pieces within [0, angle], and whether the angle lies on a piece
    """
    w = hi - lo
    before = np.r_[0.0, np.cumsum(w)[:-1]] if len(w) else np.zeros(0)
    first = np.searchsorted(pt, np.arange(p))
    key = pt * 8.0 + lo  # angles < 8 rad: one sorted key over all points

    def measure(q_pt, ang):
        if len(pt) == 0:
            return np.zeros(len(ang)), np.zeros(len(ang), bool)
        j = np.searchsorted(key, q_pt * 8.0 + ang, side="right") - 1
        jj = np.maximum(j, 0)
        mine = (j >= 0) & (pt[jj] == q_pt)
        F = np.where(mine, before[jj] - before[np.minimum(first[q_pt], len(w) - 1)] + np.clip(ang - lo[jj], 0.0, w[jj]), 0.0)
        return F, mine & (ang >= lo[jj]) & (ang <= hi[jj])

    return measure
