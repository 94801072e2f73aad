"""The solid angle's cells of a window that is not a rectangle, clipped to its glazing exactly.

A cell is an axis-aligned box in the window's plane (its gnomonic rectangle seen from its patch's
viewpoint). Its weight is the solid angle of the part of it that is glazing:

- a **convex** outline (a triangle, a round or arched pane, however finely tessellated): a box lies
  inside exactly when its four corners do and apart when a separating axis says so
  (:func:`~en17037cli.geometry.boxes_vs_convex`); any other box is clipped by the outline's edges
  whose lines cross it, and only those (a convex polygon is the intersection of its half-planes,
  and a half-plane whose line misses the box holds all of it): one or two edges for a cell on the
  rim of a 56-sided round pane, where the triangles of its tessellation overlap it many times;
- **any other** outline (panes joined into one window, a frame's notches, slivers between
  triangles): the window's triangles, which do not overlap (:func:`~en17037cli.criteria.view.frames.window_frame`
  unions overlapping glass), meet each box in convex pieces whose solid angles add up; a box inside
  one triangle is whole, one meeting no triangle's box is empty, the others are clipped triangle by
  triangle. The (box, triangle) pairs come from a vectorised test of their bounding boxes (an STR
  tree for windows of many triangles), never from a geometry library per box.

Weights are exact to round-off in both cases (the Van Oosterom-Strackee formula of each convex
piece's fan); a box whose pieces add up to its whole rectangle counts as whole.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.gnomonic import Patches
from en17037cli.geometry import clipped_solid_angle, in_triangle
from en17037cli.geometry.planar import clip_line
from en17037cli.geometry.solid_angle import polygon_solid_angle

#: Windows of at most this many triangles pair boxes with triangles by brute force (boxes x
#: triangles comparisons of bounding boxes, in blocks); more go through an STR tree.
BRUTE_TRIANGLES = 256
#: Box-triangle comparisons per block of the brute-force pairing (bounds memory).
PAIR_BLOCK = 4_000_000
#: A box whose pieces add up to its rectangle's solid angle within this fraction of it is whole.
WHOLE_REL = 1e-9


def clip_cells(f, P: Patches, ps, x0, x1, y0, y1, whole):
    """Cells (bounds in gnomonic coordinates of their patches ``ps``) against window frame ``f``.

    Parameters
    ----------
    f : :class:`~en17037cli.criteria.view.frames.WindowFrame`, not a rectangle
    x0, x1, y0, y1 : (n,) float [-], gnomonic bounds; whole : (n,) float [sr], each rectangle's solid angle

    Returns
    -------
    weight : (n,) float [sr], the glazing's part; is_full : (n,) bool, the cell is all glazing;
    ex : (n, 2) float [rad], the centroid of its largest piece (NaN where it is whole or empty)
    """
    d, px, py = P.d[ps], P.x0[ps], P.y0[ps]
    bx0, bx1, by0, by1 = px + d * x0, px + d * x1, py + d * y0, py + d * y1  # the boxes in the plane [m]
    hp = f._halfplanes()
    if len(hp):
        return _convex(f, hp, d, px, py, (bx0, bx1, by0, by1), (x0, x1, y0, y1), whole)
    return _by_triangles(f, d, px, py, (bx0, bx1, by0, by1), (x0, x1, y0, y1), whole)


def _convex(f, hp, d, px, py, box, gbox, whole):
    """A convex outline: classify every box, clip the others by the half-planes crossing them."""
    from en17037cli.criteria.view.frames import ON_OUTLINE_M
    from en17037cli.geometry import boxes_vs_convex

    n = len(d)
    bx0, bx1, by0, by1 = box
    inside, apart = boxes_vs_convex(hp, (f.xmin, f.xmax, f.ymin, f.ymax), bx0, bx1, by0, by1, ON_OUTLINE_M)
    weight = np.where(inside, whole, 0.0)
    ex = np.full((n, 2), np.nan)
    rest = np.flatnonzero(~inside & ~apart)
    if len(rest) == 0:
        return weight, inside, ex
    a, b, c = hp[:, 0], hp[:, 1], hp[:, 2]
    r0, r1, r2, r3 = (v[rest, None] for v in box)
    lo = np.minimum(a * r0, a * r1) + np.minimum(b * r2, b * r3) + c  # (rest, e): the half-planes' values
    cross = lo < 0  # over the box's corners: those whose line crosses it, or that hold none of it
    rows, cols = np.nonzero(cross)
    # the rectangle of each clipped cell in gnomonic coordinates, counterclockwise
    g0, g1, g2, g3 = (v[rest] for v in gbox)
    poly = np.zeros((len(rest), 4, 2))
    poly[:, :, 0] = np.stack([g0, g1, g1, g0], axis=1)
    poly[:, :, 1] = np.stack([g2, g2, g3, g3], axis=1)
    count = np.full(len(rest), 4)
    # each crossing half-plane in the gnomonic coordinates of its cell's patch: a (px + d X) + b (py + d Y) + c
    dd, qx, qy = d[rest][rows], px[rest][rows], py[rest][rows]
    hg = np.column_stack([a[cols] * dd, b[cols] * dd, a[cols] * qx + b[cols] * qy + c[cols]])
    rank = np.arange(len(rows)) - np.searchsorted(rows, rows)  # the crossing's place among its cell's
    for j in range(int(rank.max()) + 1 if len(rank) else 0):  # one clip per crossing edge a cell has
        sel = rank == j
        cells = rows[sel]
        sub, cnt = clip_line(poly[cells], count[cells], hg[sel])
        if sub.shape[1] > poly.shape[1]:
            poly = np.concatenate([poly, np.zeros((len(poly), sub.shape[1] - poly.shape[1], 2))], axis=1)
        poly[cells, :sub.shape[1]] = sub
        count[cells] = cnt
    om, cen = polygon_solid_angle(poly, count)
    weight[rest] = om
    ex[rest] = np.arctan(cen)
    return weight, inside, ex


def _pairs(f, bx0, bx1, by0, by1) -> tuple[np.ndarray, np.ndarray]:
    """(box, triangle) pairs whose bounding boxes meet (touching included), sorted by box."""
    tri = f.tri2
    if len(tri) > BRUTE_TRIANGLES:
        return f.triangle_pairs(bx0, bx1, by0, by1)
    tlo, thi = tri.min(axis=1), tri.max(axis=1)  # (k, 2)
    out_b, out_t = [], []
    step = max(1, PAIR_BLOCK // max(len(tri), 1))
    for s in range(0, len(bx0), step):  # blocks of boxes: bounded memory
        e = slice(s, s + step)
        meet = ((bx0[e, None] <= thi[None, :, 0]) & (bx1[e, None] >= tlo[None, :, 0])
                & (by0[e, None] <= thi[None, :, 1]) & (by1[e, None] >= tlo[None, :, 1]))
        q, t = np.nonzero(meet)
        out_b.append(q + s)
        out_t.append(t)
    return (np.concatenate(out_b), np.concatenate(out_t)) if out_b else (np.zeros(0, np.int64), np.zeros(0, np.int64))


def _by_triangles(f, d, px, py, box, gbox, whole):
    """Any outline: the pieces of each box in the window's triangles, added up."""
    n = len(d)
    bx0, bx1, by0, by1 = box
    x0, x1, y0, y1 = gbox
    ci, ti = _pairs(f, bx0, bx1, by0, by1)
    # the paired triangles in each cell's gnomonic coordinates
    tri = (f.tri2[ti] - np.stack([px[ci], py[ci]], axis=1)[:, None, :]) / d[ci][:, None, None]
    corners = np.stack([np.stack([x0, y0], 1), np.stack([x1, y0], 1), np.stack([x0, y1], 1), np.stack([x1, y1], 1)], axis=1)
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    overlap = (lo[:, 0] < x1[ci]) & (hi[:, 0] > x0[ci]) & (lo[:, 1] < y1[ci]) & (hi[:, 1] > y0[ci])
    ci, tri = ci[overlap], tri[overlap]
    inside4 = np.ones(len(ci), dtype=bool)
    for j in range(4):  # a cell whose four corners lie in one (convex) triangle lies inside it
        inside4 &= in_triangle(corners[ci, j], tri)
    is_full = np.zeros(n, dtype=bool)
    is_full[ci[inside4]] = True
    part = ~is_full[ci]
    ci, tri = ci[part], tri[part]
    om, cen = clipped_solid_angle(tri, np.column_stack([x0[ci], x1[ci], y0[ci], y1[ci]]))
    wsum = np.bincount(ci, om, n)
    whole_sum = ~is_full & (np.abs(wsum - whole) <= WHOLE_REL * whole)  # pieces in several triangles that fill it
    is_full |= whole_sum
    weight = np.where(is_full, whole, wsum)
    order = np.lexsort((-om, ci))
    first = order[np.r_[True, ci[order][1:] != ci[order][:-1]]] if len(ci) else order
    ex = np.full((n, 2), np.nan)
    ex[ci[first]] = np.arctan(cen[first])
    ex[is_full] = np.nan
    return weight, is_full, ex
