"""Solid angles of sky, landscape and ground seen through a room's windows, adaptively integrated.

Each window is sampled per viewpoint on its gnomonic grid (:mod:`~en17037cli.criteria.view.gnomonic`);
every grid vertex is one ray, shared by the four cells around it, classified by one opaque
first-hit query. Cells weigh their exact solid angle (the rectangle formula, or the clipped polygon
for windows that are not rectangles), so the weights of an unobstructed window add up to its exact
solid angle. Cells whose samples disagree, and cells crossed by the image of a frame edge that is
not on a grid line (:func:`edge_pieces`: a round frame, a diagonal member, a frame whose lines were
thinned), are mixed; mixed cells are split in four, up to ``refine_levels`` times, until each
layer's estimated error is within max(``solid_angle_rel_tolerance`` x its solid angle,
``solid_angle_abs_tolerance_sr``). Error estimate: half the solid angle of the cells still mixed.
Cells crossed by a frame edge's image are also sampled just beside it (:meth:`_Cells.sample_probes`).
A split traces the middle of a side two split cells share once (:func:`_twins`). The caller may
run several calls at once on the engine's threads (``parallel=False``): a point's values depend on
no other point.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from en17037cli.criteria.view.distance import ragged_statistic
from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import Patches, grid_lines, patches
from en17037cli.criteria.view.rays import BLOCKED, GROUND_HIT, LANDSCAPE_HIT, SKY, ViewRays
from en17037cli.criteria.view.results import SolidAngles
from en17037cli.geometry import clipped_solid_angle, corner_solid_angle, in_triangle
from en17037cli.project.settings import ViewSettings


class Sampler:
    """Traces rays from patches' viewpoints through gnomonic coordinates (X, Y) of their windows (or
    their angles, calling it).

    ``parallel``: trace each call's rays on the engine's threads (False: in the calling thread, for
    a caller that already runs one :func:`solid_angles` per thread). The rays :meth:`trace` traces
    add up in :attr:`rays` (its caller counts them into the engine); a call counts its own.
    """

    def __init__(self, view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, P: Patches, with_distance: bool,
                 parallel: bool = True):
        self.view_rays, self.rg, self.P = view_rays, rg, P
        self.points32 = points.astype(np.float32)
        self.U, self.V, self.N = rg.frame_array("u"), rg.frame_array("v"), rg.frame_array("n")
        self.rect = rg.frame_array("is_rectangle")
        self.with_distance = with_distance
        self.parallel = parallel
        self.groups = ["opaque"] if len(rg.frames) == 1 else ["opaque", rg.group]
        view_rays.engine.prepare(self.groups)  # built here, not by two threads at once
        self.per_ray = sum(view_rays.engine.embree_scene(g)[0] is not None for g in self.groups)
        self.rays = 0

    def __call__(self, patch: np.ndarray, A: np.ndarray, B: np.ndarray):
        """:meth:`trace` at gnomonic angles (alpha, beta) [rad] of the patches; the rays counted in the engine."""
        rays = self.rays
        out = self.trace(patch, np.tan(A), np.tan(B))
        self.view_rays.engine.count_rays(self.rays - rays)
        self.rays = rays
        return out

    def trace(self, patch: np.ndarray, X: np.ndarray, Y: np.ndarray):
        """Class of each sample at gnomonic coordinates X = tan(alpha), Y = tan(beta) of its patch
        (-1: outside the window's outline) and perpendicular distance [m] beyond the glazing.

        A sample counts for its window when no opaque face and no nearer window of the room lie
        before the glazing; then :meth:`~en17037cli.criteria.view.rays.ViewRays.outside_class` classifies it.

        Returns
        -------
        cls : (m,) int8; dist : (m,) float [m] (+inf unless landscape), or None without distances
        """
        P, rg = self.P, self.rg
        idx = None
        if not self.rect.all():
            w = P.win[patch]
            inside = self.rect[w].copy()
            for f in rg.frames:  # outline test for windows that are not rectangles
                sel = np.flatnonzero((w == f.index) & ~f.is_rectangle)
                if len(sel):
                    ps = patch[sel]
                    inside[sel] = f.on_glazing(P.x0[ps] + P.d[ps] * X[sel], P.y0[ps] + P.d[ps] * Y[sel])
            idx = np.flatnonzero(inside)
            patch, X, Y = patch[idx], X[idx], Y[idx]
        n = len(patch)
        c = np.empty(n, dtype=np.int8)
        dist = np.empty(n) if self.with_distance else None
        engine, vr = self.view_rays.engine, self.view_rays
        one = len(rg.frames) == 1

        def chunk(a: int, b: int) -> None:  # the rays of [a, b): directions, queries, classes, in one thread
            pa = patch[a:b]
            x, y = X[a:b], Y[a:b]
            secant = np.sqrt(1.0 + x * x + y * y)
            inv = 1.0 / secant
            dirs = np.empty((b - a, 3), dtype=np.float32)  # Embree's precision, built column by column
            if one:
                for k in range(3):  # the three coordinates
                    dirs[:, k] = (x * self.U[0, k] + y * self.V[0, k] + self.N[0, k]) * inv
            else:
                w = P.win[pa]
                for k in range(3):
                    dirs[:, k] = (x * self.U[w, k] + y * self.V[w, k] + self.N[w, k]) * inv
            t_w = P.d[pa] * secant  # distance to the glazing plane [m]
            origins = self.points32[P.pt[pa]]
            f_o, t_o = engine.first_hit_chunk("opaque", origins, dirs)
            cc = vr.outside_class(f_o, dirs)
            cc[t_o <= t_w] = BLOCKED
            if not one:  # a direction counts once, through the nearest window of the room
                f_g, t_g = engine.first_hit_chunk(rg.group, origins, dirs)
                nearer = (f_g >= 0) & (rg.window_of_face[np.maximum(f_g, 0)] != w) & (t_g < t_w * (1 - 1e-6))
                cc[nearer] = BLOCKED
            c[a:b] = cc
            if dist is not None:
                dist[a:b] = np.where(cc == LANDSCAPE_HIT, (t_o - t_w) / secant, np.inf)

        engine.map_chunks(chunk, n, parallel=self.parallel)
        self.rays += n * self.per_ray
        if idx is not None:
            full_c = np.full(len(inside), -1, dtype=np.int8)
            full_c[idx] = c
            c = full_c
            if dist is not None:
                full_d = np.full(len(inside), np.inf)
                full_d[idx] = dist
                dist = full_d
        return c, dist


def _clip_weights(rg: RoomGeometry, P: Patches, patch, tans, weight, full):
    """Exact solid angle [sr] of each cell's part inside its window, and a sample point for cells
    whose corners may all lie outside the window (NaN elsewhere).

    Cells of rectangular windows, and cells already known to lie inside (``full``), keep
    ``weight`` (the rectangle formula); the others are clipped against the window's triangles that
    overlap them (found with an STR tree, so a finely tessellated round window costs no more than
    its overlaps).

    Parameters
    ----------
    tans : ``tans(sel)``, the bounds X0, X1, Y0, Y1 of cells ``sel`` (indices) in gnomonic
        coordinates [-] (tangents of the angles)
    weight : (m,) float [sr], each cell's whole rectangle

    Returns
    -------
    weight (m,) [sr], full (m,) bool, extra (m, 2) [rad] or None where no cell was clipped
    """
    if full.all():
        return weight, full, None
    full = full.copy()
    extra = np.full((len(weight), 2), np.nan)
    w = P.win[patch]
    for f in rg.frames:  # clipping, for windows that are not rectangles
        sel = np.flatnonzero((w == f.index) & ~f.is_rectangle & ~full)
        if len(sel) == 0:
            continue
        wsum, is_full, ex = _clip_cells(f, P, patch[sel], *tans(sel))
        weight[sel] = np.where(is_full, weight[sel], wsum)
        full[sel] = is_full
        extra[sel] = np.where(is_full[:, None], np.nan, ex)
    return weight, full, extra


def _clip_cells(f, P: Patches, ps, x0, x1, y0, y1):
    """Cells (bounds in gnomonic coordinates of their patches ``ps``) clipped against the
    triangles of window frame ``f``: summed solid angle [sr], whether the cell lies inside one
    triangle, and the centroid [rad] of its largest clipped piece (a point surely inside)."""
    n = len(ps)
    d, px, py = P.d[ps], P.x0[ps], P.y0[ps]
    is_full = disjoint = np.zeros(n, dtype=bool)
    if len(f.tri2) > 1:  # cells inside the glazing, or away from it, need no clipping against its many triangles
        is_full, disjoint = f.classify_boxes(px + d * x0, px + d * x1, py + d * y0, py + d * y1)
    rest = np.flatnonzero(~is_full & ~disjoint)
    ci, ti = f.triangle_pairs(px[rest] + d[rest] * x0[rest], px[rest] + d[rest] * x1[rest],
                              py[rest] + d[rest] * y0[rest], py[rest] + d[rest] * y1[rest])
    ci = rest[ci]
    # the overlapping triangles in each cell's gnomonic coordinates
    tri = (f.tri2[ti] - np.stack([px[ci], py[ci]], axis=1)[:, None, :]) / d[ci][:, None, None]
    corners = np.stack([np.stack([x0, y0], 1), np.stack([x1, y0], 1), np.stack([x0, y1], 1), np.stack([x1, y1], 1)], axis=1)
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    overlap = (lo[:, 0] < x1[ci]) & (hi[:, 0] > x0[ci]) & (lo[:, 1] < y1[ci]) & (hi[:, 1] > y0[ci])
    ci, tri = ci[overlap], tri[overlap]
    inside4 = np.ones(len(ci), dtype=bool)
    for j in range(4):  # a cell whose four corners lie in one (convex) triangle lies inside it
        inside4 &= in_triangle(corners[ci, j], tri)
    is_full[ci[inside4]] = True
    part = ~is_full[ci]
    ci, tri = ci[part], tri[part]
    rect = np.column_stack([x0[ci], x1[ci], y0[ci], y1[ci]])
    om, cen = clipped_solid_angle(tri, rect)
    wsum = np.bincount(ci, om, n)
    order = np.lexsort((-om, ci))
    first = order[np.r_[True, ci[order][1:] != ci[order][:-1]]] if len(ci) else order
    ex = np.full((n, 2), np.nan)
    ex[ci[first]] = np.arctan(cen[first])
    return wsum, is_full, ex


#: Sample classes that are layers, with their report keys.
LAYER_CODES = (("sky", SKY), ("landscape", LANDSCAPE_HIT), ("ground", GROUND_HIT))


@dataclass
class _Cells:
    """Sampling cells, one column per cell: bounds and sample positions, their samples' classes, weights.

    Bounds (:meth:`bounds`): ``G`` rows alpha0, alpha1, beta0, beta1 of the cell [rad]; ``T`` rows
    their tangents X0, X1, Y0, Y1 (the cell in gnomonic coordinates [-]), then the gnomonic
    coordinates of the lines its samples lie on, moved inwards on a window's outline. They are
    column ``src`` of ``GG`` and ``TT``, or for the children of a split (``q``: 0-3) rows of their
    parent's (:data:`_CHILDREN`), made only for the cells that need them. ``cls`` rows: corners
    (a0 b0), (a1 b0), (a0 b1), (a1 b1) and one extra sample inside the window for cells with no
    corner in it (-1: none); ``dist`` likewise. ``extra``: (m, 2) the extra sample's angles [rad]
    (NaN: none; None: no cell has one).
    ``piece_cell`` and ``piece_xy``: the pieces of frame-edge images inside each cell (cell index;
    endpoints X0, Y0, X1, Y1 in gnomonic coordinates [-]); a cell with a piece counts as mixed.
    ``probe_cell``, ``probe_cls``, ``probe_dist``: samples just beside those pieces, as many per
    cell as it needs (:meth:`sample_probes`).
    """

    patch: np.ndarray
    GG: np.ndarray
    TT: np.ndarray
    src: np.ndarray
    q: np.ndarray | None
    cls: np.ndarray
    dist: np.ndarray | None
    w: np.ndarray
    full: np.ndarray
    extra: np.ndarray | None
    piece_cell: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    piece_xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    probe_cell: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    probe_cls: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int8))
    probe_dist: np.ndarray | None = None
    #: (4, m) int: the cell of the same size across its bottom, top, left and right side (-1: none
    #: among these cells), for the cells that may be split
    nb: np.ndarray | None = None

    def take(self, sel) -> _Cells:
        sel = np.flatnonzero(sel) if sel.dtype == bool else sel
        new = np.full(len(self.w) + 1, -1, np.int64)  # the last: where -1 (no cell) goes
        new[sel] = np.arange(len(sel))
        pc, qc = new[self.piece_cell], new[self.probe_cell]
        keep, kq = pc >= 0, qc >= 0
        return _Cells(self.patch[sel], self.GG, self.TT, self.src[sel], None if self.q is None else self.q[sel],
                      self.cls[:, sel], None if self.dist is None else self.dist[:, sel], self.w[sel], self.full[sel],
                      None if self.extra is None else self.extra[sel], pc[keep], self.piece_xy[keep], qc[kq],
                      self.probe_cls[kq], None if self.probe_dist is None else self.probe_dist[kq],
                      None if self.nb is None else new[self.nb[:, sel]])

    def bounds(self, sel) -> tuple[np.ndarray, np.ndarray]:
        """``G`` (4, k) and ``T`` (8, k) of cells ``sel`` (indices)."""
        s = self.src[sel]
        if self.q is None:
            return self.GG[:, s], self.TT[:, s]
        q, mp = self.q[sel], self.GG.shape[1]
        return self.GG.ravel()[_KID_G[q].T * mp + s], self.TT.ravel()[_KID_T[q].T * mp + s]

    def tans(self, sel) -> tuple[np.ndarray, ...]:
        """X0, X1, Y0, Y1 of cells ``sel`` (indices) [-]."""
        return tuple(self.bounds(sel)[1][:4])

    def crossed(self) -> np.ndarray:
        """(m,) bool, the cells crossed by the image of a frame edge."""
        out = np.zeros(len(self.w), dtype=bool)
        out[self.piece_cell] = True
        return out

    def sample_extra(self, sample) -> _Cells:
        """Trace a sample inside the window's part of every cell none of whose corners lies in the window."""
        if self.extra is None:
            return self
        need = np.flatnonzero(np.isfinite(self.extra[:, 0]))
        if len(need):
            need = need[np.all(self.cls[:4, need] < 0, axis=0)]
        if len(need):
            c, dd = sample.trace(self.patch[need], np.tan(self.extra[need, 0]), np.tan(self.extra[need, 1]))
            self.cls[4, need] = c
            if self.dist is not None:
                self.dist[4, need] = dd
        return self

    def sample_probes(self, sample) -> _Cells:
        """Trace two probes beside the pieces of frame-edge images in every cell they cross, so that
        a view past an edge through a gap narrower than the cell (a crescent between the two rims
        of a deep round frame) is seen, as the samples on both sides of a frame line see past an
        axis-aligned member.

        Only cells whose other samples agree are probed: the others are mixed and split anyway.
        Probes stand at a piece's midpoint, :data:`PROBE_INSET` of the cell's smaller side (in
        gnomonic coordinates) to either side of it. A cell is divided into :data:`PROBE_BINS` x
        :data:`PROBE_BINS` equal parts in (alpha, beta) and only the longest piece whose midpoint
        falls in each part is probed: the many short pieces of a finely tessellated frame cost
        at most that many probes per cell.
        """
        if len(self.piece_cell) == 0:
            return self
        kinds = self.kinds()
        agree = np.flatnonzero((kinds & (kinds - 1))[self.piece_cell] == 0)
        if len(agree) == 0:
            return self
        xy, pc = self.piece_xy[agree], self.piece_cell[agree]
        d = xy[:, 2:] - xy[:, :2]
        length = np.hypot(d[:, 0], d[:, 1])
        mid = 0.5 * (xy[:, :2] + xy[:, 2:])
        G, T = self.bounds(pc)
        am, bm = np.arctan(mid[:, 0]), np.arctan(mid[:, 1])
        ia = np.clip(((am - G[0]) / (G[1] - G[0]) * PROBE_BINS).astype(np.int64), 0, PROBE_BINS - 1)
        ib = np.clip(((bm - G[2]) / (G[3] - G[2]) * PROBE_BINS).astype(np.int64), 0, PROBE_BINS - 1)
        part = pc * PROBE_BINS * PROBE_BINS + ia * PROBE_BINS + ib
        order = np.lexsort((-length, part))
        first = order[np.r_[True, part[order][1:] != part[order][:-1]]]
        c = pc[first]
        X0, X1, Y0, Y1 = T[0, first], T[1, first], T[2, first], T[3, first]
        step = PROBE_INSET * np.minimum(X1 - X0, Y1 - Y0) / length[first]
        normal = np.column_stack([-d[first, 1], d[first, 0]]) * step[:, None]
        px = np.clip(np.concatenate([mid[first, 0] + normal[:, 0], mid[first, 0] - normal[:, 0]]), np.tile(X0, 2), np.tile(X1, 2))
        py = np.clip(np.concatenate([mid[first, 1] + normal[:, 1], mid[first, 1] - normal[:, 1]]), np.tile(Y0, 2), np.tile(Y1, 2))
        self.probe_cell = np.tile(c, 2)  # the two sides of each piece
        # aimed at (atan px, atan py): the probe's angles, as every sample is placed
        self.probe_cls, self.probe_dist = sample.trace(self.patch[self.probe_cell], np.tan(np.arctan(px)),
                                                       np.tan(np.arctan(py)))
        return self

    def valid_counts(self) -> np.ndarray:
        """(m,) int, per cell: its valid samples (corners, extra, probes)."""
        return _row_sum(self.cls >= 0) + np.bincount(self.probe_cell, self.probe_cls >= 0, len(self.w)).astype(np.int64)

    def counter(self, rows: np.ndarray):
        """``count(code)``: (k,) int, per cell of ``rows`` (indices), its samples (corners, extra,
        probes) of class ``code``, or its valid ones (None)."""
        cls = self.cls[:, rows]
        at = np.full(len(self.w), -1, np.int64)
        at[rows] = np.arange(len(rows))
        pq = at[self.probe_cell]
        on = pq >= 0
        pq, pcls = pq[on], self.probe_cls[on]

        def count(code=None) -> np.ndarray:
            if code is None:
                return _row_sum(cls >= 0) + np.bincount(pq, pcls >= 0, len(rows)).astype(np.int64)
            return _row_sum(cls == code) + np.bincount(pq, pcls == code, len(rows)).astype(np.int64)

        return count

    def kinds(self) -> np.ndarray:
        """(m,) uint8, per cell: bit c set when a sample (corners, extra, probes) has class c."""
        kinds = np.bitwise_or.reduce(_kind_bits(self.cls), axis=0)
        if len(self.probe_cell):
            ok = self.probe_cls >= 0
            np.bitwise_or.at(kinds, self.probe_cell[ok], _kind_bits(self.probe_cls[ok]))
        return kinds


def _row_sum(flags: np.ndarray) -> np.ndarray:
    """(m,) int64: the true flags of each column of (5, m) bool ``flags`` (``flags.sum(axis=0)``, row by row)."""
    f = flags.view(np.uint8)
    return (f[0] + f[1] + f[2] + f[3] + f[4]).astype(np.int64)


def _kind_bits(cls: np.ndarray) -> np.ndarray:
    """1 << c (uint8) for each sample class c, 0 for -1 (no sample): (1 << (c + 1)) >> 1."""
    return np.right_shift(np.left_shift(np.uint8(1), (cls + 1).view(np.uint8)), 1)


#: A cell is probed beside at most one piece of frame-edge image in each of this many parts per axis.
PROBE_BINS = 8
#: Probes stand this fraction of the cell's smaller side from the edge's image.
PROBE_INSET = 1e-2


def _base_cells(sample, P: Patches) -> _Cells:
    """Level-0 cells of every patch, their corner samples traced once each (shared between cells),
    their weights from the corner term of every grid vertex (shared likewise)."""
    la_ptr, la, la_l, la_r, ca_ptr, ca = grid_lines(P.a0, P.a1, P.na, P.frame_pt[0], P.frame_val[0])
    lb_ptr, lb, lb_l, lb_r, cb_ptr, cb = grid_lines(P.b0, P.b1, P.nb, P.frame_pt[1], P.frame_val[1])
    tla, tlb, tca, tcb = np.tan(la), np.tan(lb), np.tan(ca), np.tan(cb)
    m = len(P)
    nca, ncb = np.diff(ca_ptr), np.diff(cb_ptr)
    # samples: every (alpha column, beta column) pair of a patch
    ns = nca * ncb
    sbase = np.concatenate([[0], np.cumsum(ns)[:-1]])
    sp = np.repeat(np.arange(m), ns)
    ia, ib = np.divmod(np.arange(ns.sum()) - sbase[sp], ncb[sp])
    vcls, vdist = sample.trace(sp, tca[ca_ptr[sp] + ia], tcb[cb_ptr[sp] + ib])
    # cells: every (alpha interval, beta interval) pair of a patch
    nva, nvb = np.diff(la_ptr), np.diff(lb_ptr)  # lines per patch
    nla, nlb = nva - 1, nvb - 1
    nc = nla * nlb
    cbase = np.concatenate([[0], np.cumsum(nc)[:-1]])
    cp = np.repeat(np.arange(m), nc)
    i, j = np.divmod(np.arange(nc.sum()) - cbase[cp], nlb[cp])
    li, lj = la_ptr[cp] + i, lb_ptr[cp] + j  # global index of the cell's lower lines
    a_lo, a_hi, b_lo, b_hi = la_r[li], la_l[li + 1], lb_r[lj], lb_l[lj + 1]  # the sample columns of its sides
    # its corner samples: sbase + (alpha column - first) * ncb + (beta column - first) in its patch
    n, nbc = len(cp), ncb[cp]
    s0 = sbase[cp] - ca_ptr[cp] * nbc - cb_ptr[cp]
    sa_lo, sa_hi = a_lo * nbc + s0, a_hi * nbc + s0
    cls = np.empty((5, n), np.int8)
    dist = None if vdist is None else np.empty((5, n))
    for k, corner in enumerate((sa_lo + b_lo, sa_hi + b_lo, sa_lo + b_hi, sa_hi + b_hi)):
        cls[k] = vcls[corner]
        if dist is not None:
            dist[k] = vdist[corner]
    cls[4] = -1
    if dist is not None:
        dist[4] = np.inf
    G = np.stack([la[li], la[li + 1], lb[lj], lb[lj + 1]])
    T = np.stack([tla[li], tla[li + 1], tlb[lj], tlb[lj + 1], tca[a_lo], tca[a_hi], tcb[b_lo], tcb[b_hi]])
    idx = np.arange(n)
    # weights: the corner term at every grid vertex of a patch, combined per cell
    nv = nva * nvb
    vbase = np.concatenate([[0], np.cumsum(nv)[:-1]])
    vp = np.repeat(np.arange(m), nv)
    va, vb = np.divmod(np.arange(nv.sum()) - vbase[vp], nvb[vp])
    F = corner_solid_angle(tla[la_ptr[vp] + va], tlb[lb_ptr[vp] + vb])
    v00 = vbase[cp] + i * nvb[cp] + j
    v10 = v00 + nvb[cp]
    weight = F[v10 + 1] - F[v00 + 1] - F[v10] + F[v00]  # offset_rectangle_solid_angle(X0, X1, Y0, Y1)
    weight, full, extra = _clip_weights(sample.rg, P, cp, lambda sel: tuple(T[:4, sel]), weight, sample.rect[P.win[cp]])
    pc, pxy = edge_pieces(P, la_ptr, la, lb_ptr, lb, cbase, nlb)
    nbc, nac = nlb[cp], nla[cp]
    nb = np.stack([np.where(j > 0, idx - 1, -1), np.where(j < nbc - 1, idx + 1, -1),
                   np.where(i > 0, idx - nbc, -1), np.where(i < nac - 1, idx + nbc, -1)])
    cells = _Cells(cp, G, T, idx, None, cls, dist, weight, full, extra, pc, pxy, nb=nb)
    if not full.all():
        cells = cells.take(weight > 0)
    return cells.sample_extra(sample).sample_probes(sample)


def _rank(ptr, val, q_pt, q_val, right: bool = False) -> np.ndarray:
    """Number of lines of patch ``q_pt`` below ``q_val`` (``right``: at or below), per query.

    ``ptr`` and ``val``: each patch's sorted lines, val[ptr[i]:ptr[i + 1]] [rad]. An exact merge
    (lines and queries sorted together by patch, then value), vectorised over queries.
    """
    n = len(val)
    line_pt = np.repeat(np.arange(len(ptr) - 1), np.diff(ptr))
    is_line = np.r_[np.ones(n, bool), np.zeros(len(q_val), bool)]
    # on equal values, lines sort before queries for ``right`` and after them otherwise
    tie = np.where(is_line, 0 if right else 1, 1 if right else 0)
    order = np.lexsort((tie, np.r_[val, q_val], np.r_[line_pt, q_pt]))
    below = np.cumsum(is_line[order])  # lines up to and including each position
    rank = np.empty(len(order), np.int64)
    rank[order] = below
    return rank[n:] - ptr[q_pt]


#: An image of a frame edge that turns less than this across its length and whose middle lies
#: this close to a grid line lies on the line: the line already bounds the cells on either side,
#: which the edge's image then does not cross [rad]. What it leaves out is at most this wide
#: (under 4e-7 sr over a whole hemisphere); models whose axes are off by round-off (an edge 6e-8
#: rad off level over 0.35 rad) would otherwise flag a run of cells along every transom.
ON_LINE_RAD = 1e-7
#: Pieces of an edge's image shorter than this fraction of it are left out (crossings at a corner).
MIN_PIECE = 1e-12


def edge_pieces(P: Patches, la_ptr, la, lb_ptr, lb, cbase, nlb) -> tuple[np.ndarray, np.ndarray]:
    """The base cells crossed by the images of frame edges (:attr:`Patches.seg`), and the piece of
    the image inside each.

    The gnomonic projection keeps straight lines straight, and a cell [alpha0, alpha1] x [beta0,
    beta1] is the rectangle [tan alpha0, tan alpha1] x [tan beta0, tan beta1] in (X, Y): each
    image is cut where it crosses the grid lines of its patch (found per image by rank among the
    lines, ragged counts by repeat), and each piece falls in the cell of its midpoint. An image on
    a grid line (an axis-aligned edge whose vertices drew the line) crosses no cell.

    Parameters
    ----------
    la_ptr, la, lb_ptr, lb : each patch's grid lines in alpha and beta [rad] (:func:`grid_lines`)
    cbase, nlb : (m,) int, each patch's first base cell and its number of beta intervals

    Returns
    -------
    cell : (q,) int, base cell of each piece; xy : (q, 4) float [-], its endpoints X0, Y0, X1, Y1
    """
    sp, S = P.seg_pt, P.seg
    if len(sp) == 0:
        return np.zeros(0, np.int64), np.zeros((0, 4))
    ang = np.arctan(S)  # alpha0, beta0, alpha1, beta1
    drop = np.zeros(len(sp), dtype=bool)
    for c, ptr, val in ((0, la_ptr, la), (1, lb_ptr, lb)):  # the two axes: images on a grid line
        a0, a1 = ang[:, c], ang[:, c + 2]
        mid = 0.5 * (a0 + a1)
        r = _rank(ptr, val, sp, mid)
        nl = np.diff(ptr)[sp]
        below = val[ptr[sp] + np.clip(r - 1, 0, nl - 1)]
        above = val[ptr[sp] + np.clip(r, 0, nl - 1)]
        near = np.minimum(np.abs(mid - below), np.abs(above - mid))
        drop |= (np.abs(a1 - a0) <= ON_LINE_RAD) & (near <= ON_LINE_RAD)
    keep = np.flatnonzero(~drop)
    sp, S, ang = sp[keep], S[keep], ang[keep]
    k = len(sp)
    # crossings with each axis's lines strictly between the image's ends: parameters along it
    seg_id, par = [np.arange(k), np.arange(k)], [np.zeros(k), np.ones(k)]
    for c, ptr, val in ((0, la_ptr, la), (1, lb_ptr, lb)):
        lo, hi = np.minimum(ang[:, c], ang[:, c + 2]), np.maximum(ang[:, c], ang[:, c + 2])
        first = _rank(ptr, val, sp, lo, right=True)
        n = np.maximum(_rank(ptr, val, sp, hi) - first, 0)
        rows = np.repeat(np.arange(k), n)
        line = ptr[sp[rows]] + first[rows] + (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n))
        seg_id.append(rows)
        par.append((np.tan(val[line]) - S[rows, c]) / (S[rows, c + 2] - S[rows, c]))
    seg_id, par = np.concatenate(seg_id), np.clip(np.concatenate(par), 0.0, 1.0)
    order = np.lexsort((par, seg_id))
    seg_id, par = seg_id[order], par[order]
    nxt = np.flatnonzero((seg_id[1:] == seg_id[:-1]) & (par[1:] - par[:-1] > MIN_PIECE))
    rows, ta, tb = seg_id[nxt], par[nxt, None], par[nxt + 1, None]
    p0, dp = S[rows, :2], S[rows, 2:] - S[rows, :2]
    xy = np.concatenate([p0 + ta * dp, p0 + tb * dp], axis=1)
    mid = np.arctan(p0 + 0.5 * (ta + tb) * dp)
    pt = sp[rows]
    i = np.clip(_rank(la_ptr, la, pt, mid[:, 0], right=True) - 1, 0, np.diff(la_ptr)[pt] - 2)
    j = np.clip(_rank(lb_ptr, lb, pt, mid[:, 1], right=True) - 1, 0, np.diff(lb_ptr)[pt] - 2)
    return cbase[pt] + i * nlb[pt] + j, xy


def _split_pieces(cell, xy, Xm, Ym) -> tuple[np.ndarray, np.ndarray]:
    """Pieces of frame-edge images in cells split at gnomonic coordinates ``Xm``, ``Ym`` (per cell,
    [-]): each piece cut where it crosses the two lines, and each part given to the child of its
    midpoint, numbered as :func:`_split` numbers them (child q of cell c is q m + c)."""
    m = len(Xm)
    if len(cell) == 0:
        return cell, xy
    d = xy[:, 2:] - xy[:, :2]
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = (Xm[cell] - xy[:, 0]) / d[:, 0]
        ty = (Ym[cell] - xy[:, 1]) / d[:, 1]
    tx = np.where((tx > 0) & (tx < 1), tx, np.nan)
    ty = np.where((ty > 0) & (ty < 1), ty, np.nan)
    T = np.sort(np.column_stack([np.zeros(len(cell)), tx, ty, np.ones(len(cell))]), axis=1)  # NaN last
    T = np.where(np.isnan(T), 1.0, T)
    ta, tb = T[:, :3].reshape(-1, 1), T[:, 1:].reshape(-1, 1)
    rows = np.repeat(np.arange(len(cell)), 3)
    ok = (tb - ta)[:, 0] > MIN_PIECE
    rows, ta, tb = rows[ok], ta[ok], tb[ok]
    p0, dp = xy[rows, :2], d[rows]
    mid = p0 + 0.5 * (ta + tb) * dp
    c = cell[rows]
    q = (mid[:, 0] > Xm[c]).astype(np.int64) + 2 * (mid[:, 1] > Ym[c])
    return q * m + c, np.concatenate([p0 + ta * dp, p0 + tb * dp], axis=1)


#: The four children of a cell: for each, its rows of ``T`` as indices into [X0, X1, Y0, Y1, SX0,
#: SX1, SY0, SY1, Xm, Ym] (its rows of ``G``: the first four, Xm and Ym standing for Am and Bm),
#: its corner samples as indices into [parent corners 0-3, new samples 4-8 (bottom, top, left and
#: right edge midpoints, centre)], and its place (i, j) in the 2 x 2 split.
_CHILDREN = (
    ((0, 8, 2, 9, 4, 8, 6, 9), (0, 4, 6, 8), (0, 0)),
    ((8, 1, 2, 9, 8, 5, 6, 9), (4, 1, 8, 7), (1, 0)),
    ((0, 8, 9, 3, 4, 8, 9, 7), (6, 8, 2, 5), (0, 1)),
    ((8, 1, 9, 3, 8, 5, 9, 7), (8, 7, 5, 3), (1, 1)),
)
#: Rows of the parent's [X0, X1, Y0, Y1, SX0, SX1, SY0, SY1, Xm, Ym] and [A0, A1, B0, B1, Am, Bm]
#: that are each child's ``T`` and ``G``.
_KID_T = np.array([rows for rows, _, _ in _CHILDREN])
_KID_G = np.where(_KID_T[:, :4] >= 8, _KID_T[:, :4] - 4, _KID_T[:, :4])


#: The neighbours of each child (0-3: lower left, lower right, upper left, upper right) across its
#: bottom, top, left and right side: (0, k) its sibling k, (1, k) child k of its parent's neighbour there.
_KID_NB = (((1, 2), (0, 2), (1, 1), (0, 1)), ((1, 3), (0, 3), (0, 0), (1, 0)),
           ((0, 0), (1, 0), (1, 3), (0, 3)), ((0, 1), (1, 1), (0, 2), (1, 2)))


def _twins(cells: _Cells, at: np.ndarray, rest: np.ndarray, X: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(twin, source): the new samples of cells ``rest`` that are the same ray as a neighbour's, both
    split now (the middle of the side they share: a cell's bottom and left samples are its
    neighbours' top and right ones), as indices into the 5 m new samples (block k: sample k of
    every cell), and the sample each repeats. ``at``: each cell's place in ``rest`` (-1: not split)."""
    none = np.zeros(0, np.int64)
    if cells.nb is None:
        return none, none
    m = len(rest)
    r = np.arange(m)
    twin, source = [none], [none]
    for side, facing in ((0, 1), (2, 3)):
        n = at[cells.nb[side, rest]]
        ok = n >= 0
        twin.append(side * m + r[ok])
        source.append(facing * m + n[ok])
    t, s = np.concatenate(twin), np.concatenate(source)
    same = (X[t] == X[s]) & (Y[t] == Y[s])  # a side sampled on both sides of a frame line: two rays
    return t[same], s[same]


def _split(sample, cells: _Cells, rest: np.ndarray, neighbours: bool = True) -> _Cells:
    """Split cells ``rest`` (indices) in four at their angular midpoints; five new samples per cell
    (a side's middle once where the cells on both sides are split); ``neighbours``: find the
    children's (:attr:`_Cells.nb`), for another split.

    The children's weights come from the corner term at the 3 x 3 vertices of each cell (the
    numbers of :func:`~en17037cli.geometry.offset_rectangle_solid_angle`, each vertex once).
    """
    m = len(rest)
    patch = cells.patch[rest]
    G, T = cells.bounds(rest)
    Am, Bm = 0.5 * (G[0] + G[1]), 0.5 * (G[2] + G[3])
    Xm, Ym = np.tan(Am), np.tan(Bm)
    # new samples: bottom, top, left, right edge midpoints and the centre; the middle of an edge two
    # children of one cell share, both split, is traced once
    X5, Y5 = np.concatenate([Xm, Xm, T[4], T[5], Xm]), np.concatenate([T[6], T[7], Ym, Ym, Ym])
    at = np.full(len(cells.w) + 1, -1, np.int64)  # the last: where -1 (no cell) goes
    at[rest] = np.arange(m)
    twin, source = _twins(cells, at, rest, X5, Y5)
    kept = np.ones(5 * m, dtype=bool)
    kept[twin] = False
    kept = np.flatnonzero(kept)
    kcls, kdist = sample.trace(np.tile(patch, 5)[kept], X5[kept], Y5[kept])
    ncls = np.empty(5 * m, np.int8)
    ncls[kept] = kcls
    ncls[twin] = ncls[source]
    ndist = None
    if kdist is not None:
        ndist = np.empty(5 * m)
        ndist[kept] = kdist
        ndist[twin] = ndist[source]
    cls = np.concatenate([cells.cls[:4, rest], ncls.reshape(5, m)])
    dist = None if ndist is None else np.concatenate([cells.dist[:4, rest], ndist.reshape(5, m)])
    GG = np.concatenate([G, Am[None], Bm[None]])
    TT = np.concatenate([T, Xm[None], Ym[None]])
    kid_cls = np.full((5, 4 * m), -1, np.int8)
    kid_dist = None if dist is None else np.full((5, 4 * m), np.inf)
    xs, ys = (T[0], Xm, T[1]), (T[2], Ym, T[3])
    F = [[corner_solid_angle(x, y) for y in ys] for x in xs]
    w = np.empty(4 * m)
    for q, (_, cor, (i, j)) in enumerate(_CHILDREN):
        kid_cls[:4, q * m:(q + 1) * m] = cls[list(cor)]
        if kid_dist is not None:
            kid_dist[:4, q * m:(q + 1) * m] = dist[list(cor)]
        w[q * m:(q + 1) * m] = F[i + 1][j + 1] - F[i][j + 1] - F[i + 1][j] + F[i][j]
    kid_patch = np.tile(patch, 4)
    src, quad = np.tile(np.arange(m), 4), np.repeat(np.arange(4, dtype=np.int8), m)
    tans = lambda sel: tuple(TT[_KID_T[quad[sel], :4].T, src[sel]])  # noqa: E731 - the children's bounds, where clipped
    w, full, extra = _clip_weights(sample.rg, sample.P, kid_patch, tans, w, np.tile(cells.full[rest], 4))
    at = np.full(len(cells.w), -1, np.int64)
    at[rest] = np.arange(m)
    pc = at[cells.piece_cell]
    keep = pc >= 0
    pc, pxy = _split_pieces(pc[keep], cells.piece_xy[keep], Xm, Ym)
    kids = _Cells(kid_patch, GG, TT, src, quad, kid_cls, kid_dist, w, full, extra, pc, pxy,
                  nb=_kid_neighbours(cells, at, rest) if neighbours and cells.nb is not None else None)
    if not full.all():
        kids = kids.take(w > 0)
    return kids.sample_extra(sample).sample_probes(sample)


def _kid_neighbours(cells: _Cells, at: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """(4, 4 m) int: the neighbours of the children of cells ``rest`` (:data:`_KID_NB`)."""
    m = len(rest)
    r = np.arange(m)
    outer = at[cells.nb[:, rest]]  # each parent's neighbours among the cells split (-1: none)
    nb = np.empty((4, 4 * m), np.int64)
    for q, sides in enumerate(_KID_NB):
        for side, (across, k) in enumerate(sides):
            nb[side, q * m:(q + 1) * m] = k * m + (outer[side] if across else r)
            if across:
                nb[side, q * m:(q + 1) * m][outer[side] < 0] = -1
    return nb


def solid_angles(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings,
                 parallel: bool = True) -> SolidAngles:
    """Solid angle of sky, landscape and ground seen through the room's windows from each point.

    Parameters
    ----------
    points : (p, 3) float [m], local frame
    parallel : trace on the engine's threads (False: in the calling thread, for a caller that runs
        one call per thread); the results are the same

    Returns
    -------
    SolidAngles, per point; with ``distance_m`` for the ``solid_angle`` distance method (the
    perpendicular distance (delta_1 - delta_0) r . n of Brembilla et al. (2021) eq. (1) over the
    leaving cells, weighted by solid angle)
    """
    p = len(points)
    out = {key: np.zeros(p) for key in ("sky", "landscape", "ground", "glazing", "err_sky", "err_landscape", "err_ground")}
    out["cells"] = np.zeros(p, dtype=int)
    P = patches(rg, points, np.radians(settings.angular_resolution_deg))
    with_dist = settings.distance_method == "solid_angle"
    sample = Sampler(view_rays, rg, points, P, with_dist, parallel)
    dist_rows, dist_w, dist_p = [], [], []
    cells = _base_cells(sample, P) if len(P.pt) else None
    rel, abs_ = settings.solid_angle_rel_tolerance, settings.solid_angle_abs_tolerance_sr
    for level in range(settings.refine_levels + 1):
        if cells is None or len(cells.w) == 0:
            break
        pi, w, cls = P.pt[cells.patch], cells.w, cells.cls
        kinds = cells.kinds()
        mixed = ((kinds & (kinds - 1)) != 0) | cells.crossed()  # samples that disagree, or a frame edge's image
        mi = np.flatnonzero(mixed)
        count = cells.counter(mi)
        nvalid = np.maximum(count(), 1)  # of the mixed cells
        # share of each layer: 1 or 0 in a pure cell, the share of its samples in a mixed one
        share = {}
        for key, code in LAYER_CODES:
            s = (kinds == (1 << code)).astype(float)
            s[mi] = count(code) / nvalid
            share[key] = s
        # Error control: a point stops refining once every layer's estimated error (half the
        # solid angle of its mixed cells) is within max(rel * layer solid angle, abs).
        # (At the last level every cell is final.)
        last = level == settings.refine_levels
        done = np.ones(p, dtype=bool)
        pm, half_m, kinds_m = pi[mi], 0.5 * w[mi], kinds[mi]  # the mixed cells (the others add 0 to an error)
        for key, code in ([] if last else LAYER_CODES):
            est = out["err_" + key] + np.bincount(pm, half_m * ((kinds_m >> code) & 1), p)
            value = out[key] + np.bincount(pi, w * share[key], p)
            done &= est <= np.maximum(rel * value, abs_)
        final = slice(None) if last else np.flatnonzero(~mixed | done[pi])
        fm = slice(None) if last else np.flatnonzero(done[pm])  # the final ones among the mixed
        fp, fw = pi[final], w[final]
        out["glazing"] += np.bincount(fp, fw, p)
        out["cells"] += np.bincount(fp, minlength=p)
        for key, code in LAYER_CODES:
            out[key] += np.bincount(fp, fw * share[key][final], p)
            out["err_" + key] += np.bincount(pm[fm], half_m[fm] * ((kinds_m[fm] >> code) & 1), p)
        if with_dist:  # each valid sample of a final cell carries an equal share of its weight
            nv_all = np.maximum(cells.valid_counts(), 1)
            c = cls[:, final].T  # (cells, samples), in the cells' order
            ok = (c >= 0) & (c != BLOCKED)
            sw = (fw / nv_all[final])[:, None] * ok
            r, col = np.nonzero(sw > 0)
            dist_rows.append(cells.dist[:, final].T[r, col])
            dist_w.append(sw[r, col])
            dist_p.append(fp[r])
            is_final = np.zeros(len(w), dtype=bool)
            is_final[final] = True
            if cells.probe_dist is not None:  # and its probes'
                q = np.flatnonzero(is_final[cells.probe_cell] & (cells.probe_cls >= 0) & (cells.probe_cls != BLOCKED))
                qc = cells.probe_cell[q]
                dist_rows.append(cells.probe_dist[q])
                dist_w.append(w[qc] / nv_all[qc])
                dist_p.append(pi[qc])
        if not last:
            rest = np.ones(len(w), dtype=bool)
            rest[final] = False
            if not rest.any():
                break
            cells = _split(sample, cells, np.flatnonzero(rest), neighbours=level + 1 < settings.refine_levels)
    view_rays.engine.count_rays(sample.rays)
    dist = gap = None
    if with_dist:
        dist, gap = ragged_statistic(np.concatenate(dist_p) if dist_p else np.zeros(0, int),
                                     np.concatenate(dist_rows) if dist_rows else np.zeros(0),
                                     np.concatenate(dist_w) if dist_w else np.zeros(0), p, settings.distance_statistic)
    return SolidAngles(sr={k: out[k] for k, _ in LAYER_CODES}, err_sr={k: out["err_" + k] for k, _ in LAYER_CODES},
                       glazing_sr=out["glazing"], cells=out["cells"], distance_m=dist, distance_gap_m=gap)
