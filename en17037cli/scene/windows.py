"""Windows: glazing faces grouped into openings, and the modelling check on glazing over an uncut wall."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import points_in_triangles, triangle_normals, window_axes
from en17037cli.geometry.topology import connected_components, shared_edges, weld
from en17037cli.io.mesh import Part
from en17037cli.scene.model import WINDOW, Window

#: Window faces whose normals differ by less than this are coplanar [deg] ...
COPLANAR_ANGLE_DEG = 1.0
#: ... and whose planes are closer than this [m].
COPLANAR_OFFSET_M = 1e-3
#: A face of a window at least this much covered by its outer faces is dropped (:func:`covered_faces`).
COVERED_SHARE = 0.9
#: Vertices closer than this are one vertex when finding windows [m].
WELD_M = 1e-5
__all__ = ["connected_components", "shared_edges", "outer_surface", "coplanar_clusters", "find_windows",
           "check_glazing_over_opaque"]

#: An opaque face this close to a window's plane lies in it [m] ...
UNCUT_DISTANCE_M = 1e-3
#: ... and covering more than this share of the window's area makes it a modelling error ...
UNCUT_SHARE = 0.01
#: ... where the model names its elements (a received IFC), more than this share; less is a warning
#: (another element's frame or casing flush with part of the glass hides that part, as it should).
UNCUT_ERROR_SHARE = 0.5


#: Glass layers of one pane closer than this are one thin solid (a pane modelled with thickness,
#: double or triple glazing): the scene keeps its outer face [m].
MAX_GLAZING_THICKNESS_M = 0.1
#: Parallel panes of one window product whose planes are closer than this are one window (a
#: sliding door's leaves, a stepped pane) [m]; farther apart, or at an angle, they are several.
KEYED_PLANE_GAP_M = 0.3


def outer_surface(tv: np.ndarray, normals: np.ndarray, areas: np.ndarray, group: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Faces to keep of glazing modelled as thin solids: the outer face of each pane.

    Each group (edge-connected glazing: one pane's solid) whose faces parallel to its main plane
    lie in two or more layers within :data:`MAX_GLAZING_THICKNESS_M` is a thin solid (both sides
    of the glass, the rims between them, maybe a stepped edge): only the faces on its outer side
    stay, outer seen from ``centre`` (3,) [m], a point inside the building. Those are the faces
    whose normals point outwards where the solid's faces are oriented consistently (one side's
    area matches the other's), which keeps a stepped pane whole; else the outermost layer. A
    group with one layer (a pane modelled as a surface) stays whole.

    Returns
    -------
    (k,) bool mask over the faces
    """
    keep = np.ones(len(tv), dtype=bool)
    cos_tol = np.cos(np.radians(COPLANAR_ANGLE_DEG))
    for g in np.unique(group):  # one step per pane
        members = np.flatnonzero(group == g)
        n, a = normals[members], areas[members]
        d = np.linalg.eigh((n * a[:, None]).T @ n)[1][:, -1]  # the main plane's normal (either sign)
        pane = np.abs(n @ d) >= cos_tol
        offs = tv[members].mean(axis=1) @ d
        po = np.sort(offs[pane])
        layers = np.r_[True, np.diff(po) > COPLANAR_OFFSET_M].sum() if len(po) else 0
        if layers < 2 or po[-1] - po[0] > MAX_GLAZING_THICKNESS_M:
            continue
        side = 1.0 if (tv[members].reshape(-1, 3).mean(axis=0) - centre) @ d >= 0 else -1.0
        facing = n @ (side * d)
        out_area, in_area = a[pane & (facing > 0)].sum(), a[pane & (facing < 0)].sum()
        if abs(out_area - in_area) <= 0.05 * max(out_area, in_area):  # oriented faces: those facing out
            keep[members] = pane & (facing > 0)
        else:
            outer = (side * offs).max()
            keep[members] = pane & (np.abs(side * offs - outer) <= COPLANAR_OFFSET_M)
    return keep


def covered_faces(tris: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, float | None]:
    """Faces of one window hidden behind others of it, seen along ``normal`` (outward), and the
    window's area seen that way [m2] (None where no faces overlap: the sum of the faces' areas).

    Glass bars and stepped panes leave faces at several depths over one another. Outermost first,
    a face at least :data:`COVERED_SHARE` covered by the faces already kept is dropped; the area is
    the union of the faces' outlines, so each part of the opening counts once."""
    import shapely

    a, up = window_axes(normal)
    proj = shapely.polygons(np.stack([tris @ a, tris @ up], axis=-1))
    area = shapely.area(proj)
    union = shapely.union_all(shapely.make_valid(proj)).area
    if area.sum() <= union * (1 + 1e-6):
        return np.zeros(len(tris), bool), None
    out = np.zeros(len(tris), bool)
    kept = shapely.Polygon()
    for i in np.argsort(-(tris.mean(axis=1) @ normal), kind="stable"):  # outermost first; only windows with overlaps
        if area[i] > 0 and kept.intersection(proj[i]).area >= COVERED_SHARE * area[i]:
            out[i] = True
            continue
        kept = kept.union(shapely.make_valid(proj[i]))
    return out, float(union)


def coplanar_clusters(normals: np.ndarray, centroids: np.ndarray, offset_m: float = COPLANAR_OFFSET_M) -> np.ndarray:
    """Index of a representative face for each face (k,), faces grouped by their plane: normals
    within :data:`COPLANAR_ANGLE_DEG` (either sign) and offsets within ``offset_m`` [m], whether or
    not they touch. The first face not yet placed opens a plane, vectorised over faces."""
    cos_tol = np.cos(np.radians(COPLANAR_ANGLE_DEG))
    rep = np.full(len(normals), -1)
    while (rep < 0).any():  # one pass per plane (a window has one to a few)
        i = int(np.flatnonzero(rep < 0)[0])
        same = (rep < 0) & (np.abs(normals @ normals[i]) >= cos_tol) & (np.abs((centroids - centroids[i]) @ normals[i]) <= offset_m)
        rep[same] = i
    return rep


def find_windows(vertices: np.ndarray, triangles: np.ndarray, face_ids: np.ndarray, parts: list[Part],
                 part: np.ndarray, centre: np.ndarray | None = None) -> tuple[list[Window], np.ndarray]:
    """Group window faces into windows, after reducing thin-solid glass to its outer faces.

    Faces of a product that names its windows (``Part.window``, an IfcWindow's GlobalId) form one
    window per direction, its panes together (parallel panes within :data:`KEYED_PLANE_GAP_M`: a
    sliding door's leaves), named after the product. Other glazing forms windows of
    edge-connected coplanar faces: vertices are welded within :data:`WELD_M`; two faces sharing
    an edge join when their normals differ by less than :data:`COPLANAR_ANGLE_DEG` and their
    planes by less than :data:`COPLANAR_OFFSET_M`; such a window is named after the part of its
    first face; several products of one Name are told apart by their ids (``Fenster-015
    (12ErTRo_9EmBI9cF9PJCvF)``), several pieces of one by a number. Glass modelled with thickness
    keeps its outer face (:func:`outer_surface`).

    Returns
    -------
    windows, dropped : the windows, and the face ids of glazing left out (inner faces and rims of
        thin solids)
    """
    if len(face_ids) == 0:
        return [], np.zeros(0, np.int64)
    tri = triangles[face_ids]
    t = weld(vertices, tri, WELD_M)  # weld only the glazing's own vertices
    a, b = shared_edges(t)
    tv = vertices[tri]
    normals, areas = triangle_normals(tv)
    wkey = np.array([parts[p].window or "" for p in part[face_ids]], dtype=object)
    keyed = wkey != ""
    solid = connected_components(len(tri), a, b)  # glazing joined by edges, whatever the angle: one pane's solid
    if centre is None:
        centre = vertices.mean(axis=0)
    keep = outer_surface(tv, normals, areas, solid, centre)
    dropped = face_ids[~keep]
    # the parts of the faces a thin solid leaves out, by solid: a window stands for them too (its source)
    drop_solid, drop_part = solid[~keep], part[dropped]
    solid = solid[keep]
    face_ids, tri, tv, normals, areas, wkey, keyed = (x[keep] for x in (face_ids, tri, tv, normals, areas, wkey, keyed))
    a, b = shared_edges(t[keep])
    cos_ok = np.abs(np.einsum("ij,ij->i", normals[a], normals[b])) >= np.cos(np.radians(COPLANAR_ANGLE_DEG))
    offset_ok = np.abs(np.einsum("ij,ij->i", normals[a], tv[b].mean(axis=1) - tv[a].mean(axis=1))) <= COPLANAR_OFFSET_M
    join = cos_ok & offset_ok & ~keyed[a] & ~keyed[b]
    label = connected_components(len(tv), a[join], b[join])
    if keyed.any():  # a product's panes: one window per direction, parallel panes close together as one
        for k in np.unique(wkey[keyed]):  # one step per window product
            idx = np.flatnonzero(wkey == k)
            label[idx] = idx[coplanar_clusters(normals[idx], tv[idx].mean(axis=1), KEYED_PLANE_GAP_M)]
    roots = np.unique(label)
    base_names = []
    for root in roots:  # one small step per window, not per face
        p = parts[part[face_ids[np.flatnonzero(label == root)[0]]]]
        base_names.append(p.label or p.attrs.get("file", "") or "window")
    keys_of = [wkey[np.flatnonzero(label == root)[0]] for root in roots]
    counts = {n: base_names.count(n) for n in base_names}
    # products that share a Name (two IfcWindows 'Fenster-015'): told apart by their ids; the pieces
    # of one product (its panes facing two ways) by a number
    by_key = {(n, key): sum(1 for m, q in zip(base_names, keys_of) if m == n and q == key) for n, key in zip(base_names, keys_of)}
    seen: dict = {}
    windows = []
    hidden = []
    for k, root in enumerate(roots):
        members = np.flatnonzero(label == root)
        tris = tv[members]
        n, ar = triangle_normals(tris)
        n = n * np.where(n @ n[np.argmax(ar)] < 0, -1.0, 1.0)[:, None]  # faces wound either way: one side
        normal = (n * ar[:, None]).sum(axis=0)
        normal /= np.linalg.norm(normal)
        area = float(ar.sum())
        made_of = np.unique(np.concatenate([part[face_ids[members]], drop_part[np.isin(drop_solid, solid[members])]]))
        if wkey[members[0]]:  # a product's panes at several depths: each part of the opening once
            cover, seen_area = covered_faces(tris, normal if (tris.mean(axis=(0, 1)) - centre) @ normal >= 0 else -normal)
            if cover.any():
                hidden.append(face_ids[members[cover]])
                members, tris = members[~cover], tris[~cover]
            area = area if seen_area is None else seen_area
        name = base_names[k]
        key = keys_of[k]
        if counts[name] > 1 and key and by_key[(name, key)] < counts[name]:
            base = f"{name} ({key})"
            if by_key[(name, key)] > 1:
                seen[base] = seen.get(base, 0) + 1
                base = f"{base} #{seen[base]}"
            name = base
        elif counts[name] > 1:
            seen[name] = seen.get(name, 0) + 1
            name = f"{name} #{seen[name]}"
        first = parts[part[face_ids[members[0]]]]
        windows.append(Window(name=name, index=k, face_ids=face_ids[members], triangles=tris, normal=normal,
                              area_m2=area, key=wkey[members[0]] or None, host=tuple(first.host),
                              parts=tuple(int(x) for x in made_of)))
    return windows, np.sort(np.concatenate([dropped, *hidden])) if hidden else dropped


def own_parts(parts: list[Part], window: Window) -> np.ndarray:
    """(parts,) bool: the parts that are the window's own element: its product (``attrs['id']`` its
    key) and, for a piece of an assembly (a curtain wall's plate), the assembly's other pieces
    (its mullions): the element's frame, never a wall left uncut."""
    if window.key is None:
        return np.zeros(len(parts), bool)
    mine = [p for p in parts if p.window == window.key]
    asm = {p.assembly for p in mine if p.assembly}
    return np.array([p.attrs.get("id") == window.key or (p.assembly is not None and p.assembly in asm) for p in parts], bool)


def describe_part(part: Part) -> str:
    """An element as messages name it: ``IfcWall 'Name' (GlobalId)`` where the file says, else its label."""
    cls, name, gid = (part.attrs.get(k) for k in ("class", "name", "id"))
    if cls and gid:
        return f"{cls} '{name}' ({gid})" if name else f"{cls} ({gid})"
    return f"'{part.label or '(unnamed)'}'"


def file_label(part: Part) -> str:
    """'file: object' label of a part, for messages about models without element ids."""
    stem, name = part.attrs.get("file", ""), part.label or "(unnamed)"
    return f"{stem}: {name}" if stem else name


@dataclass(frozen=True)
class UncutGlazing:
    """A window whose glazing lies on an opaque face of another element (no opening cut for it).

    position : index of the window in the list checked; element : how messages name the window;
    reason : what was found; advice : what a project file can do about it; other : how messages
    name the element that covers it
    """

    position: int
    element: str
    reason: str
    advice: str
    other: str


def check_glazing_over_opaque(vertices, triangles, layer, windows: list[Window], parts: list[Part], part,
                              where: str) -> tuple[list[str], list[UncutGlazing]]:
    """Windows whose glazing lies over an opaque face of another element, with no opening cut for
    it: warnings where such a face hides only a part of it, and the windows it hides (to be
    quarantined: :func:`en17037cli.scene.quarantine.quarantine_windows`).

    An opaque face within :data:`UNCUT_DISTANCE_M` of a window's glazing, whose overlap with the
    window covers more than :data:`UNCUT_SHARE` of the window's area, hides the glazing from every
    ray (a silent zero view). Walls whose opening is cut around a glazing in the same plane only
    touch its outline and pass; the window's own frame (:func:`own_parts`) touching or surrounding
    its glass is its frame and never counts. Where the model names its elements (IFC: a file the
    user received) the window is hidden when more than :data:`UNCUT_ERROR_SHARE` is covered (a
    wall left uncut covers it all); a smaller overlap is a warning naming the other element.
    Vectorised over faces; one shapely overlap per layer of glazing of a window.

    Raises :class:`InputError` only where every window of the model is hidden so (nothing is left
    to assess: the model's windows are all drawn on their walls), with the first one's advice.

    Parameters
    ----------
    parts : the scene's parts; part : (m,) int, part of each face
    """
    import shapely

    opaque = np.flatnonzero(layer != WINDOW)
    warnings: list[str] = []
    hidden: list[UncutGlazing] = []
    if len(opaque) == 0:
        return warnings, hidden
    n_parts = len(parts)
    for k, w in enumerate(windows):  # one pass per window
        mine = own_parts(parts, w)
        others = opaque[~mine[part[opaque]]] if mine.any() else opaque
        if len(others) == 0:
            continue
        n = w.normal
        a, up = window_axes(n)
        offs = w.triangles.mean(axis=1) @ n
        levels = np.unique(np.round(offs / UNCUT_DISTANCE_M)) * UNCUT_DISTANCE_M
        per_part = np.zeros(n_parts)
        for lv in levels:  # the glazing's planes (one, or a few for a stepped pane)
            s_v = vertices @ n - lv  # per vertex first: no (m, 3, 3) copy of a large scene
            near = others[np.all(np.abs(s_v[triangles[others]]) <= UNCUT_DISTANCE_M, axis=1)]
            if len(near) == 0:
                continue
            mine_lv = w.triangles[np.abs(offs - lv) <= UNCUT_DISTANCE_M]
            win = shapely.union_all(shapely.polygons(np.stack([mine_lv @ a, mine_lv @ up], axis=-1))).buffer(0)
            rel = vertices[triangles[near]]
            faces = shapely.polygons(np.stack([rel @ a, rel @ up], axis=-1))
            overlap = shapely.area(shapely.intersection(shapely.make_valid(faces), win))
            per_part += np.bincount(part[near], overlap, n_parts)
        worst = int(np.argmax(per_part))
        if per_part[worst] <= UNCUT_SHARE * w.area_m2:
            continue
        share = f"{100 * per_part[worst] / w.area_m2:.0f}%"
        own = parts[int(part[w.face_ids[0]])]
        other = parts[worst]
        named = w.key is not None and "id" in other.attrs
        within = f"within {UNCUT_DISTANCE_M * 1000:.0f} mm of the glazing"
        if named and per_part[worst] <= UNCUT_ERROR_SHARE * w.area_m2:
            warnings.append(f"window '{w.name}' ({describe_part(own)}): {describe_part(other)} has an opaque face {within} "
                            f"over {share} of it, which it hides")
            continue
        if named:  # a file the user received: what a project file can do
            hidden.append(UncutGlazing(
                k, f"window '{w.name}' ({describe_part(own)})",
                f"it lies on {describe_part(other)}: an opaque face of that element {within} covers {share} of it, so no "
                "ray can pass (the file cuts no opening for the window in that element)",
                f"to check the room without this window, add the layer rule {{id: '{w.key}', layer: interior}}; to let "
                f"light through that element, leave it out with model.files[].exclude: ['{other.attrs['id']}']",
                describe_part(other)))
        elif "id" in other.attrs and other.attrs.get("file") != own.attrs.get("file"):  # a context model's object
            hidden.append(UncutGlazing(
                k, f"window '{w.name}' ({file_label(own)})",
                f"it lies on '{file_label(other)}', an opaque face of another model file {within} covering {share} of it: "
                "no ray could pass",
                f"where that object is the checked building as the context model draws it, leave it out with exclude: "
                f"['{other.attrs['id']}'] on that file (or exclude_overlapping: true); else check the placement of the two "
                "files (transform, crs)", f"'{file_label(other)}'"))
        else:
            hidden.append(UncutGlazing(
                k, f"window '{w.name}' ({file_label(own)})",
                f"it lies on '{file_label(other)}', an opaque face {within} covering {share} of it: no ray could pass",
                "cut the opening in that wall, or move the glazing off the wall plane", f"'{file_label(other)}'"))
    if hidden and len(hidden) == len(windows):  # nothing left to assess: the model's own error, said once
        first = hidden[0]
        raise InputError(f"{where}: {first.element} {first.reason[3:]}; {first.advice}"
                         + (f" ({len(hidden) - 1} other window(s) likewise)" if len(hidden) > 1 else ""))
    return warnings, hidden


def glazing_grid(window: Window, n: int) -> np.ndarray:
    """Up to n x n points [m] spread over a window's glazing: a grid over its extent in its plane,
    inset by half a step, kept where it lies on the glazing (possibly none)."""
    a, up = window_axes(window.normal)
    rel = window.triangles - window.centroid
    x, y = rel @ a, rel @ up
    gx = np.linspace(x.min(), x.max(), 2 * n + 1)[1::2]
    gy = np.linspace(y.min(), y.max(), 2 * n + 1)[1::2]
    X, Y = (g.ravel() for g in np.meshgrid(gx, gy))
    inside = points_in_triangles(np.column_stack([X, Y]), np.stack([x, y], axis=-1))
    return window.centroid + X[inside, None] * a + Y[inside, None] * up
