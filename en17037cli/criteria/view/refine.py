"""The refinement of the solid angle's cells: a mixed cell split in four at its angular midpoints.

:func:`split_cells` traces five new samples per cell (the middle of a side that two split cells
share once: :func:`_twins`), weighs the children exactly (:func:`~en17037cli.criteria.view.cells.clip_weights`)
and hands on the pieces of frame-edge images (:func:`~en17037cli.criteria.view.edges.split_pieces`)
and, for another split, each child's neighbours (:func:`_kid_neighbours`).
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.cells import CHILDREN, KID_T, Cells, clip_weights
from en17037cli.criteria.view.edges import split_pieces
from en17037cli.geometry import corner_solid_angle

#: The neighbours of each child (0-3: lower left, lower right, upper left, upper right) across its
#: bottom, top, left and right side: (0, k) its sibling k, (1, k) child k of its parent's neighbour there.
_KID_NB = (((1, 2), (0, 2), (1, 1), (0, 1)), ((1, 3), (0, 3), (0, 0), (1, 0)),
           ((0, 0), (1, 0), (1, 3), (0, 3)), ((0, 1), (1, 1), (0, 2), (1, 2)))


def _twins(cells: Cells, at: np.ndarray, rest: np.ndarray, X: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def split_cells(sample, cells: Cells, rest: np.ndarray, neighbours: bool = True) -> Cells:
    """Split cells ``rest`` (indices) in four at their angular midpoints; five new samples per cell
    (a side's middle once where the cells on both sides are split); ``neighbours``: find the
    children's (:attr:`~en17037cli.criteria.view.cells.Cells.nb`), for another split.

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
    for q, (_, cor, (i, j)) in enumerate(CHILDREN):
        kid_cls[:4, q * m:(q + 1) * m] = cls[list(cor)]
        if kid_dist is not None:
            kid_dist[:4, q * m:(q + 1) * m] = dist[list(cor)]
        w[q * m:(q + 1) * m] = F[i + 1][j + 1] - F[i][j + 1] - F[i + 1][j] + F[i][j]
    kid_patch = np.tile(patch, 4)
    src, quad = np.tile(np.arange(m), 4), np.repeat(np.arange(4, dtype=np.int8), m)
    tans = lambda sel: tuple(TT[KID_T[quad[sel], :4].T, src[sel]])  # noqa: E731 - the children's bounds, where clipped
    w, full, extra = clip_weights(sample.rg, sample.P, kid_patch, tans, w, np.tile(cells.full[rest], 4))
    at = np.full(len(cells.w), -1, np.int64)
    at[rest] = np.arange(m)
    pc = at[cells.piece_cell]
    keep = pc >= 0
    pc, pxy = split_pieces(pc[keep], cells.piece_xy[keep], Xm, Ym)
    kids = Cells(kid_patch, GG, TT, src, quad, kid_cls, kid_dist, w, full, extra, pc, pxy,
                  nb=_kid_neighbours(cells, at, rest) if neighbours and cells.nb is not None else None)
    if not full.all():
        kids = kids.take(w > 0)
    return kids.sample_extra(sample).sample_probes(sample)


def _kid_neighbours(cells: Cells, at: np.ndarray, rest: np.ndarray) -> np.ndarray:
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
