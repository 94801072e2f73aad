"""The images of frame edges in the solid angle's cells.

A cell whose samples all agree may still be crossed by the image of a frame edge that is not on a
grid line (a round frame, a diagonal member, a frame whose lines were thinned): the view may change
inside it. :func:`edge_pieces` finds, for the base cells, the piece of each edge's image inside each
cell it crosses; :func:`split_pieces` hands the pieces on to the children of a split
(:func:`~en17037cli.criteria.view.refine.split_cells`). A cell with a piece counts as mixed.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.gnomonic import Patches


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
    """The base cells crossed by the images of frame edges (:attr:`~en17037cli.criteria.view.gnomonic.Patches.seg`), and the piece of
    the image inside each.

    The gnomonic projection keeps straight lines straight, and a cell [alpha0, alpha1] x [beta0,
    beta1] is the rectangle [tan alpha0, tan alpha1] x [tan beta0, tan beta1] in (X, Y): each
    image is cut where it crosses the grid lines of its patch (found per image by rank among the
    lines, ragged counts by repeat), and each piece falls in the cell of its midpoint. An image on
    a grid line (an axis-aligned edge whose vertices drew the line) crosses no cell.

    Parameters
    ----------
    la_ptr, la, lb_ptr, lb : each patch's grid lines in alpha and beta [rad] (:func:`~en17037cli.criteria.view.gnomonic.grid_lines`)
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


def split_pieces(cell, xy, Xm, Ym) -> tuple[np.ndarray, np.ndarray]:
    """Pieces of frame-edge images in cells split at gnomonic coordinates ``Xm``, ``Ym`` (per cell,
    [-]): each piece cut where it crosses the two lines, and each part given to the child of its
    midpoint, numbered as :func:`~en17037cli.criteria.view.refine.split_cells` numbers them (child q
    of cell c is q m + c)."""
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
