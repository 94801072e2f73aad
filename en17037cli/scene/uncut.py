"""Windows set in walls the file does not cut: the opening cut along the window's outline, through
the wall's thickness, with a note (as the DXF reader cuts windows drawn on their walls).

An export that writes no IfcOpeningElement (Vectorworks 2013), or one cut short of the wall's
depth (an opening 0.1 m into a 0.4 m wall), leaves the wall's faces over the glass: no ray from the
room can pass, and the room would FAIL with 0 h on a modelling error. The case is told from a real
obstruction by where the opaque faces lie: a window's wall is an element whose faces parallel to
the glass cover at least :data:`COVER_SHARE` of it within :data:`WALL_DEPTH_M` of it, and which
either is the window's host (the file's IfcRelFillsElement names it: its opening does not go
through) or covers the glass on both sides (the glass lies inside its thickness). A neighbour's
wall metres away, a facade in front of the glass that is not its host: not the window's wall, left
as drawn (the preflight names what blocks and how far it lies; a blocked window whose obstruction
lies within a wall's thickness withholds its room's verdict: :mod:`en17037cli.preflight`).

Why cut rather than quarantine: the intent is plain (a window inside a wall's thickness is set in
it; nobody draws glass inside solid concrete), the cut gives the geometry a correct export gives
(the IfcOpeningElement of a window is its outline through the wall), so one building gives one
answer whether or not its exporter cuts openings, and the user, who cannot edit a received IFC,
gets a result. Reveals are added along the cut (the faces of the hole through the wall), so the
wall still shades the glass at grazing angles as an opening cut by the file would. Glass lying on
a wall's face (within 1 mm) is another case, left to the quarantine
(:func:`~en17037cli.scene.windows.check_glazing_over_opaque`): there the window's place in the
wall is not known.

Keyed windows only (``Part.window``: an IfcWindow, a door's or a plate's glazing): their element's
outline and host are known; and panes only, glazing no thicker than
:data:`~en17037cli.scene.windows.MAX_GLAZING_THICKNESS_M` across (a door whose "glass" is a box the
wall's depth is not a pane set in the wall). Vertices are in the file's units (``unit_m`` [m] each).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from en17037cli.geometry import triangle_normals, window_axes
from en17037cli.io.mesh import Mesh
from en17037cli.io.openings import plane_basis, polygon_triangles_2d
from en17037cli.scene.windows import MAX_GLAZING_THICKNESS_M, coplanar_clusters, describe_part

#: A window's wall lies within this distance of its glass [m] (the thickest walls read: 0.45 m of
#: concrete; old masonry to 0.6 m).
WALL_DEPTH_M = 0.6
#: The wall's faces cover at least this share of the glass (seen across its plane) on a side ...
COVER_SHARE = 0.5
#: ... are parallel to it within this angle [deg] ...
PARALLEL_DEG = 10.0
#: ... and lie farther than this from its plane [m] (closer: glass drawn on the wall's face, the
#: quarantine's case).
ON_FACE_M = 1e-3
#: A direction of a window's glazing faces is a pane's when its area is at least this share of the
#: largest direction's (a corner window's two panes; not the rims of glass modelled as a thin solid).
PANE_DIRECTION_SHARE = 0.25


def _proj(tri: np.ndarray, u: np.ndarray, w: np.ndarray):
    import shapely

    return shapely.make_valid(shapely.polygons(np.stack([tri @ u, tri @ w], axis=-1)))


def _filled(geom):
    import shapely

    return shapely.union_all([shapely.Polygon(g.exterior) for g in getattr(geom, "geoms", [geom])
                              if g.geom_type == "Polygon" and not g.is_empty] or [shapely.Polygon()])


def _walls_of(tri, normals, opaque_ok, elem, host, glass_tri, own_tri, n, unit_m):
    """Where one direction of a window's panes (normal ``n``, glass ``glass_tri``, its element's
    triangles ``own_tri``) lies in an uncut wall: (walls, hole, cut, depths, g, u, w), or None.

    walls : ids of the elements that are its wall (module docstring); hole : shapely polygon in the
    (u, w) axes of the plane, the window's outline where those walls lie; cut : the wall faces it
    cuts; depths : (min, max) of those faces' planes at the hole about the glass's plane ``g`` along
    ``n`` [file units]."""
    import shapely

    u, w = window_axes(n)
    g = float(np.median(glass_tri.reshape(-1, 3) @ n))
    glass = shapely.union_all(_proj(glass_tri, u, w))
    area = float(glass.area)
    if area <= 0:
        return None
    depth = WALL_DEPTH_M / unit_m
    lo, hi = glass_tri.reshape(-1, 3).min(axis=0) - depth, glass_tri.reshape(-1, 3).max(axis=0) + depth
    near = opaque_ok & np.all((tri.min(axis=1) <= hi) & (tri.max(axis=1) >= lo), axis=1)
    near &= np.abs(normals @ n) >= np.cos(np.radians(PARALLEL_DEG))
    idx = np.flatnonzero(near)
    if len(idx) == 0:
        return None
    off = tri[idx].mean(axis=1) @ n - g
    cover = shapely.area(shapely.intersection(_proj(tri[idx], u, w), glass))
    levels = np.unique(glass_tri.mean(axis=1) @ n - g)  # the glass's planes: both faces of a thin solid
    on_face = np.min(np.abs(off[:, None] - levels[None, :]), axis=1) <= ON_FACE_M / unit_m
    if cover[on_face].sum() > COVER_SHARE * area:
        return None  # glass drawn on a wall's face: the quarantine's case
    idx, off = idx[~on_face & (np.abs(off) <= depth)], off[~on_face & (np.abs(off) <= depth)]
    walls = []
    for e in sorted(set(elem[idx])):  # the few elements near one window
        sides = [float(shapely.union_all(_proj(tri[idx[(elem[idx] == e) & (s * off > 0)]], u, w)).intersection(glass).area)
                 / area for s in (1.0, -1.0)]
        if max(sides) >= COVER_SHARE and (e in host or min(sides) >= COVER_SHARE):
            walls.append(e)
    if not walls:
        return None
    mine = idx[np.isin(elem[idx], walls)]
    hole = _filled(shapely.union_all(_proj(own_tri, u, w))).intersection(shapely.union_all(_proj(tri[mine], u, w)))
    hole = shapely.make_valid(hole)
    if hole.area <= 0:
        return None
    cut = mine[shapely.area(shapely.intersection(_proj(tri[mine], u, w), hole)) > 1e-9 * area]
    c = np.asarray(hole.centroid.coords[0])
    at = c[0] * u + c[1] * w  # the hole's centre in the plane through the origin: each face's depth there
    nf = normals[cut]
    d = (np.einsum("ij,ij->i", nf, tri[cut, 0]) - nf @ at) / (nf @ n) - g
    return walls, hole, cut, (float(d.min()), float(d.max())), g, u, w


def _reveals(hole, u, w, n, g, d) -> np.ndarray:
    """(k, 3, 3): the faces of the hole's sides from depth g + d[0] to g + d[1] along n."""
    rings = [np.asarray(r.coords)[:-1] for p in getattr(hole, "geoms", [hole]) if p.geom_type == "Polygon"
             for r in (p.exterior, *p.interiors)]
    out = []
    for r in rings:  # a hole has one ring, or a few
        a, b = r, np.roll(r, -1, axis=0)
        pa, pb = a[:, :1] * u + a[:, 1:] * w, b[:, :1] * u + b[:, 1:] * w
        p0, p1, q0, q1 = (pa + (g + d[0]) * n, pb + (g + d[0]) * n, pa + (g + d[1]) * n, pb + (g + d[1]) * n)
        out += [np.stack([p0, p1, q1], axis=1), np.stack([p0, q1, q0], axis=1)]
    return np.concatenate(out) if out else np.zeros((0, 3, 3))


def cut_uncut_walls(mesh: Mesh, part_layer: np.ndarray, window_code: int, unit_m: float, name: str) -> Mesh:
    """The mesh with each keyed window's uncut wall cut along the window's outline, through its
    thickness, with reveals; its parts' host set to that wall where the file names none; a note.

    Parameters
    ----------
    part_layer : (parts,) int layer code of each part (-1 ignore); window_code : the window layer's code
    unit_m : [m] one unit of the mesh's vertices; name : the file, for the note
    """
    import shapely

    parts = mesh.parts
    keys = sorted({p.window for i, p in enumerate(parts) if p.window and part_layer[i] == window_code})
    if not keys:
        return mesh
    tri = mesh.vertices[mesh.triangles]
    normals, areas = triangle_normals(tri)
    face_layer = part_layer[mesh.part]
    opaque = (face_layer >= 0) & (face_layer != window_code)
    ids = np.array([p.attrs.get("id") or f"part {i}" for i, p in enumerate(parts)], dtype=object)
    elem = ids[mesh.part]
    holes: dict[int, list] = {}  # wall face -> hole rings (3D, in the glass's plane)
    reveals, reveal_part, done, hosts = [], [], [], {}
    for key in keys:  # one window element at a time
        glazing = [i for i, p in enumerate(parts) if p.window == key and part_layer[i] == window_code]
        asm = {parts[i].assembly for i in glazing} - {None}
        own = np.array([ids[i] == key or (p.assembly is not None and p.assembly in asm) for i, p in enumerate(parts)])
        host = {h for i in glazing for h in parts[i].host} | asm
        gf = np.flatnonzero(np.isin(mesh.part, glazing))
        ok = opaque & ~own[mesh.part]
        outline = np.flatnonzero(np.isin(mesh.part, [i for i in range(len(parts)) if ids[i] == key] + glazing))
        rep = coplanar_clusters(normals[gf], tri[gf].mean(axis=1), np.inf)
        dirs = np.unique(rep)
        rep_area = {r: float(areas[gf[rep == r]].sum()) for r in dirs}
        for r in dirs:  # one direction of the window's panes (one, or a corner window's two); not a thin solid's rims
            if rep_area[r] < PANE_DIRECTION_SHARE * max(rep_area.values()):
                continue
            sel = gf[rep == r]
            n = normals[sel[np.argmax(areas[sel])]]
            if np.ptp(tri[sel].reshape(-1, 3) @ n) > MAX_GLAZING_THICKNESS_M / unit_m:
                continue  # not a pane: a volume of glass (a door's glazing drawn as a box the wall's depth)
            found = _walls_of(tri, normals, ok, elem, host, tri[sel], tri[outline], n, unit_m)
            if found is None:
                continue
            walls, hole, cut, d, g, u, w = found
            for p in getattr(hole, "geoms", [hole]):
                if p.geom_type != "Polygon":
                    continue
                ring = np.asarray(p.exterior.coords)[:-1]
                for f in cut:
                    holes.setdefault(int(f), []).append(ring[:, :1] * u + ring[:, 1:] * w + g * n)
            rv = _reveals(hole, u, w, n, g, d)
            reveals.append(rv)
            reveal_part.append(np.full(len(rv), mesh.part[cut[0]]))
            wall_parts = [i for i in range(len(parts)) if ids[i] in walls]
            done.append(f"{describe_part(parts[glazing[0]])} in {', '.join(describe_part(parts[i]) for i in wall_parts[:1])}")
            if not host:
                hosts[key] = tuple(sorted(walls))
    if not done:
        return mesh
    drop = np.zeros(len(tri), bool)
    new_v, new_part = [], []
    for f, rings in holes.items():  # each wall face once, with the holes of every window cut in it
        c, nf, uf, vf, good = plane_basis(tri[f])
        if not good:
            continue
        to2 = lambda p, c=c, uf=uf, vf=vf: np.stack([(p - c) @ uf, (p - c) @ vf], axis=-1)  # noqa: E731
        rest = shapely.difference(shapely.make_valid(shapely.Polygon(to2(tri[f]))),
                                  shapely.union_all([shapely.make_valid(shapely.Polygon(to2(r))) for r in rings]))
        t2 = polygon_triangles_2d(rest)
        if len(t2):
            t3 = c + t2[..., :1] * uf + t2[..., 1:] * vf
            flip = np.einsum("ij,j->i", np.cross(t3[:, 1] - t3[:, 0], t3[:, 2] - t3[:, 0]), nf) < 0
            t3[flip] = t3[flip][:, ::-1]
            new_v.append(t3.reshape(-1, 3))
            new_part.append(np.full(len(t3), mesh.part[f]))
        drop[f] = True
    for rv, rp in zip(reveals, reveal_part):
        new_v.append(rv.reshape(-1, 3))
        new_part.append(rp)
    nv = np.concatenate(new_v) if new_v else np.zeros((0, 3))
    added = np.arange(len(nv)).reshape(-1, 3) + len(mesh.vertices)
    new_parts = [replace(p, host=hosts[p.window]) if p.window in hosts and not p.host else p for p in parts]
    note = (f"{name}: {len(done)} window(s) set in a wall the file does not cut (their glass within the wall's thickness, "
            f"its faces over the glass): the opening cut along each window's outline through the wall, with reveals: "
            + "; ".join(done[:5]) + (f" and {len(done) - 5} more" if len(done) > 5 else ""))
    return replace(mesh, vertices=np.concatenate([mesh.vertices, nv]), triangles=np.concatenate([mesh.triangles[~drop], added]),
                   part=np.concatenate([mesh.part[~drop], *new_part]), parts=new_parts, notes=[*mesh.notes, note])
