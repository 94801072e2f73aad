"""Triangles from the flat surface arrays of :mod:`~en17037cli.io.cityjson.builder`, in numpy.

A surface is an outer ring and optional inner rings (holes). Surfaces without holes are
ear-clipped in their best-fit (Newell) plane, all surfaces of one vertex count together
(:func:`en17037cli.geometry.triangulate_polygons`); triangles are taken as they are. Surfaces with
holes get their planes and projections all at once too, and mapbox-earcut runs once per surface
with the hole indices. A surface whose triangles cover less than 99.9 % of its area
(self-intersecting, degenerate) is counted; so is one whose outer ring has fewer than 3 vertices.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry import triangulate_polygons
from en17037cli.geometry.triangles import plane_bases


def triangulate_surfaces(vertices, gidx, ring_len, s_nrings, surf_keep):
    """Triangles of the kept surfaces, the surface of each, and what could not be triangulated.

    Parameters
    ----------
    vertices : (n, 3) float [m]
    gidx : (v,) int, global vertex index of every ring vertex, rings one after the other
    ring_len : (r,) int, each ring's vertex count
    s_nrings : (s,) int, each surface's ring count (its first ring the outer one)
    surf_keep : (s,) bool, the surfaces to triangulate

    Returns
    -------
    triangles : (t, 3) int64, global vertex indices
    surface : (t,) int64, the surface of each triangle
    n_degenerate : how many kept surfaces were dropped for having fewer than 3 vertices
    n_failed : how many surfaces' triangles cover less than 99.9 % of their area
    """
    ring_start = np.cumsum(ring_len) - ring_len
    first_ring = np.cumsum(s_nrings) - s_nrings
    has_ring = s_nrings > 0
    outer_len = np.zeros(len(s_nrings), dtype=np.int64)
    outer_len[has_ring] = ring_len[first_ring[has_ring]]
    valid = surf_keep & has_ring & (outer_len >= 3)
    n_degenerate = int((surf_keep & ~(has_ring & (outer_len >= 3))).sum())
    holes = valid & (s_nrings > 1)
    simple = valid & ~holes
    out_t, out_s = [], []
    n_failed = 0
    for k in np.unique(outer_len[simple]):
        rows = np.flatnonzero(simple & (outer_len == k))
        idx = gidx[ring_start[first_ring[rows]][:, None] + np.arange(k)]
        if k == 3:
            out_t.append(idx)
            out_s.append(rows)
            continue
        pts = vertices[idx]
        local = triangulate_polygons(pts)
        counts = np.fromiter(map(len, local), dtype=np.int64, count=len(local))
        poly = np.repeat(np.arange(len(rows)), counts)
        loc = np.concatenate(local) if len(local) else np.zeros((0, 3), dtype=np.int64)
        t = idx[poly[:, None], loc]
        n_failed += _count_lost_area(pts, vertices[t], poly, len(rows))
        out_t.append(t)
        out_s.append(rows[poly])
    if holes.any():
        rows = np.flatnonzero(holes)
        t, surf, lost = _triangulate_with_holes(vertices, gidx, ring_start, ring_len, first_ring, s_nrings, rows)
        n_failed += lost
        out_t.append(t)
        out_s.append(surf)
    if not out_t:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64), n_degenerate, n_failed
    return np.concatenate(out_t).astype(np.int64), np.concatenate(out_s).astype(np.int64), n_degenerate, n_failed


def _newell_area(polys: np.ndarray) -> np.ndarray:
    """Area [m^2] of (n, k, 3) planar polygons from the Newell normal, computed about each centroid."""
    c = polys - polys.mean(axis=1, keepdims=True)
    return 0.5 * np.linalg.norm(np.cross(c, np.roll(c, -1, axis=1)).sum(axis=1), axis=1)


def _count_lost_area(polys: np.ndarray, tri_pts: np.ndarray, poly: np.ndarray, n: int) -> int:
    """How many polygons' triangles cover less than 99.9 % of the polygon's area (ear clipping gave up)."""
    area = _newell_area(polys)
    tri_area = 0.5 * np.linalg.norm(np.cross(tri_pts[:, 1] - tri_pts[:, 0], tri_pts[:, 2] - tri_pts[:, 0]), axis=1)
    covered = np.bincount(poly, weights=tri_area, minlength=n)
    return int((covered < area * (1 - 1e-3) - 1e-9).sum())


def _triangulate_with_holes(vertices, gidx, ring_start, ring_len, first_ring, s_nrings, rows):
    """Ear-clip surfaces with holes, each in the best-fit (Newell) plane of its outer ring.

    The planes, the 2D projections and the areas are computed for all the surfaces at once;
    mapbox-earcut then runs once per surface with the ring ends (its hole indices).

    Parameters
    ----------
    vertices : (n, 3) float [m]
    gidx : (v,) int, global vertex index of every ring vertex, rings one after the other
    ring_start, ring_len : (r,) int, each ring's offset into ``gidx`` and vertex count
    first_ring, s_nrings : (s,) int, each surface's first ring and ring count
    rows : (h,) int, the surfaces to triangulate (two or more rings each)

    Returns
    -------
    triangles : (t, 3) int, global vertex indices
    surface : (t,) int, the surface (a value of ``rows``) of each triangle
    lost : how many surfaces' triangles cover less than 99.9 % of their area
    """
    import mapbox_earcut

    nr = s_nrings[rows]
    ring = np.repeat(first_ring[rows] - np.cumsum(nr) + nr, nr) + np.arange(nr.sum())  # ring ids, surface by surface
    ring_surf = np.repeat(np.arange(len(rows)), nr)
    is_outer = np.r_[True, ring_surf[1:] != ring_surf[:-1]]
    ok = is_outer | (ring_len[ring] >= 3)  # inner rings with fewer than 3 vertices are no holes
    ring, ring_surf, is_outer = ring[ok], ring_surf[ok], is_outer[ok]
    lens = ring_len[ring]
    off = np.cumsum(lens) - lens
    ids = gidx[np.repeat(ring_start[ring] - off, lens) + np.arange(lens.sum())]
    pts = vertices[ids]
    vert_ring = np.repeat(np.arange(len(ring)), lens)
    centre = np.add.reduceat(pts, off, axis=0) / lens[:, None]
    nxt = np.arange(len(pts)) + 1
    nxt[off + lens - 1] = off
    c = pts - centre[vert_ring]
    newell = np.add.reduceat(np.cross(c, c[nxt]), off, axis=0)  # (rings, 3): twice the area vector
    ring_area = 0.5 * np.linalg.norm(newell, axis=1)
    outer = np.flatnonzero(is_outer)
    n, u, v, good = plane_bases(newell[outer])
    vert_surf = ring_surf[vert_ring]
    d = pts - centre[outer][vert_surf]
    flat = np.stack([np.einsum("ij,ij->i", d, u[vert_surf]), np.einsum("ij,ij->i", d, v[vert_surf])], axis=1)
    s_off = off[outer]
    s_end = np.r_[s_off[1:], len(pts)]
    r_end = off + lens  # ring ends, global; minus the surface's offset gives earcut's ring_end_indices
    r_bounds = np.r_[outer, len(ring)]
    out = []
    for i in np.flatnonzero(good):
        a = s_off[i]
        loc = mapbox_earcut.triangulate_float64(flat[a:s_end[i]], (r_end[r_bounds[i]:r_bounds[i + 1]] - a).astype(np.uint32))
        out.append(loc.astype(np.int64) + a)
    loc = np.concatenate(out).reshape(-1, 3) if out else np.zeros((0, 3), dtype=np.int64)
    tri_surf = vert_surf[loc[:, 0]]
    tp = pts[loc]
    tri_area = 0.5 * np.linalg.norm(np.cross(tp[:, 1] - tp[:, 0], tp[:, 2] - tp[:, 0]), axis=1)
    covered = np.bincount(tri_surf, weights=tri_area, minlength=len(rows))
    want = np.bincount(ring_surf, weights=np.where(is_outer, ring_area, -ring_area), minlength=len(rows))
    lost = int((good & (covered < want * (1 - 1e-3) - 1e-9)).sum())
    return ids[loc], rows[tri_surf], lost
