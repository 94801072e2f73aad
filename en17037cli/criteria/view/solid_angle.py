"""Solid angles of sky, landscape and ground seen through a room's windows, adaptively integrated.

Each window is sampled per viewpoint on its gnomonic grid (:mod:`~en17037cli.criteria.view.gnomonic`);
every grid vertex is one ray, shared by the four cells around it, classified by one opaque
first-hit query. Cells weigh their exact solid angle (the rectangle formula, or the clipped polygon
for windows that are not rectangles), so the weights of an unobstructed window add up to its exact
solid angle. Cells whose samples disagree are split in four, up to ``refine_levels`` times, until
each layer's estimated error is within max(``solid_angle_rel_tolerance`` x its solid angle,
``solid_angle_abs_tolerance_sr``). Error estimate: half the solid angle of the cells still mixed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.criteria.view.distance import ragged_statistic
from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import Patches, grid_lines, patches
from en17037cli.criteria.view.rays import BLOCKED, GROUND_HIT, LANDSCAPE_HIT, SKY, ViewRays
from en17037cli.criteria.view.results import SolidAngles
from en17037cli.geometry import clipped_solid_angle, in_triangle, offset_rectangle_solid_angle
from en17037cli.project.settings import ViewSettings


class Sampler:
    """Traces rays from patches' viewpoints through gnomonic angles (alpha, beta) of their windows."""

    def __init__(self, view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, P: Patches, with_distance: bool):
        self.view_rays, self.rg, self.P = view_rays, rg, P
        self.points32 = points.astype(np.float32)
        self.U, self.V, self.N = rg.frame_array("u"), rg.frame_array("v"), rg.frame_array("n")
        self.rect = rg.frame_array("is_rectangle")
        self.with_distance = with_distance

    def __call__(self, patch: np.ndarray, A: np.ndarray, B: np.ndarray):
        """Class of each sample (-1: outside the window's outline) and perpendicular distance [m] beyond the glazing.

        A sample counts for its window when no opaque face and no nearer window of the room lie
        before the glazing; then :meth:`~en17037cli.criteria.view.rays.ViewRays.outside_class` classifies it.

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
                    inside[sel] = f.on_glazing(P.x0[ps] + P.d[ps] * X[sel], P.y0[ps] + P.d[ps] * Y[sel])
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
        f_o, t_o = self.view_rays.engine.first_hit("opaque", origins, dirs)
        c = self.view_rays.outside_class(f_o, dirs)
        c[t_o <= t_w] = BLOCKED
        if len(rg.frames) > 1:  # a direction counts once, through the nearest window of the room
            f_g, t_g = self.view_rays.engine.first_hit(rg.group, origins, dirs)
            nearer = (f_g >= 0) & (rg.window_of_face[np.maximum(f_g, 0)] != w) & (t_g < t_w * (1 - 1e-6))
            c[nearer] = BLOCKED
        dist = None
        if self.with_distance:
            dist = np.where(c == LANDSCAPE_HIT, (t_o - t_w) / secant, np.inf)
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
    rectangle formula; the others are clipped against the window's triangles that overlap them
    (found with an STR tree, so a finely tessellated round window costs no more than its overlaps).

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
        wsum, is_full, ex = _clip_cells(f, P, patch[sel], X0[sel], X1[sel], Y0[sel], Y1[sel])
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

    def take(self, sel) -> _Cells:
        return _Cells(self.patch[sel], self.G[sel], self.cls[sel], None if self.dist is None else self.dist[sel],
                      self.w[sel], self.full[sel], self.extra[sel])

    def sample_extra(self, sample) -> _Cells:
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
    la_ptr, la, la_l, la_r, ca_ptr, ca = grid_lines(P.a0, P.a1, P.na, P.frame_pt[0], P.frame_val[0])
    lb_ptr, lb, lb_l, lb_r, cb_ptr, cb = grid_lines(P.b0, P.b1, P.nb, P.frame_pt[1], P.frame_val[1])
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


def solid_angles(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings) -> SolidAngles:
    """Solid angle of sky, landscape and ground seen through the room's windows from each point.

    Parameters
    ----------
    points : (p, 3) float [m], local frame

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
    sample = Sampler(view_rays, rg, points, P, with_dist)
    dist_rows, dist_w, dist_p = [], [], []
    cells = _base_cells(sample, P) if len(P.pt) else None
    rel, abs_ = settings.solid_angle_rel_tolerance, settings.solid_angle_abs_tolerance_sr
    for level in range(settings.refine_levels + 1):
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
        last = level == settings.refine_levels
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
    dist = gap = None
    if with_dist:
        dist, gap = ragged_statistic(np.concatenate(dist_p) if dist_p else np.zeros(0, int),
                                     np.concatenate(dist_rows) if dist_rows else np.zeros(0),
                                     np.concatenate(dist_w) if dist_w else np.zeros(0), p, settings.distance_statistic)
    return SolidAngles(sr={k: out[k] for k, _ in LAYER_CODES}, err_sr={k: out["err_" + k] for k, _ in LAYER_CODES},
                       glazing_sr=out["glazing"], cells=out["cells"], distance_m=dist, distance_gap_m=gap)
