"""View-out engine (EN 17037 clause 5.2): sight angle, outside distance and view layers.

For each viewpoint:

* **Solid angles.** Each window is sampled in its own plane on a grid uniform in the two
  gnomonic angles alpha = atan(X), beta = atan(Y) seen from the point (:class:`Patches`), cells
  at most ``angular_resolution_deg`` each way, so the cost scales with the windows' solid angle
  and each ray is shared by the four cells around it. One ray per sample, against the opaque
  faces, classifies it (blocked before the glazing / blocked by interior faces beyond it / sky /
  landscape / ground, :func:`~en17037cli.raytrace.outside_class`). Cells whose samples disagree
  are split in four, up to ``refine_levels`` times, until the point's estimated error of every
  layer is within max(``solid_angle_rel_tolerance`` x its solid angle,
  ``solid_angle_abs_tolerance_sr``). Each cell weighs its exact solid angle (the rectangle
  formula, or the clipped polygon for windows that are not rectangles), so the weights of an
  unobstructed window add up to its exact solid angle; a cell still mixed after refinement is
  shared among its samples' classes. Error estimate: half the solid angle of the cells still
  mixed. Features narrower than a cell can fall between samples: the resolution is reported.
* **Horizontal sight angle.** A horizontal fan at eye height over the azimuths in which the
  windows lie (:func:`fan_intervals`), ``horizontal_resolution_deg`` apart; every change between
  "leaves through a window" and "blocked" is located by bisection to ``angle_tolerance_deg``.
  Error estimate: the remaining bracket widths plus the end insets, summed (a bound).
* **Outside distance.** ``horizontal`` (default): over the leaving horizontal directions, the
  distance from the glazing plane to the first ``landscape`` face, measured horizontally and
  perpendicular to the window; ``solid_angle``: the perpendicular distance (delta_1 - delta_0)
  r . n of Brembilla et al. (2021) eq. (1) over the leaving cells, weighted by solid angle.
  Unobstructed directions count as +inf; ground never obstructs.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli import standard
from en17037cli.errors import InputError
from en17037cli.geometry import offset_rectangle_solid_angle
from en17037cli.raytrace import (BLOCKED, GLAZING_OFFSET_M, GROUND_HIT, LANDSCAPE_HIT, SKY, outside_class,
                                 trace_through_windows)
from en17037cli.scene import GROUND, LANDSCAPE
from en17037cli.view_math import (clipped_solid_angle, frame_vertices, grid_points, in_triangle,
                                  points_in_triangles, weighted_statistic, window_frame)

#: Samples on a window's outline are moved this fraction of a cell inwards, so that no ray is aimed
#: exactly at the line where glazing and wall meet.
EDGE_INSET = 1e-3
#: A window is seen only from points at least this far in front of its plane [m].
MIN_PLANE_DISTANCE_M = 1e-6
#: Base cells per chunk of viewpoints (bounds memory; each chunk is vectorised).
CELLS_PER_CHUNK = 300_000


@dataclass
class RoomGeometry:
    """Per-room lookups: the room's windows as :class:`~en17037cli.view_math.WindowFrame` and their faces."""

    frames: list
    window_of_face: np.ndarray  # (n_faces,) int, index into frames, -1 for faces that are no window of the room
    triangles: np.ndarray  # (k, 3, 3) all window triangles of the room [m]
    triangle_window: np.ndarray  # (k,) int, index into frames
    group: str  # ray-engine group of the room's windows

    def frame_array(self, attr: str) -> np.ndarray:
        return np.array([getattr(f, attr) for f in self.frames])


def room_geometry(scene, room, frame_depth_m: float = 0.5) -> RoomGeometry:
    """Lookups of ``room``'s windows; opaque faces within ``frame_depth_m`` of a window's plane
    and over it are its frame (:func:`~en17037cli.view_math.frame_vertices`)."""
    from en17037cli.raytrace import room_window_group
    from en17037cli.scene import WINDOW

    opaque = scene.triangles[scene.layer != WINDOW]
    frames = [window_frame(w, i) for i, w in enumerate(room.windows)]
    for f in frames:
        f.frame_xys = frame_vertices(f, scene.vertices, opaque, frame_depth_m)
    wof = np.full(len(scene.triangles), -1, dtype=np.int64)
    for f in frames:
        wof[f.face_ids] = f.index
    tris = np.concatenate([w.triangles for w in room.windows])
    tw = np.concatenate([np.full(len(w.triangles), i) for i, w in enumerate(room.windows)])
    return RoomGeometry(frames, wof, tris, tw, room_window_group(room))


def viewpoints(scene, room, view_cfg: dict, explicit) -> tuple[list, list]:
    """Viewpoints of a room grouped by eye height.

    Returns
    -------
    groups : list of (eye_height_m, (n, 3) float local [m])
    notes : list of str
    """
    notes = []
    if explicit is not None:
        pts = scene.to_local(np.asarray(explicit, dtype=float))
        heights = np.round(pts[:, 2] - room.floor_z, 3)
        groups = [(float(h), pts[heights == h]) for h in np.unique(heights)]
    else:
        utilised = room.floor.buffer(-view_cfg["wall_margin_m"], join_style="mitre")
        if utilised.is_empty:
            raise InputError(f"rooms '{room.name}': the utilised area (floor inset by view.wall_margin_m = {view_cfg['wall_margin_m']} m) is empty; reduce the margin")
        xy = grid_points(utilised, view_cfg["grid_spacing_m"])
        groups = [(float(h), np.column_stack([xy, np.full(len(xy), room.floor_z + h)])) for h in view_cfg["eye_heights_m"]]
    out = []
    for h, p in groups:
        p = p.copy()
        moved = 0
        for w in room.windows:  # per window, vectorised over points
            c = w.centroid
            s = (p - c) @ w.normal
            close = np.abs(s) < GLAZING_OFFSET_M
            if np.any(close):
                p[close] -= (s[close] + GLAZING_OFFSET_M)[:, None] * w.normal
                moved += int(close.sum())
        if moved:
            notes.append(f"room '{room.name}': {moved} viewpoints at eye height {h} m lay on a glazing plane and were moved {GLAZING_OFFSET_M * 1000:.0f} mm into the room")
        out.append((h, p))
    return out, notes


@dataclass
class Patches:
    """The room's windows as seen from each viewpoint: one patch per (point, window in front of it).

    A patch is sampled on a tensor grid in the angles alpha = atan(X), beta = atan(Y) of the
    gnomonic coordinates X = (x - x0) / d, Y = (y - y0) / d of the window's plane (d: distance
    of the point from the plane, (x0, y0): foot of the perpendicular): ``na`` x ``nb`` uniform
    cells of at most ``resolution`` each way, plus a grid line through the image of every vertex
    of the window's frame (:attr:`~en17037cli.view_math.WindowFrame.frame_xys`), so that thin
    mullions and transoms fill whole cells instead of slipping between samples.
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

    def __len__(self):
        return len(self.pt)


def patches(rg: RoomGeometry, points: np.ndarray, resolution_rad: float) -> Patches:
    """:class:`Patches` of ``points`` (p, 3) [m] for the room's windows at ``resolution_rad``."""
    parts, fa, fb = [], [], []
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
        e = f.frame_xys
        if len(e) and len(ok):  # images of the frame's vertices, seen through the glazing plane
            depth = e[None, :, 2] + d[:, None]
            pi, vi = np.nonzero(depth > MIN_PLANE_DISTANCE_M)
            fa.append((pi + offset, np.arctan((e[vi, 0] - x0[pi]) / depth[pi, vi])))
            fb.append((pi + offset, np.arctan((e[vi, 1] - y0[pi]) / depth[pi, vi])))
        offset += len(ok)
    cols = [np.concatenate(c) for c in zip(*parts)]
    empty = (np.zeros(0, np.int64), np.zeros(0))
    fa = [np.concatenate(c) for c in zip(*fa)] if fa else empty
    fb = [np.concatenate(c) for c in zip(*fb)] if fb else empty
    return Patches(*cols, frame_pt=(fa[0], fb[0]), frame_val=(fa[1], fb[1]))


#: Grid lines of a patch closer than this are one line [rad].
LINE_MERGE_RAD = 1e-9


def _grid_lines(lo, hi, n, extra_pt, extra_val):
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


class _Sampler:
    """Traces rays from patches' viewpoints through gnomonic angles (alpha, beta) of their windows."""

    def __init__(self, engine, rg: RoomGeometry, points: np.ndarray, P: Patches, with_distance: bool):
        self.engine, self.rg, self.P = engine, rg, P
        self.points32 = points.astype(np.float32)
        self.U, self.V, self.N = rg.frame_array("u"), rg.frame_array("v"), rg.frame_array("n")
        self.rect = rg.frame_array("is_rectangle")
        self.with_distance = with_distance
        self.rays = 0

    def __call__(self, patch: np.ndarray, A: np.ndarray, B: np.ndarray):
        """Class of each sample (-1: outside the window's outline) and perpendicular distance [m] beyond the glazing.

        A sample counts for its window when no opaque face and no nearer window of the room lie
        before the glazing; then :func:`~en17037cli.raytrace.outside_class` classifies it.

        Returns
        -------
        cls : (m,) int8; dist : (m,) float [m] (+inf unless landscape), or None without distances
        """
        P, rg = self.P, self.rg
        X, Y = np.tan(A), np.tan(B)
        w = P.win[patch]
        idx = None
        if not self.rect.all():
            inside = self.rect[w].copy()
            for f in rg.frames:  # outline test for windows that are not rectangles
                sel = np.flatnonzero((w == f.index) & ~f.is_rectangle)
                if len(sel):
                    ps = patch[sel]
                    xy = np.column_stack([P.x0[ps] + P.d[ps] * X[sel], P.y0[ps] + P.d[ps] * Y[sel]])
                    inside[sel] = points_in_triangles(xy, f.tri2)
            idx = np.flatnonzero(inside)
            patch, X, Y, w = patch[idx], X[idx], Y[idx], w[idx]
        secant = np.sqrt(1.0 + X * X + Y * Y)
        inv = 1.0 / secant
        dirs = np.empty((len(X), 3), dtype=np.float32)  # Embree's precision, built column by column
        one = len(rg.frames) == 1
        for k in range(3):  # the three coordinates
            u, v, n = (a[0, k] if one else a[w, k] for a in (self.U, self.V, self.N))
            dirs[:, k] = (X * u + Y * v + n) * inv
        t_w = P.d[patch] * secant  # distance to the glazing plane [m]
        origins = self.points32[P.pt[patch]]
        f_o, t_o = self.engine.first_hit("opaque", origins, dirs)
        c = outside_class(self.engine, f_o, dirs)
        c[t_o <= t_w] = BLOCKED
        if len(rg.frames) > 1:  # a direction counts once, through the nearest window of the room
            f_g, t_g = self.engine.first_hit(rg.group, origins, dirs)
            nearer = (f_g >= 0) & (rg.window_of_face[np.maximum(f_g, 0)] != w) & (t_g < t_w * (1 - 1e-6))
            c[nearer] = BLOCKED
        dist = None
        if self.with_distance:
            dist = np.where(c == LANDSCAPE_HIT, (t_o - t_w) / secant, np.inf)
        self.rays += len(c)
        if idx is not None:
            full_c = np.full(len(A), -1, dtype=np.int8)
            full_c[idx] = c
            c = full_c
            if dist is not None:
                full_d = np.full(len(A), np.inf)
                full_d[idx] = dist
                dist = full_d
        return c, dist


def _cell_weights(rg: RoomGeometry, P: Patches, patch, G, full):
    """Exact solid angle [sr] of each cell's part inside its window, and a sample point for cells
    whose corners may all lie outside the window (NaN elsewhere).

    Cells of rectangular windows, and cells already known to lie inside (``full``), weigh the
    rectangle formula; the others are clipped against the window's triangles.

    Parameters
    ----------
    G : (m, >= 4) float, cell bounds alpha0, alpha1, beta0, beta1 [rad] in the first columns

    Returns
    -------
    weight (m,) [sr], full (m,) bool, extra (m, 2) [rad]
    """
    X0, X1, Y0, Y1 = (np.tan(G[:, i]) for i in range(4))
    weight = offset_rectangle_solid_angle(X0, X1, Y0, Y1)
    full = full.copy()
    extra = np.full((len(G), 2), np.nan)
    if full.all():
        return weight, full, extra
    w = P.win[patch]
    for f in rg.frames:  # clipping, for windows that are not rectangles
        sel = np.flatnonzero((w == f.index) & ~f.is_rectangle & ~full)
        if len(sel) == 0:
            continue
        ps = patch[sel]
        # the window's triangles in each cell's gnomonic coordinates
        g = (f.tri2[None, :, :, :] - np.stack([P.x0[ps], P.y0[ps]], axis=1)[:, None, None, :]) / P.d[ps][:, None, None, None]
        x0, x1, y0, y1 = X0[sel], X1[sel], Y0[sel], Y1[sel]
        corners = np.stack([np.stack([x0, y0], 1), np.stack([x1, y0], 1), np.stack([x0, y1], 1), np.stack([x1, y1], 1)], axis=1)
        k = len(f.tri2)
        ci, ti = np.divmod(np.arange(len(sel) * k), k)
        tri = g[ci, ti]
        lo, hi = tri.min(axis=1), tri.max(axis=1)
        overlap = (lo[:, 0] < x1[ci]) & (hi[:, 0] > x0[ci]) & (lo[:, 1] < y1[ci]) & (hi[:, 1] > y0[ci])
        ci, tri = ci[overlap], tri[overlap]
        inside4 = np.ones(len(ci), dtype=bool)
        for j in range(4):  # a cell whose four corners lie in one (convex) triangle lies inside it
            inside4 &= in_triangle(corners[ci, j], tri)
        is_full = np.zeros(len(sel), dtype=bool)
        is_full[ci[inside4]] = True
        part = ~is_full[ci]
        ci, tri = ci[part], tri[part]
        rect = np.column_stack([x0[ci], x1[ci], y0[ci], y1[ci]])
        om, cen = clipped_solid_angle(tri, rect)
        wsum = np.bincount(ci, om, len(sel))
        # the centroid of the largest clipped piece: a point surely inside the window's part of the cell
        order = np.lexsort((-om, ci))
        first = order[np.r_[True, ci[order][1:] != ci[order][:-1]]] if len(ci) else order
        ex = np.full((len(sel), 2), np.nan)
        ex[ci[first]] = np.arctan(cen[first])
        weight[sel] = np.where(is_full, weight[sel], wsum)
        full[sel] = is_full
        extra[sel] = np.where(is_full[:, None], np.nan, ex)
    return weight, full, extra


#: Sample classes that are layers, with their report keys.
LAYER_CODES = (("sky", SKY), ("landscape", LANDSCAPE_HIT), ("ground", GROUND_HIT))


@dataclass
class _Cells:
    """Sampling cells: bounds and sample positions in (alpha, beta), their samples' classes, weights.

    G columns: alpha0, alpha1, beta0, beta1 (the cell), then the same for its samples (moved
    inwards on a window's outline) [rad]. ``cls`` columns: corners (a0 b0), (a1 b0), (a0 b1),
    (a1 b1) and one extra sample inside the window for cells with no corner in it (-1: none).
    """

    patch: np.ndarray
    G: np.ndarray
    cls: np.ndarray
    dist: np.ndarray | None
    w: np.ndarray
    full: np.ndarray
    extra: np.ndarray

    def take(self, sel) -> "_Cells":
        return _Cells(self.patch[sel], self.G[sel], self.cls[sel], None if self.dist is None else self.dist[sel],
                      self.w[sel], self.full[sel], self.extra[sel])

    def sample_extra(self, sample) -> "_Cells":
        """Trace a sample inside the window's part of every cell none of whose corners lies in the window."""
        need = np.flatnonzero(np.all(self.cls[:, :4] < 0, axis=1) & np.isfinite(self.extra[:, 0]))
        if len(need):
            c, dd = sample(self.patch[need], self.extra[need, 0], self.extra[need, 1])
            self.cls[need, 4] = c
            if self.dist is not None:
                self.dist[need, 4] = dd
        return self


def _base_cells(sample, P: Patches) -> _Cells:
    """Level-0 cells of every patch, their corner samples traced once each (shared between cells)."""
    la_ptr, la, la_l, la_r, ca_ptr, ca = _grid_lines(P.a0, P.a1, P.na, P.frame_pt[0], P.frame_val[0])
    lb_ptr, lb, lb_l, lb_r, cb_ptr, cb = _grid_lines(P.b0, P.b1, P.nb, P.frame_pt[1], P.frame_val[1])
    m = len(P)
    nca, ncb = np.diff(ca_ptr), np.diff(cb_ptr)
    # samples: every (alpha column, beta column) pair of a patch
    ns = nca * ncb
    sbase = np.concatenate([[0], np.cumsum(ns)[:-1]])
    sp = np.repeat(np.arange(m), ns)
    ia, ib = np.divmod(np.arange(ns.sum()) - sbase[sp], ncb[sp])
    vcls, vdist = sample(sp, ca[ca_ptr[sp] + ia], cb[cb_ptr[sp] + ib])
    # cells: every (alpha interval, beta interval) pair of a patch
    nla, nlb = np.diff(la_ptr) - 1, np.diff(lb_ptr) - 1
    nc = nla * nlb
    cbase = np.concatenate([[0], np.cumsum(nc)[:-1]])
    cp = np.repeat(np.arange(m), nc)
    i, j = np.divmod(np.arange(nc.sum()) - cbase[cp], nlb[cp])
    li, lj = la_ptr[cp] + i, lb_ptr[cp] + j  # global index of the cell's lower lines

    def sample_index(col_a, col_b):
        return sbase[cp] + (col_a - ca_ptr[cp]) * ncb[cp] + (col_b - cb_ptr[cp])

    corner = np.stack([sample_index(la_r[li], lb_r[lj]), sample_index(la_l[li + 1], lb_r[lj]),
                       sample_index(la_r[li], lb_l[lj + 1]), sample_index(la_l[li + 1], lb_l[lj + 1])], axis=1)
    G = np.column_stack([la[li], la[li + 1], lb[lj], lb[lj + 1],
                         ca[la_r[li]], ca[la_l[li + 1]], cb[lb_r[lj]], cb[lb_l[lj + 1]]])
    cls = np.concatenate([vcls[corner], np.full((len(cp), 1), -1, np.int8)], axis=1)
    dist = None if vdist is None else np.concatenate([vdist[corner], np.full((len(cp), 1), np.inf)], axis=1)
    weight, full, extra = _cell_weights(sample.rg, P, cp, G, sample.rect[P.win[cp]])
    cells = _Cells(cp, G, cls, dist, weight, full, extra)
    if not full.all():
        cells = cells.take(weight > 0)
    return cells.sample_extra(sample)


#: The four children of a cell: for each, its bounds and sample positions as columns of
#: [A0, A1, B0, B1, SA0, SA1, SB0, SB1, Am, Bm], and its corner samples as indices into
#: [parent corners 0-3, new samples 4-8 (bottom, top, left and right edge midpoints, centre)].
_CHILDREN = (
    ((0, 8, 2, 9, 4, 8, 6, 9), (0, 4, 6, 8)),
    ((8, 1, 2, 9, 8, 5, 6, 9), (4, 1, 8, 7)),
    ((0, 8, 9, 3, 4, 8, 9, 7), (6, 8, 2, 5)),
    ((8, 1, 9, 3, 8, 5, 9, 7), (8, 7, 5, 3)),
)


def _split(sample, cells: _Cells) -> _Cells:
    """Split cells in four at their angular midpoints; five new samples per cell."""
    m = len(cells.w)
    G = cells.G
    Am, Bm = 0.5 * (G[:, 0] + G[:, 1]), 0.5 * (G[:, 2] + G[:, 3])
    # new samples: bottom, top, left, right edge midpoints and the centre
    na = np.concatenate([Am, Am, G[:, 4], G[:, 5], Am])
    nb = np.concatenate([G[:, 6], G[:, 7], Bm, Bm, Bm])
    ncls, ndist = sample(np.tile(cells.patch, 5), na, nb)
    GG = np.column_stack([G, Am, Bm])
    cls = np.concatenate([cells.cls[:, :4], ncls.reshape(5, m).T], axis=1)
    dist = None if ndist is None else np.concatenate([cells.dist[:, :4], ndist.reshape(5, m).T], axis=1)
    kid_G = np.concatenate([GG[:, list(cols)] for cols, _ in _CHILDREN])
    kid_cls = np.concatenate([np.column_stack([cls[:, list(cor)], np.full(m, -1, np.int8)]) for _, cor in _CHILDREN])
    kid_dist = None if dist is None else np.concatenate(
        [np.column_stack([dist[:, list(cor)], np.full(m, np.inf)]) for _, cor in _CHILDREN])
    patch = np.tile(cells.patch, 4)
    full = np.tile(cells.full, 4)
    w, full, extra = _cell_weights(sample.rg, sample.P, patch, kid_G, full)
    kids = _Cells(patch, kid_G, kid_cls, kid_dist, w, full, extra)
    if not full.all():
        kids = kids.take(w > 0)
    return kids.sample_extra(sample)


def solid_angles(engine, rg: RoomGeometry, points: np.ndarray, cfg: dict) -> dict:
    """Solid angle of sky, landscape and ground seen through the room's windows from each point.

    Returns a dict of (p,) arrays [sr]: ``sky``, ``landscape``, ``ground``, ``glazing`` (the
    windows' geometric solid angle, summed over windows), ``err_sky``/``err_landscape``/
    ``err_ground``, and for the ``solid_angle`` distance method ``distance`` [m] and
    ``distance_gap`` [m]; ``cells`` (p,) int, the final cells.
    """
    p = len(points)
    out = {key: np.zeros(p) for key in ("sky", "landscape", "ground", "glazing", "err_sky", "err_landscape", "err_ground")}
    out["cells"] = np.zeros(p, dtype=int)
    P = patches(rg, points, np.radians(cfg["angular_resolution_deg"]))
    with_dist = cfg["distance_method"] == "solid_angle"
    sample = _Sampler(engine, rg, points, P, with_dist)
    dist_rows, dist_w, dist_p = [], [], []
    cells = _base_cells(sample, P) if len(P.pt) else None
    rel, abs_ = cfg["solid_angle_rel_tolerance"], cfg["solid_angle_abs_tolerance_sr"]
    for level in range(cfg["refine_levels"] + 1):
        if cells is None or len(cells.w) == 0:
            break
        pi, w, cls = P.pt[cells.patch], cells.w, cells.cls
        kinds = np.bitwise_or.reduce(np.where(cls >= 0, np.left_shift(1, np.maximum(cls, 0)), 0).astype(np.uint8), axis=1)
        mixed = (kinds & (kinds - 1)) != 0
        mi = np.flatnonzero(mixed)
        valid_m = cls[mi] >= 0
        nvalid_m = np.maximum(valid_m.sum(axis=1), 1)
        # share of each layer: 1 or 0 in a pure cell, the share of its samples in a mixed one
        share = {}
        for key, code in LAYER_CODES:
            s = (kinds == (1 << code)).astype(float)
            s[mi] = (cls[mi] == code).sum(axis=1) / nvalid_m
            share[key] = s
        # Error control: a point stops refining once every layer's estimated error (half the
        # solid angle of its mixed cells) is within max(rel * layer solid angle, abs).
        done = np.ones(p, dtype=bool)
        half_mixed = 0.5 * w * mixed
        for key, code in LAYER_CODES:
            est = out["err_" + key] + np.bincount(pi, half_mixed * ((kinds >> code) & 1), p)
            value = out[key] + np.bincount(pi, w * share[key], p)
            done &= est <= np.maximum(rel * value, abs_)
        last = level == cfg["refine_levels"]
        final = slice(None) if last else np.flatnonzero(~mixed | done[pi])
        fp, fw = pi[final], w[final]
        out["glazing"] += np.bincount(fp, fw, p)
        out["cells"] += np.bincount(fp, minlength=p)
        for key, code in LAYER_CODES:
            out[key] += np.bincount(fp, fw * share[key][final], p)
            out["err_" + key] += np.bincount(fp, half_mixed[final] * ((kinds[final] >> code) & 1), p)
        if with_dist:  # each valid sample of a final cell carries an equal share of its weight
            c = cls[final]
            ok = (c >= 0) & (c != BLOCKED)
            sw = (fw / np.maximum((c >= 0).sum(axis=1), 1))[:, None] * ok
            r, col = np.nonzero(sw > 0)
            dist_rows.append(cells.dist[final][r, col])
            dist_w.append(sw[r, col])
            dist_p.append(fp[r])
        if not last:
            rest = np.ones(len(w), dtype=bool)
            rest[final] = False
            if not rest.any():
                break
            cells = _split(sample, cells.take(rest))
    if with_dist:
        vals, wts = _pad_rows(np.concatenate(dist_p) if dist_p else np.zeros(0, int),
                              np.concatenate(dist_rows) if dist_rows else np.zeros(0),
                              np.concatenate(dist_w) if dist_w else np.zeros(0), p)
        out["distance"], out["distance_gap"] = weighted_statistic(vals, wts, cfg["distance_statistic"])
    return out


def _pad_rows(row: np.ndarray, values: np.ndarray, weights: np.ndarray, p: int):
    """Scatter ragged (row, value, weight) triples into (p, kmax) arrays padded with weight 0."""
    order = np.argsort(row, kind="stable")
    row, values, weights = row[order], values[order], weights[order]
    counts = np.bincount(row, minlength=p)
    kmax = max(int(counts.max()) if len(counts) else 0, 1)
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    col = np.arange(len(row)) - start[row]
    V = np.full((p, kmax), np.nan)
    W = np.zeros((p, kmax))
    V[row, col] = values
    W[row, col] = weights
    return V, W


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
    s = tri[None, :, :, 2] - points[:, None, None, 2]  # (p, k, 3) height of each vertex above the eye
    ends = []
    for a, b in ((0, 1), (1, 2), (2, 0)):  # the three edges of every triangle
        sa, sb = s[..., a], s[..., b]
        cross = (sa <= 0) != (sb <= 0)
        t = sa / np.where(cross, sa - sb, 1.0)
        xy = tri[None, :, a, :2] + t[..., None] * (tri[None, :, b, :2] - tri[None, :, a, :2])
        ends.append((cross, xy))
    flags = np.stack([e[0] for e in ends], axis=-1)  # (p, k, 3)
    xy = np.stack([e[1] for e in ends], axis=-2)  # (p, k, 3, 2)
    two = flags.sum(axis=-1) == 2
    first = np.argmax(flags, axis=-1)
    second = 2 - np.argmax(flags[..., ::-1], axis=-1)
    pi, ki = np.nonzero(two)
    e1 = xy[pi, ki, first[pi, ki]] - points[pi, :2]
    e2 = xy[pi, ki, second[pi, ki]] - points[pi, :2]
    n = rg.frame_array("n")[tw[ki]]
    front = np.einsum("ij,ij->i", rg.frame_array("origin")[tw[ki]] - points[pi], n) > MIN_PLANE_DISTANCE_M
    pi, e1, e2 = pi[front], e1[front], e2[front]
    t1, t2 = np.arctan2(e1[:, 1], e1[:, 0]), np.arctan2(e2[:, 1], e2[:, 0])
    delta = (t2 - t1 + np.pi) % (2 * np.pi) - np.pi
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
    run_end = np.maximum.accumulate(end)
    new = np.r_[True, key[1:] > run_end[:-1] + 1e-12]
    g0 = np.flatnonzero(new)
    if len(g0) == 0:
        return np.zeros(0, np.int64), np.zeros(0), np.zeros(0)
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


def horizontal(engine, rg: RoomGeometry, points: np.ndarray, cfg: dict) -> dict:
    """Horizontal sight angle and horizontal outside distance from each point.

    Rays are traced only towards the windows: over each merged azimuth interval of
    :func:`fan_intervals`, at most ``horizontal_resolution_deg`` apart, the two end rays moved
    half of ``angle_tolerance_deg`` inwards; every change between "leaves" and "blocked" is then
    located by bisection to ``angle_tolerance_deg``. An eye at a window's sill or head height is
    moved :data:`EDGE_HEIGHT_M` inside the window (:func:`fan_heights`).

    Returns a dict of (p,) arrays: ``angle_deg``, ``angle_err_deg``, ``transitions`` and, for the
    ``horizontal`` distance method, ``distance`` [m] and ``distance_gap`` [m].
    """
    p = len(points)
    res = np.radians(cfg["horizontal_resolution_deg"])
    tol = np.radians(cfg["angle_tolerance_deg"])
    points = fan_heights(rg, points)
    ipt, start, width = fan_intervals(rg, points)
    inset = np.minimum(0.5 * tol, 0.25 * width)
    n = np.maximum(np.ceil(width / res - 1e-9), 1).astype(np.int64)
    cnt = n + 1
    base = np.concatenate([[0], np.cumsum(cnt)[:-1]]).astype(np.int64)
    iv = np.repeat(np.arange(len(ipt)), cnt)
    k = np.arange(cnt.sum()) - base[iv]
    lo_edge, hi_edge = start + inset, start + width - inset
    ang = lo_edge[iv] + (hi_edge - lo_edge)[iv] * k / n[iv]
    pidx = ipt[iv]

    def trace(pt_idx, angles):
        d = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(len(angles))])
        cls, wface, oface, odist, gdist = trace_through_windows(engine, rg.group, points[pt_idx], d)
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
    for _ in range(n_iter):  # bisection: all transitions of all points at once
        mid = 0.5 * (lo + hi)
        lm = trace(tp, mid)[0]
        same = lm == s_lo
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
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
    out = {
        "angle_deg": np.degrees(angle),
        # full bracket widths plus the end insets: a bound even where float32 rays blur the bracket ends
        "angle_err_deg": np.degrees(np.bincount(tp, hi - lo, p) + np.bincount(ipt, 2 * inset, p)),
        "transitions": np.bincount(tp, minlength=p),
        "rays": np.bincount(pidx, minlength=p) + n_iter * np.bincount(tp, minlength=p),
    }
    if cfg["distance_method"] == "horizontal":
        idx = np.flatnonzero(leave)
        t_l = np.where(engine.layer_of(oface[idx]) == LANDSCAPE, odist[idx], np.inf)
        beyond_ground = np.flatnonzero(engine.layer_of(oface[idx]) == GROUND)
        if len(beyond_ground):  # ground never obstructs: look for landscape behind it
            g = idx[beyond_ground]
            t_l[beyond_ground] = engine.first_hit("landscape", points[pidx[g]], dirs[g])[1]
        nrm = rg.frame_array("n")[rg.window_of_face[wface[idx]]]
        nh = nrm.copy()
        nh[:, 2] = 0.0
        nh /= np.maximum(np.linalg.norm(nh, axis=1, keepdims=True), 1e-12)
        dist = np.full(len(ang), np.nan)
        dist[idx] = (t_l - gdist[idx]) * np.einsum("ij,ij->i", dirs[idx], nh)
        vals, wts = _pad_rows(pidx, dist, weight, p)
        out["distance"], out["distance_gap"] = weighted_statistic(vals, wts, cfg["distance_statistic"])
    return out


def _chunks(rg: RoomGeometry, points: np.ndarray, cfg: dict):
    """Slices of ``points`` holding at most about CELLS_PER_CHUNK base cells each."""
    P = patches(rg, points, np.radians(cfg["angular_resolution_deg"]))
    per_point = np.bincount(P.pt, P.na * P.nb, len(points))
    cum = np.cumsum(per_point)
    cuts = [0]
    while cuts[-1] < len(points):
        nxt = int(np.searchsorted(cum, (cum[cuts[-1] - 1] if cuts[-1] else 0) + CELLS_PER_CHUNK, side="right"))
        cuts.append(min(max(nxt, cuts[-1] + 1), len(points)))
    return [slice(a, b) for a, b in zip(cuts[:-1], cuts[1:])]


def assess_points(engine, rg: RoomGeometry, points: np.ndarray, cfg: dict, thresholds: dict, progress=None) -> dict:
    """Every per-point quantity, level and error estimate for one set of viewpoints (vectorised)."""
    parts = []
    for sl in _chunks(rg, points, cfg):  # chunks bound memory; each chunk is vectorised
        chunk = points[sl]
        sa = solid_angles(engine, rg, chunk, cfg)
        hz = horizontal(engine, rg, chunk, cfg)
        parts.append({**sa, **{("h_" + k): v for k, v in hz.items()}})
        if progress:
            progress(len(chunk))
    r = {k: np.concatenate([q[k] for q in parts]) for k in parts[0]} if parts else {}
    if not parts:
        return {}
    if cfg["distance_method"] == "horizontal":
        dist, gap = r["h_distance"], r["h_distance_gap"]
    else:
        dist, gap = r["distance"], r["distance_gap"]
    thr = cfg["layer_threshold_sr"]
    visible = {k: r[k] > thr for k in ("sky", "landscape", "ground")}
    lv_angle = standard.level_from_value(r["h_angle_deg"], thresholds["horizontal_sight_angle_deg"])
    lv_dist = standard.level_from_value(np.where(np.isnan(dist), -np.inf, dist), thresholds["outside_distance_m"])
    lv_layers = standard.level_from_layers(visible["sky"], visible["landscape"], visible["ground"])
    level = np.minimum(np.minimum(lv_angle, lv_dist), lv_layers)
    near = (
        standard.near_threshold(r["h_angle_deg"], r["h_angle_err_deg"], thresholds["horizontal_sight_angle_deg"])
        | standard.near_threshold(dist, gap, thresholds["outside_distance_m"])
        | np.any([standard.near_threshold(r[k], r["err_" + k], [thr]) for k in ("sky", "landscape", "ground")], axis=0)
    )
    r.update(distance=dist, distance_gap=gap, visible=visible, level_angle=lv_angle, level_distance=lv_dist,
             level_layers=lv_layers, level=level, near=near)
    return r


def assess_room(engine, scene, room, cfg: dict, thresholds: dict, explicit=None, progress=None, planned=None) -> dict:
    """View result of one room: per eye height, per point values, shares and levels.

    ``planned`` is the room's :func:`viewpoints` result when the caller already made it (to size a
    progress bar); otherwise the viewpoints are made here.

    Returns
    -------
    dict with ``eye_heights`` (list of dicts holding numpy arrays), ``level`` (str), ``notes``.
    """
    rg = room_geometry(scene, room, cfg["frame_depth_m"])
    groups, notes = planned if planned is not None else viewpoints(scene, room, cfg, explicit)
    eye = []
    for h, pts in groups:  # one pass per eye height (two by default)
        r = assess_points(engine, rg, pts, cfg, thresholds, progress)
        lv = {}
        share = {}
        for crit, key in (("horizontal_sight_angle", "level_angle"), ("outside_distance", "level_distance"),
                          ("layers", "level_layers"), ("view", "level")):
            level, sh = standard.room_level(r.get(key, []), cfg["area_fraction"])
            lv[crit] = level
            share[crit] = sh
        eye.append({"eye_height_m": h, "points_local": pts, "values": r,
                    "level": min(lv["horizontal_sight_angle"], lv["outside_distance"], lv["layers"]),
                    "level_by_criterion": {k: lv[k] for k in ("horizontal_sight_angle", "outside_distance", "layers")},
                    "share_by_level": share})
    level = min(e["level"] for e in eye) if eye else 0
    return {"eye_heights": eye, "level": level, "notes": notes}

