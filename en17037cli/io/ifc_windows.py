"""Where an IfcWindow's pane lies, taken from the window itself, and panes for windows whose glass
the file does not say.

**The pane's plane** (:func:`window_plane`). A window is a plate: much thinner across its wall
than it is wide or high. Its plane is found from the window, and the element its opening is cut
in only confirms it (a host can mislead: a 13 cm lintel over a window is wider than it is high, so
its faces lie mostly flat; a roof light with no host has nothing else to go by). Candidates: the
three axes of the window's own placement (IFC writes width along x, depth along y, height along z;
other tools turn it as they like), the plane most of its faces lie in, and its host's faces
around it. The window's extent is measured along each; the candidate across which it is thinnest
is its normal where that depth is at most :data:`THIN_RATIO` of its smaller in-plane side. A
window nearly as deep as it is wide (a small window with linings through a thick wall) is
ambiguous: then the candidate whose in-plane sides match the window's OverallWidth x
OverallHeight best (a 0.6 m square window 0.54 m deep matches within 10 % across its width too:
the closer match, across its depth, wins), else its host's faces, else the plane of most of its
faces.

**Panes from geometry** (:func:`panes_from_geometry`): the thin plates in that plane
(:func:`~en17037cli.io.ifc_glazing.pane_faces`), kept only where together they cover at least
:data:`PANE_MIN_OUTLINE_SHARE` of the window's outline (less is a frame's bar or a sill seen
edge-on, not glass); else the holes its frames leave (:func:`~en17037cli.io.ifc_glazing.frame_opening_panes`).

**A window the file gives no geometry** (:func:`opening_pane`): where its IfcOpeningElement is
cut in a wall, the opening's outline in the wall's plane (clipped to the wall) at the wall's
mid-plane is taken as an unglazed pane: no frame, and no glass the file describes.

References: buildingSMART IFC4 ADD2 TC1, IfcWindow (5.1.3.37: OverallWidth, OverallHeight, the
local placement's axes), IfcOpeningElement (6.1.3.13), IfcRelFillsElement (4.5.3.10).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.geometry import triangle_normals, window_axes
from en17037cli.io.ifc_glazing import frame_opening_panes, pane_faces, principal_normal

#: A window is thin across the candidate plane when its depth there is at most this share of its
#: smaller side in the plane (a 1.2 m window 0.45 m deep: 0.38).
THIN_RATIO = 0.5
#: In-plane sides match OverallWidth x OverallHeight within this share of each (or 5 cm).
OUTLINE_MATCH = 0.1
#: Thin plates in the window's plane are its panes only when together they cover at least this
#: share of the window's outline seen across that plane (a sash's glass, not a frame member).
PANE_MIN_OUTLINE_SHARE = 0.2
#: A host whose faces lie within this angle of the window's own plane confirms it [deg].
HOST_AGREES_DEG = 10.0
#: Host faces within this distance of an opening (in its plane) give the wall around it [m].
WALL_NEAR_M = 0.3
#: Host faces within this angle of the opening's plane are the wall's faces [deg].
WALL_PARALLEL_DEG = 10.0


@dataclass(frozen=True)
class Plane:
    """The plane of a window's pane: ``normal`` (3,) unit (either sign), ``how`` it was found (for
    notes), and whether the window's host's faces lie in another plane."""

    normal: np.ndarray
    how: str
    host_disagrees: bool = False


def host_normal(tri: np.ndarray, near: np.ndarray) -> np.ndarray | None:
    """(3,) normal of the host's faces around a window (the wall's plane), from the host's
    triangles ``tri`` (k, 3, 3) [m] whose bounding boxes reach within 0.5 m of the window's
    bounding box ``near`` (2, 3) [m]; area-weighted, so the wall's faces outweigh its reveals."""
    lo, hi = near[0] - 0.5, near[1] + 0.5
    close = np.all((tri.min(axis=1) <= hi) & (tri.max(axis=1) >= lo), axis=1)
    return principal_normal(tri[close]) if close.any() else None


def placement_axes(product, place) -> np.ndarray | None:
    """(3, 3) unit x, y, z axes (columns) of ``product``'s ObjectPlacement in the model's frame
    (``place``: the map conversion applied to vertices [m], affine), or None where it has none."""
    import ifcopenshell.util.placement as ifc_placement

    p = getattr(product, "ObjectPlacement", None)
    if p is None:
        return None
    try:
        m = np.asarray(ifc_placement.get_local_placement(p), dtype=float)[:3, :3]
    except Exception:  # a placement ifcopenshell cannot resolve: the geometry decides
        return None
    pts = place(np.vstack([np.zeros(3), m.T]))
    axes = (pts[1:] - pts[0]).T
    norms = np.linalg.norm(axes, axis=0)
    return None if np.any(norms < 1e-9) else axes / norms


def overall_size(product, unit_m: float) -> tuple[float, float] | None:
    """(OverallWidth, OverallHeight) [m] of an IfcWindow or IfcDoor where the file gives both."""
    w, h = getattr(product, "OverallWidth", None), getattr(product, "OverallHeight", None)
    if not w or not h:
        return None
    return float(w) * unit_m, float(h) * unit_m


def window_plane(vertices: np.ndarray, faces: np.ndarray, axes: np.ndarray | None = None,
                 overall: tuple[float, float] | None = None, host_n: np.ndarray | None = None) -> Plane:
    """The plane of a window's pane (see the module docstring).

    Parameters
    ----------
    vertices : (n, 3) float [m]; faces : (m, 3) int: the window's geometry
    axes : (3, 3) its placement's unit axes (columns), or None
    overall : (OverallWidth, OverallHeight) [m], or None
    host_n : (3,) unit normal of its host's faces around it, or None
    """
    tri = vertices[faces]
    pts = vertices[np.unique(faces)]
    cands: list[tuple[np.ndarray, np.ndarray, np.ndarray, str]] = []
    if axes is not None:
        for k, name in enumerate("xyz"):
            cands.append((axes[:, k], axes[:, (k + 1) % 3], axes[:, (k + 2) % 3], f"its placement's {name} axis"))
    for n, label in ((host_n, "its host's faces"), (principal_normal(tri), "the plane most of its faces lie in")):
        if n is not None:
            n = np.asarray(n, float) / np.linalg.norm(n)
            cands.append((n, *window_axes(n), label))
    dims = np.array([[np.ptp(pts @ n), np.ptp(pts @ u), np.ptp(pts @ w)] for n, u, w, _ in cands])
    k = int(np.argmin(dims[:, 0] + 1e-6 * np.arange(len(cands))))  # the first of equals: the placement's
    depth, side = dims[k, 0], min(dims[k, 1], dims[k, 2])
    if depth <= THIN_RATIO * side:
        how = f"its geometry's thinnest extent ({depth:.2f} m across {dims[k, 1]:.2f} x {dims[k, 2]:.2f} m, along {cands[k][3]})"
    else:
        k = -1
        if overall is not None:
            ow, oh = overall
            tol = lambda a: max(0.05, OUTLINE_MATCH * a)  # noqa: E731
            best = None
            for i, (d, eu, ew) in enumerate(dims):  # a handful of candidates: the one whose sides match best
                for a, b in ((ow, oh), (oh, ow)):
                    if abs(eu - a) <= tol(a) and abs(ew - b) <= tol(b):
                        miss = max(abs(eu - a) / tol(a), abs(ew - b) / tol(b))  # a 0.6 m square 0.54 m deep matches
                        if best is None or (miss, d) < best[:2]:  # across its depth exactly, across its width within 10 %
                            best = (miss, d, i)
            if best is not None:
                k = best[2]
                how = f"its OverallWidth x OverallHeight ({ow:.2f} x {oh:.2f} m, across {cands[k][3]})"
        if k < 0:
            k = next((i for i, c in enumerate(cands) if c[3] == "its host's faces"), len(cands) - 1)
            how = cands[k][3]
    normal = cands[k][0]
    disagrees = host_n is not None and abs(float(normal @ host_n)) < np.cos(np.radians(HOST_AGREES_DEG))
    return Plane(normal, how, disagrees)


def _outline_area(tri: np.ndarray, u: np.ndarray, w: np.ndarray, filled: bool = False) -> float:
    """Area of the union of the triangles (k, 3, 3) projected on (u, w) [m2]; ``filled``: with its
    holes (a frame's openings) counted in."""
    import shapely

    if len(tri) == 0:
        return 0.0
    union = shapely.union_all(shapely.make_valid(shapely.polygons(np.stack([tri @ u, tri @ w], axis=-1))))
    if not filled:
        return float(union.area)
    return float(sum(shapely.Polygon(g.exterior).area for g in getattr(union, "geoms", [union]) if g.geom_type == "Polygon"))


def panes_from_geometry(vertices: np.ndarray, faces: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, float]:
    """The panes of a window whose file says nothing of its glass, in the plane of ``normal``.

    Returns
    -------
    glass : (m,) bool, the faces that are its panes (the thin plates in its plane), all False where
        there are none or they cover less than :data:`PANE_MIN_OUTLINE_SHARE` of its outline
    opening : (k, 3, 3) [m] panes filling the holes its frames leave where it has no pane, or None
    share : the thin plates' share of the outline before that test (0 where there are none)
    """
    glass = pane_faces(vertices, faces, normal)
    share = 0.0
    if glass.any():
        u, w = window_axes(np.asarray(normal, float))
        tri = vertices[faces]
        share = _outline_area(tri[glass], u, w) / max(_outline_area(tri, u, w, filled=True), 1e-12)
        if share < PANE_MIN_OUTLINE_SHARE:
            glass = np.zeros(len(faces), bool)
    opening = None if glass.any() else frame_opening_panes(vertices, faces, normal)
    return glass, opening, share


def opening_pane(op_v: np.ndarray, op_f: np.ndarray, wall: np.ndarray | None, axes: np.ndarray | None = None,
                 overall: tuple[float, float] | None = None) -> np.ndarray | None:
    """(k, 3, 3) [m]: an unglazed pane for a window the file gives no geometry, from the opening it fills.

    The opening's plane is found as a window's is (:func:`window_plane`, the wall's faces around it
    as host); its outline there (the union of its faces seen across the plane), clipped to the
    wall's outline (the convex hull of its faces in that plane) where the wall is given, is triangulated (mapbox-earcut) in the wall's
    mid-plane: halfway between the wall's faces parallel to the plane within
    :data:`WALL_NEAR_M` of the opening, kept within the opening's depth (the opening's middle
    where there are none). None where the opening leaves no area.

    Parameters
    ----------
    op_v : (n, 3) float [m]; op_f : (m, 3) int: the IfcOpeningElement's geometry
    wall : (t, 3, 3) [m] the triangles of the element(s) it is cut in, or None
    axes, overall : the window's (or opening's) placement axes and OverallWidth x OverallHeight [m]
    """
    import shapely

    from en17037cli.io.openings import polygon_triangles_2d

    op_tri = op_v[op_f]
    box = np.array([op_v.min(axis=0), op_v.max(axis=0)])
    near = None
    if wall is not None and len(wall):
        lo, hi = box[0] - WALL_NEAR_M, box[1] + WALL_NEAR_M
        near = wall[np.all((wall.min(axis=1) <= hi) & (wall.max(axis=1) >= lo), axis=1)]
        near = near if len(near) else None
    host_n = None if near is None else principal_normal(near)
    n = window_plane(op_v, op_f, axes, overall, host_n).normal
    u, w = window_axes(n)
    proj = lambda t: shapely.make_valid(shapely.polygons(np.stack([t @ u, t @ w], axis=-1)))  # noqa: E731
    outline = shapely.union_all(proj(op_tri))
    depth = op_v @ n
    d_lo, d_hi = float(depth.min()), float(depth.max())
    mid = 0.5 * (d_lo + d_hi)
    if near is not None:
        normals, areas = triangle_normals(near)
        par = (np.abs(normals @ n) >= np.cos(np.radians(WALL_PARALLEL_DEG))) & (areas > 0)
        if par.any():
            outline = outline.intersection(shapely.union_all(proj(near[par])).convex_hull)
            offs = near[par].reshape(-1, 3) @ n
            mid = float(np.clip(0.5 * (offs.min() + offs.max()), d_lo, d_hi))
    flat = polygon_triangles_2d(shapely.make_valid(outline))
    if len(flat) == 0:
        return None
    return flat[..., :1] * u + flat[..., 1:] * w + mid * n


def openings_of(window) -> list:
    """The IfcOpeningElements a window fills (IfcRelFillsElement)."""
    return [r.RelatingOpeningElement for r in (getattr(window, "FillsVoids", None) or ()) if r.RelatingOpeningElement is not None]


def panes_of_bare_windows(windows: list, shapes, walls: dict, host_of: dict, place, unit_m: float):
    """Panes for IfcWindows the file gives no geometry (:func:`opening_pane`).

    Parameters
    ----------
    windows : the IfcWindows with no shape
    shapes : iterable of (opening product, vertices (n, 3) [m, unplaced], faces) of their openings
    walls : GlobalId -> (vertices [m, placed], faces) of the model's elements
    host_of : window GlobalId -> GlobalIds of the elements its openings are cut in
    place : the map placement of vertices [m]

    Returns
    -------
    panes : (window, triangles (k, 3, 3) [m], host ids) of each window that gets one
    bare : (window, why) of the others
    """
    by_opening = {op.id(): (op, place(v), fc) for op, v, fc in shapes if len(fc)}
    panes, bare = [], []
    for w in windows:  # the windows with no geometry, each with its one or few openings
        ops = openings_of(w)
        host = host_of.get(w.GlobalId, ())
        wall = [walls[h][0][walls[h][1]] for h in host if h in walls]
        tris = []
        for op in ops:
            if op.id() in by_opening:
                _, v, fc = by_opening[op.id()]
                t = opening_pane(v, fc, np.concatenate(wall) if wall else None, placement_axes(w, place),
                                 overall_size(w, unit_m))
                if t is not None:
                    tris.append(t)
        if tris:
            panes.append((w, np.concatenate(tris), host))
        else:
            what = "no geometry in the file (no Representation)" if getattr(w, "Representation", None) is None \
                else "no geometry from ifcopenshell"
            bare.append((w, f"{what}, and {'no IfcOpeningElement with geometry' if ops else 'no IfcOpeningElement'} "
                            "whose outline could stand for it: left out"))
    return panes, bare
