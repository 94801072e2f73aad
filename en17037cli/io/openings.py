"""Openings cut from the faces they are drawn on: a planar polygon minus its openings, triangulated.

Formats that draw a wall whole and its windows on top of it, in its plane (gbXML surfaces and
their ``Opening`` children, EnergyPlus's DXF output), need the opening cut from the wall before
rays are traced: otherwise the wall hides the glazing. Both operations work in the plane of the
host face: project to 2D (an orthonormal basis of the plane), subtract with shapely, ear-clip
with mapbox-earcut (outer ring and holes), lift back onto the plane.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry.triangles import plane_bases

#: A drawn opening lies within this distance of its host face's plane, in model units of metres [m].
PLANE_TOLERANCE_M = 1e-3


def _earcut(poly) -> tuple[np.ndarray, np.ndarray]:
    """(k, 2) points and (t, 3) triangles of a shapely Polygon (with holes) by mapbox-earcut."""
    import mapbox_earcut

    rings = [np.asarray(poly.exterior.coords)[:-1]] + [np.asarray(r.coords)[:-1] for r in poly.interiors]
    rings = [r for r in rings if len(r) >= 3]
    if not rings:
        return np.zeros((0, 2)), np.zeros((0, 3), dtype=np.int64)
    pts = np.concatenate(rings)
    ends = np.cumsum([len(r) for r in rings]).astype(np.uint32)
    tri = mapbox_earcut.triangulate_float64(pts, ends).astype(np.int64).reshape(-1, 3)
    return pts, tri


def polygon_triangles_2d(geom) -> np.ndarray:
    """(t, 3, 2) triangles [same units as the input] covering a shapely (Multi)Polygon, holes left open."""
    out = []
    for poly in getattr(geom, "geoms", [geom]):
        if poly.geom_type != "Polygon" or poly.is_empty or poly.area <= 0:
            continue
        pts, tri = _earcut(poly)
        if len(tri):
            out.append(pts[tri])
    return np.concatenate(out) if out else np.zeros((0, 3, 2))


def plane_basis(ring: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
    """(origin (3,), n, u, v) of the best-fit (Newell) plane of a (k, 3) ring, and whether it has an area."""
    c = ring.mean(axis=0)
    d = ring - c
    newell = np.cross(d, np.roll(d, -1, axis=0)).sum(axis=0)
    n, u, v, good = plane_bases(newell[None])
    return c, n[0], u[0], v[0], bool(good[0])


def polygon_minus_openings(outer: np.ndarray, openings: list[np.ndarray],
                           tolerance: float = PLANE_TOLERANCE_M) -> tuple[np.ndarray, int]:
    """Triangles (t, 3, 3) of a planar polygon with the openings drawn on it cut out, and how many
    openings were cut (those lying within ``tolerance`` of its plane and overlapping it).

    Parameters
    ----------
    outer : (k, 3) float [m], the host face's ring (not repeated at the end)
    openings : list of (j, 3) float [m] rings drawn on it
    tolerance : float [m], how far off the host's plane an opening may lie (it is projected onto it)

    Returns
    -------
    triangles : (t, 3, 3) float [m] on the host's plane, the outer ring's turn kept (normal as Newell's)
    cut : int, openings subtracted
    """
    import shapely

    c, n, u, v, good = plane_basis(outer)
    if not good:
        return np.zeros((0, 3, 3)), 0
    to2 = lambda p: np.column_stack([(p - c) @ u, (p - c) @ v])  # noqa: E731
    host = shapely.make_valid(shapely.Polygon(to2(outer)))
    cut = 0
    holes = []
    for o in openings:
        if len(o) < 3 or np.abs((o - c) @ n).max() > tolerance:
            continue
        h = shapely.make_valid(shapely.Polygon(to2(o)))
        if h.area > 0 and host.intersects(h) and host.intersection(h).area > 1e-9:
            holes.append(h)
            cut += 1
    if holes:
        host = shapely.difference(host, shapely.union_all(holes))
    t2 = polygon_triangles_2d(host)
    t3 = c + t2[..., :1] * u + t2[..., 1:] * v
    if len(t3):  # earcut turns triangles as it likes: give each the outer ring's normal
        flip = np.einsum("ij,j->i", np.cross(t3[:, 1] - t3[:, 0], t3[:, 2] - t3[:, 0]), n) < 0
        t3[flip] = t3[flip][:, ::-1]
    return t3, cut


def cut_openings(vertices: np.ndarray, triangles: np.ndarray, part: np.ndarray, window_part: np.ndarray,
                 opaque_part: np.ndarray, tolerance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Cut every window drawn on a coplanar opaque face out of that face.

    Window triangles are grouped by plane; for each plane, the opaque triangles whose three
    vertices lie within ``tolerance`` of it and whose area overlaps the windows there lose that
    overlap (the rest re-triangulated, their part kept). One shapely difference per affected face.

    Parameters
    ----------
    vertices : (n, 3) float, model units; triangles : (m, 3) int; part : (m,) int
    window_part, opaque_part : (parts,) bool, which parts are glazing and which opaque (others untouched)
    tolerance : float, model units: how far from a window's plane an opaque face may lie

    Returns
    -------
    vertices, triangles, part : the new mesh (new vertices appended; untouched faces keep their indices)
    windows_cut : how many window planes cut an opaque face
    """
    import shapely

    win = np.flatnonzero(window_part[part])
    opq = np.flatnonzero(opaque_part[part])
    if len(win) == 0 or len(opq) == 0:
        return vertices, triangles, part, 0
    wt = vertices[triangles[win]]
    wn = np.cross(wt[:, 1] - wt[:, 0], wt[:, 2] - wt[:, 0])
    norm = np.linalg.norm(wn, axis=1)
    ok = norm > 0
    wn = np.where(ok[:, None], wn / np.where(ok, norm, 1.0)[:, None], 0.0)
    sign = np.where((wn[:, 0] < 0) | ((wn[:, 0] == 0) & (wn[:, 1] < 0)) | ((wn[:, 0] == 0) & (wn[:, 1] == 0) & (wn[:, 2] < 0)), -1.0, 1.0)
    wn = wn * sign[:, None]  # one orientation per plane
    wd = np.einsum("ij,ij->i", wn, wt[:, 0])
    key = np.column_stack([np.round(wn, 3), np.round(wd / max(tolerance, 1e-12))])
    _, group = np.unique(key[ok], axis=0, return_inverse=True)
    group = group.ravel()
    ot = vertices[triangles[opq]]
    drop = np.zeros(len(triangles), dtype=bool)
    new_v, new_part = [], []
    windows_cut = 0
    for g in range(int(group.max()) + 1 if len(group) else 0):  # one pass per window plane
        rows = np.flatnonzero(ok)[group == g]
        n, d = wn[rows[0]], wd[rows[0]]
        near = np.all(np.abs(ot @ n - d) <= tolerance, axis=1) & ~drop[opq]
        if not near.any():
            continue
        _, u, v, _ = plane_bases(n[None])
        u, v = u[0], v[0]
        origin = n * d
        to2 = lambda p, o=origin, u=u, v=v: np.stack([(p - o) @ u, (p - o) @ v], axis=-1)  # noqa: E731
        glass = shapely.union_all(shapely.make_valid(shapely.polygons(to2(wt[rows]))))
        faces = shapely.make_valid(shapely.polygons(to2(ot[near])))
        overlap = shapely.area(shapely.intersection(faces, glass))
        hit = np.flatnonzero(near)[overlap > 1e-9 * max(float(glass.area), 1e-12)]
        if len(hit) == 0:
            continue
        windows_cut += 1
        for i in hit:  # the affected faces only
            rest = shapely.difference(shapely.make_valid(shapely.Polygon(to2(ot[i]))), glass)
            t2 = polygon_triangles_2d(rest)
            if len(t2):
                t3 = origin + t2[..., :1] * u + t2[..., 1:] * v
                own = np.cross(ot[i, 1] - ot[i, 0], ot[i, 2] - ot[i, 0])
                flip = np.einsum("ij,j->i", np.cross(t3[:, 1] - t3[:, 0], t3[:, 2] - t3[:, 0]), own) < 0
                t3[flip] = t3[flip][:, ::-1]
                new_v.append(t3.reshape(-1, 3))
                new_part.append(np.full(len(t3), part[opq[i]]))
            drop[opq[i]] = True
    if not drop.any():
        return vertices, triangles, part, windows_cut
    nv = np.concatenate(new_v) if new_v else np.zeros((0, 3))
    added = np.arange(len(nv)).reshape(-1, 3) + len(vertices)
    keep = ~drop
    return (np.concatenate([vertices, nv]), np.concatenate([triangles[keep], added]),
            np.concatenate([part[keep], *new_part]) if new_part else part[keep], windows_cut)
