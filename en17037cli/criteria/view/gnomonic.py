"""Gnomonic sampling grids of windows seen from viewpoints.

A window seen from a point is sampled in its own plane on a grid uniform in the two gnomonic
angles alpha = atan(X), beta = atan(Y) (a cube-map face aligned with the window), so the number
of cells follows the window's solid angle, plus a grid line through the image of every vertex of
the window's frame, so thin mullions and transoms fill whole cells. The images of the frame's
edges (:func:`edge_images`) are kept too: the cells crossed by those not on a grid line count as
mixed (:func:`~en17037cli.criteria.view.solid_angle.edge_pieces`).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from en17037cli.criteria.view.frames import RoomGeometry

#: Samples on a window's outline are moved this fraction of a cell inwards, so that no ray is aimed
#: exactly at the line where glazing and wall meet.
EDGE_INSET = 1e-3
#: A window is seen only from points at least this far in front of its plane [m].
MIN_PLANE_DISTANCE_M = 1e-6


@dataclass
class Patches:
    """The room's windows as seen from each viewpoint: one patch per (point, window in front of it).

    A patch is sampled on a tensor grid in the angles alpha = atan(X), beta = atan(Y) of the
    gnomonic coordinates X = (x - x0) / d, Y = (y - y0) / d of the window's plane (d: distance
    of the point from the plane, (x0, y0): foot of the perpendicular): ``na`` x ``nb`` uniform
    cells of at most ``resolution`` each way, plus a grid line through the image of every vertex
    of the window's frame (:attr:`~en17037cli.criteria.view.frames.WindowFrame.frame_xys`), so that
    thin mullions and transoms fill whole cells instead of slipping between samples; and the images
    of the frame's edges (``seg_pt``, ``seg``), whose cells count as mixed where they are not on a line.
    """

    pt: np.ndarray
    win: np.ndarray
    d: np.ndarray  # [m]
    x0: np.ndarray  # [m]
    y0: np.ndarray  # [m]
    a0: np.ndarray  # [rad]
    a1: np.ndarray
    b0: np.ndarray
    b1: np.ndarray
    na: np.ndarray
    nb: np.ndarray
    frame_pt: tuple = ()  # per axis: patch of each frame breakpoint
    frame_val: tuple = ()  # per axis: the breakpoint [rad]
    #: (k,) int: patch of each image of a frame edge (:func:`edge_images`)
    seg_pt: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    #: (k, 4) float: its endpoints X0, Y0, X1, Y1 in gnomonic coordinates [-], inside the patch
    seg: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))

    def __len__(self):
        return len(self.pt)


def patches(rg: RoomGeometry, points: np.ndarray, resolution_rad: float, with_edges: bool = True) -> Patches:
    """:class:`Patches` of ``points`` (p, 3) [m] for the room's windows at ``resolution_rad``, with the
    images of their frames' edges unless ``with_edges`` is False."""
    parts, fa, fb, segs = [], [], [], []
    offset = 0
    for f in rg.frames:  # one pass per window of the room, vectorised over points
        r = points - f.origin
        d = -(r @ f.n)
        x0, y0 = r @ f.u, r @ f.v
        ok = np.flatnonzero(d > MIN_PLANE_DISTANCE_M)
        d, x0, y0 = d[ok], x0[ok], y0[ok]
        a0, a1 = np.arctan((f.xmin - x0) / d), np.arctan((f.xmax - x0) / d)
        b0, b1 = np.arctan((f.ymin - y0) / d), np.arctan((f.ymax - y0) / d)
        na = np.maximum(np.ceil((a1 - a0) / resolution_rad - 1e-9), 1).astype(np.int64)
        nb = np.maximum(np.ceil((b1 - b0) / resolution_rad - 1e-9), 1).astype(np.int64)
        parts.append((ok, np.full(len(ok), f.index), d, x0, y0, a0, a1, b0, b1, na, nb))
        for e, out, foot in ((f.frame_x, fa, x0), (f.frame_y, fb, y0)):
            if e is not None and len(e) and len(ok):  # images of the frame's axis-parallel edges
                depth = e[None, :, 1] + d[:, None]
                pi, vi = np.nonzero(depth > MIN_PLANE_DISTANCE_M)
                out.append((pi + offset, np.arctan((e[vi, 0] - foot[pi]) / depth[pi, vi])))
        if with_edges and f.frame_edges is not None and len(f.frame_edges) and len(ok):
            sp, seg = edge_images(f.frame_edges, f.frame_edge_opposite, d, x0, y0, np.tan(a0), np.tan(a1), np.tan(b0), np.tan(b1))
            if not f.is_rectangle and len(sp):  # images outside the outline of a pane that is not a rectangle hide nothing
                ds, xs, ys = d[sp], x0[sp], y0[sp]
                on = f.meets_glazing(xs + ds * seg[:, 0], ys + ds * seg[:, 1], xs + ds * seg[:, 2], ys + ds * seg[:, 3])
                sp, seg = sp[on], seg[on]
            segs.append((sp + offset, seg))
        offset += len(ok)
    cols = [np.concatenate(c) for c in zip(*parts)]
    empty = (np.zeros(0, np.int64), np.zeros(0))
    fa = [np.concatenate(c) for c in zip(*fa)] if fa else empty
    fb = [np.concatenate(c) for c in zip(*fb)] if fb else empty
    quantum = FRAME_LINE_QUANTUM * resolution_rad
    fa = thin_breakpoints(*fa, cols[5], cols[6], quantum)
    fb = thin_breakpoints(*fb, cols[7], cols[8], quantum)
    out = Patches(*cols, frame_pt=(fa[0], fb[0]), frame_val=(fa[1], fb[1]))
    if segs:
        out.seg_pt, out.seg = (np.concatenate(c) for c in zip(*segs))
    return out


def edge_images(edges: np.ndarray, opposite: np.ndarray, d, x0, y0, X0, X1, Y0, Y1):
    """Images of a window's frame edges seen from its patches, clipped to each patch's rectangle.

    A point (x, y, s) of the window's frame (s along the outward normal) is seen from a patch's
    point at X = (x - x0) / (s + d), Y = (y - y0) / (s + d) on the glazing plane's gnomonic
    coordinates: a straight edge has a straight image. The part of an edge in front of the point
    (s + d > :data:`MIN_PLANE_DISTANCE_M`) and inside the patch's rectangle [X0, X1] x [Y0, Y1] is
    found by clipping in the edge's own parameter (each bound is linear in it). An edge shared by
    two faces counts only where it is a silhouette: both faces on one side of the plane through
    the point and the edge (faces on both sides hide what lies on either side of it alike).

    Parameters
    ----------
    edges, opposite : (k, 2, 3) float [m], :attr:`WindowFrame.frame_edges` and ``frame_edge_opposite``
    d, x0, y0 : (m,) float [m], each patch's point: distance in front of the plane, foot of the perpendicular
    X0, X1, Y0, Y1 : (m,) float [-], each patch's rectangle in gnomonic coordinates

    Returns
    -------
    pt : (q,) int, patch of each image; seg : (q, 4) float [-], its endpoints X0, Y0, X1, Y1
    """
    m, k = len(d), len(edges)
    pi = np.repeat(np.arange(m), k)
    ei = np.tile(np.arange(k), m)
    view = np.column_stack([x0, y0, -d])  # the patches' points in (x, y, s)
    two = np.isfinite(opposite[:, 0, 0])
    if two.any():  # silhouettes: both opposite corners on one side of the plane through point and edge
        j = np.flatnonzero(two[ei])
        pj, ej = pi[j], ei[j]
        a = edges[ej, 0] - view[pj]
        b = edges[ej, 1] - view[pj]
        ab = np.cross(a, b)
        s1 = np.einsum("ij,ij->i", ab, opposite[ej, 0] - view[pj])
        s2 = np.einsum("ij,ij->i", ab, opposite[ej, 1] - view[pj])
        keep = np.ones(len(pi), dtype=bool)
        keep[j] = s1 * s2 >= 0
        pi, ei = pi[keep], ei[keep]
    p0, p1 = edges[ei, 0], edges[ei, 1]
    dd = d[pi]
    # bounds g(t) = g0 + t (g1 - g0) >= 0 along the edge p0 + t (p1 - p0), t in [0, 1]
    depth0, depth1 = p0[:, 2] + dd, p1[:, 2] + dd
    gx0, gx1 = p0[:, 0] - x0[pi], p1[:, 0] - x0[pi]
    gy0, gy1 = p0[:, 1] - y0[pi], p1[:, 1] - y0[pi]
    bounds = ((depth0 - MIN_PLANE_DISTANCE_M, depth1 - MIN_PLANE_DISTANCE_M),
              (gx0 - X0[pi] * depth0, gx1 - X0[pi] * depth1), (X1[pi] * depth0 - gx0, X1[pi] * depth1 - gx1),
              (gy0 - Y0[pi] * depth0, gy1 - Y0[pi] * depth1), (Y1[pi] * depth0 - gy0, Y1[pi] * depth1 - gy1))
    t0, t1 = np.zeros(len(pi)), np.ones(len(pi))
    for g0, g1 in bounds:  # Liang-Barsky: five half-planes
        with np.errstate(divide="ignore", invalid="ignore"):
            cut = g0 / (g0 - g1)
        t0 = np.where((g0 < 0) & (g1 >= 0), np.maximum(t0, cut), t0)
        t1 = np.where((g1 < 0) & (g0 >= 0), np.minimum(t1, cut), t1)
        t1 = np.where((g0 < 0) & (g1 < 0), -1.0, t1)
    ok = np.flatnonzero(t1 > t0)
    pi, t0, t1 = pi[ok], t0[ok, None], t1[ok, None]
    p0, dp = p0[ok], (p1 - p0)[ok]
    q0, q1 = p0 + t0 * dp, p0 + t1 * dp
    dep0, dep1 = q0[:, 2] + d[pi], q1[:, 2] + d[pi]
    seg = np.column_stack([(q0[:, 0] - x0[pi]) / dep0, (q0[:, 1] - y0[pi]) / dep0,
                           (q1[:, 0] - x0[pi]) / dep1, (q1[:, 1] - y0[pi]) / dep1])
    # clipping leaves the endpoints on the bounds up to round-off
    for c, lo, hi in ((0, X0, X1), (1, Y0, Y1), (2, X0, X1), (3, Y0, Y1)):
        seg[:, c] = np.clip(seg[:, c], lo[pi], hi[pi])
    long = np.abs(seg[:, 2] - seg[:, 0]) + np.abs(seg[:, 3] - seg[:, 1]) > MIN_SEGMENT
    return pi[long], seg[long]


#: Images of frame edges shorter than this (gnomonic units: ~radians near the axis) are left out.
MIN_SEGMENT = 1e-12


#: A patch with more frame breakpoints than this on an axis (a finely tessellated round or arched
#: frame) keeps one per :data:`FRAME_LINE_QUANTUM` of the resolution ...
MAX_FRAME_LINES = 64
#: ... so its grid has at most about 1 / FRAME_LINE_QUANTUM times the uniform lines, and memory stays bounded.
FRAME_LINE_QUANTUM = 1.0


def thin_breakpoints(pt: np.ndarray, val: np.ndarray, lo: np.ndarray, hi: np.ndarray, quantum_rad: float):
    """Frame breakpoints inside their patch's range, thinned where a patch has too many.

    Breakpoints outside (lo, hi) of their patch draw no line and are dropped. A patch with more
    than :data:`MAX_FRAME_LINES` keeps the first breakpoint in each ``quantum_rad`` bin: a few
    hundred vertices of a tessellated round frame would multiply the cells a hundredfold, and the
    cells crossed by the images of edges whose lines were dropped count as mixed instead
    (:func:`~en17037cli.criteria.view.solid_angle.edge_pieces`). Straight mullions and transoms
    give far fewer breakpoints and keep all of theirs.

    Returns
    -------
    pt : (q,) int; val : (q,) float [rad]
    """
    inside = (val > lo[pt] + LINE_MERGE_RAD) & (val < hi[pt] - LINE_MERGE_RAD)
    pt, val = pt[inside], val[inside]
    if len(pt) == 0:
        return pt, val
    count = np.bincount(pt)
    crowded = count[pt] > MAX_FRAME_LINES
    if not crowded.any():
        return pt, val
    keep = ~crowded
    cp, cv = pt[crowded], val[crowded]
    bins = np.floor(cv / quantum_rad).astype(np.int64)
    order = np.lexsort((cv, bins, cp))
    first = np.r_[True, (cp[order][1:] != cp[order][:-1]) | (bins[order][1:] != bins[order][:-1])]
    chosen = order[first]
    return np.concatenate([pt[keep], cp[chosen]]), np.concatenate([val[keep], cv[chosen]])


#: Grid lines of a patch closer than this are one line [rad].
LINE_MERGE_RAD = 1e-9


def grid_lines(lo, hi, n, extra_pt, extra_val):
    """Sorted grid lines of each patch and the sample columns on them.

    Lines: ``n + 1`` uniform lines over [lo, hi] and the breakpoints strictly inside. Samples
    sit on uniform lines; the two outer lines are sampled ``EDGE_INSET`` of a cell inwards, and a
    breakpoint line is sampled just beside it on both sides, so no ray is aimed exactly at an
    edge of the glazing or of the frame.

    Returns
    -------
    line_ptr : (m + 1,) int, lines of patch i are line_val[line_ptr[i]:line_ptr[i + 1]]
    line_val : (L,) float [rad]
    lcol, rcol : (L,) int, the sample column just left / right of each line (global index)
    col_ptr : (m + 1,) int; col_val : (C,) float [rad]
    """
    m = len(lo)
    cnt = n + 1
    pp = np.repeat(np.arange(m), cnt)
    k = np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    val = np.where(k == n[pp], hi[pp], lo[pp] + ((hi - lo) / n)[pp] * k)
    inside = (extra_val > lo[extra_pt] + LINE_MERGE_RAD) & (extra_val < hi[extra_pt] - LINE_MERGE_RAD)
    pt = np.concatenate([pp, extra_pt[inside]])
    val = np.concatenate([val, extra_val[inside]])
    brk = np.concatenate([np.zeros(len(pp), bool), np.ones(int(inside.sum()), bool)])
    order = np.lexsort((val, pt))
    pt, val, brk = pt[order], val[order], brk[order]
    dup = np.r_[False, (pt[1:] == pt[:-1]) & (val[1:] - val[:-1] < LINE_MERGE_RAD)]
    grp = np.cumsum(~dup) - 1
    ng = grp[-1] + 1 if len(grp) else 0
    is_brk = np.bincount(grp, brk.astype(float), ng) > 0
    is_uni = np.bincount(grp, (~brk).astype(float), ng) > 0
    pt, val = pt[~dup], val[~dup]
    line_ptr = np.concatenate([[0], np.cumsum(np.bincount(pt, minlength=m))])
    first = np.zeros(len(pt), bool)
    first[line_ptr[:-1]] = True
    last = np.zeros(len(pt), bool)
    last[line_ptr[1:] - 1] = True
    prev_gap = np.r_[0.0, np.diff(val)]
    next_gap = np.r_[np.diff(val), 0.0]
    two = is_brk & ~is_uni & ~first & ~last  # sampled on both sides
    ncol = np.where(two, 2, 1)
    cstart = np.concatenate([[0], np.cumsum(ncol)[:-1]])
    col_val = np.empty(int(ncol.sum()))
    left_val = np.where(last, val - EDGE_INSET * prev_gap, np.where(two, val - EDGE_INSET * prev_gap, val))
    right_val = np.where(first, val + EDGE_INSET * next_gap, np.where(two, val + EDGE_INSET * next_gap, val))
    col_val[cstart] = np.where(first, right_val, left_val)
    col_val[cstart[two] + 1] = right_val[two]
    lcol = cstart
    rcol = cstart + (ncol - 1)
    col_ptr = np.concatenate([[0], np.cumsum(np.bincount(pt, ncol, m).astype(np.int64))])
    return line_ptr, val, lcol, rcol, col_ptr, col_val
