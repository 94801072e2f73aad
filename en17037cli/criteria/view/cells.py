"""The solid angle's sampling cells: their bounds, samples, classes and exact weights.

:class:`Cells` holds the cells of one level of refinement, one column per cell; :func:`base_cells`
makes the level-0 cells of every patch (:mod:`~en17037cli.criteria.view.gnomonic`), their corner
samples traced once each and shared between cells (:class:`~en17037cli.criteria.view.sampler.Sampler`),
their weights the exact solid angle of each cell (the rectangle formula, or the cell clipped against
a window that is not a rectangle: :func:`clip_weights`). Cells crossed by a frame edge's image
(:mod:`~en17037cli.criteria.view.edges`) are probed beside it (:meth:`Cells.sample_probes`). The
split of mixed cells in four is :mod:`~en17037cli.criteria.view.refine`.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from en17037cli.criteria.view.clip import clip_cells
from en17037cli.criteria.view.edges import edge_pieces
from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import Patches, grid_lines
from en17037cli.geometry import corner_solid_angle


def clip_weights(rg: RoomGeometry, P: Patches, patch, tans, weight, full):
    """Exact solid angle [sr] of each cell's part inside its window, and a sample point for cells
    whose corners may all lie outside the window (NaN elsewhere).

    Cells of rectangular windows, and cells already known to lie inside (``full``), keep
    ``weight`` (the rectangle formula); the others are clipped against their window's outline
    (:func:`~en17037cli.criteria.view.clip.clip_cells`).

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
        weight[sel], full[sel], extra[sel] = clip_cells(f, P, patch[sel], *tans(sel), weight[sel])
    return weight, full, extra


#: The four children of a cell: for each, its rows of ``T`` as indices into [X0, X1, Y0, Y1, SX0,
#: SX1, SY0, SY1, Xm, Ym] (its rows of ``G``: the first four, Xm and Ym standing for Am and Bm),
#: its corner samples as indices into [parent corners 0-3, new samples 4-8 (bottom, top, left and
#: right edge midpoints, centre)], and its place (i, j) in the 2 x 2 split.
CHILDREN = (
    ((0, 8, 2, 9, 4, 8, 6, 9), (0, 4, 6, 8), (0, 0)),
    ((8, 1, 2, 9, 8, 5, 6, 9), (4, 1, 8, 7), (1, 0)),
    ((0, 8, 9, 3, 4, 8, 9, 7), (6, 8, 2, 5), (0, 1)),
    ((8, 1, 9, 3, 8, 5, 9, 7), (8, 7, 5, 3), (1, 1)),
)
#: Rows of the parent's [X0, X1, Y0, Y1, SX0, SX1, SY0, SY1, Xm, Ym] and [A0, A1, B0, B1, Am, Bm]
#: that are each child's ``T`` and ``G``.
KID_T = np.array([rows for rows, _, _ in CHILDREN])
KID_G = np.where(KID_T[:, :4] >= 8, KID_T[:, :4] - 4, KID_T[:, :4])


@dataclass
class Cells:
    """Sampling cells, one column per cell: bounds and sample positions, their samples' classes, weights.

    Bounds (:meth:`bounds`): ``G`` rows alpha0, alpha1, beta0, beta1 of the cell [rad]; ``T`` rows
    their tangents X0, X1, Y0, Y1 (the cell in gnomonic coordinates [-]), then the gnomonic
    coordinates of the lines its samples lie on, moved inwards on a window's outline. They are
    column ``src`` of ``GG`` and ``TT``, or for the children of a split (``q``: 0-3) rows of their
    parent's (:data:`CHILDREN`), made only for the cells that need them. ``cls`` rows: corners
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

    def take(self, sel) -> Cells:
        sel = np.flatnonzero(sel) if sel.dtype == bool else sel
        new = np.full(len(self.w) + 1, -1, np.int64)  # the last: where -1 (no cell) goes
        new[sel] = np.arange(len(sel))
        pc, qc = new[self.piece_cell], new[self.probe_cell]
        keep, kq = pc >= 0, qc >= 0
        return Cells(self.patch[sel], self.GG, self.TT, self.src[sel], None if self.q is None else self.q[sel],
                      self.cls[:, sel], None if self.dist is None else self.dist[:, sel], self.w[sel], self.full[sel],
                      None if self.extra is None else self.extra[sel], pc[keep], self.piece_xy[keep], qc[kq],
                      self.probe_cls[kq], None if self.probe_dist is None else self.probe_dist[kq],
                      None if self.nb is None else new[self.nb[:, sel]])

    def compact(self) -> Cells:
        """The same cells with only the columns of ``GG`` and ``TT`` they use (after :meth:`take`
        of a few cells of many: a level's bounds are 96 bytes a cell)."""
        used, src = np.unique(self.src, return_inverse=True)
        if len(used) == self.GG.shape[1]:
            return self
        return dataclasses.replace(self, GG=self.GG[:, used], TT=self.TT[:, used], src=src.astype(np.int64))

    def bounds(self, sel) -> tuple[np.ndarray, np.ndarray]:
        """``G`` (4, k) and ``T`` (8, k) of cells ``sel`` (indices)."""
        s = self.src[sel]
        if self.q is None:
            return self.GG[:, s], self.TT[:, s]
        q, mp = self.q[sel], self.GG.shape[1]
        return self.GG.ravel()[KID_G[q].T * mp + s], self.TT.ravel()[KID_T[q].T * mp + s]

    def tans(self, sel) -> tuple[np.ndarray, ...]:
        """X0, X1, Y0, Y1 of cells ``sel`` (indices) [-]."""
        return tuple(self.bounds(sel)[1][:4])

    def crossed(self) -> np.ndarray:
        """(m,) bool, the cells crossed by the image of a frame edge."""
        out = np.zeros(len(self.w), dtype=bool)
        out[self.piece_cell] = True
        return out

    def sample_extra(self, sample) -> Cells:
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

    def sample_probes(self, sample) -> Cells:
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


def base_cells(sample, P: Patches) -> Cells:
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
    weight, full, extra = clip_weights(sample.rg, P, cp, lambda sel: tuple(T[:4, sel]), weight, sample.rect[P.win[cp]])
    pc, pxy = edge_pieces(P, la_ptr, la, lb_ptr, lb, cbase, nlb)
    nbc, nac = nlb[cp], nla[cp]
    nb = np.stack([np.where(j > 0, idx - 1, -1), np.where(j < nbc - 1, idx + 1, -1),
                   np.where(i > 0, idx - nbc, -1), np.where(i < nac - 1, idx + nbc, -1)])
    cells = Cells(cp, G, T, idx, None, cls, dist, weight, full, extra, pc, pxy, nb=nb)
    if not full.all():
        cells = cells.take(weight > 0)
    return cells.sample_extra(sample).sample_probes(sample)
