"""Windows: glazing faces grouped into openings, and the modelling check on glazing over an uncut wall."""
from __future__ import annotations

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals, window_axes
from en17037cli.io.mesh import Part
from en17037cli.scene.model import WINDOW, Window

#: Window faces whose normals differ by less than this are coplanar [deg] ...
COPLANAR_ANGLE_DEG = 1.0
#: ... and whose planes are closer than this [m].
COPLANAR_OFFSET_M = 1e-3
#: Vertices closer than this are one vertex when finding windows [m].
WELD_M = 1e-5

#: An opaque face this close to a window's plane lies in it [m] ...
UNCUT_DISTANCE_M = 1e-3
#: ... and covering more than this share of the window's area makes it a modelling error.
UNCUT_SHARE = 0.01


def connected_components(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Component label (the smallest member index) of each of ``n`` nodes joined by edges (a, b).

    Vectorised min-label propagation with pointer jumping; converges in at most the
    component diameter.
    """
    label = np.arange(n)
    while True:
        new = label.copy()
        np.minimum.at(new, a, label[b])
        np.minimum.at(new, b, label[a])
        new = new[new]
        if np.array_equal(new, label):
            return label
        label = new


#: Glass layers of one pane closer than this are one thin solid (a pane modelled with thickness,
#: double or triple glazing): the scene keeps its outer face [m].
MAX_GLAZING_THICKNESS_M = 0.1


def shared_edges(tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (a, b) of faces (rows of ``tri``, welded vertex ids) that share an edge."""
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(tri)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    e, o = edges[order], owner[order]
    same = np.all(e[1:] == e[:-1], axis=1)
    return o[:-1][same], o[1:][same]


def outer_surface(tv: np.ndarray, normals: np.ndarray, areas: np.ndarray, group: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Faces to keep of glazing modelled as thin solids: the outer face of each pane.

    Each group (a window product's glazing, or glazing faces joined by edges) whose faces parallel
    to its main plane lie in two or more layers within :data:`MAX_GLAZING_THICKNESS_M` is a thin
    solid (both sides of the glass, and the rims between them): only its outermost layer stays,
    outermost seen from ``centre`` (3,) [m], a point inside the building. A group with one layer
    (a pane modelled as a surface) stays whole.

    Returns
    -------
    (k,) bool mask over the faces
    """
    keep = np.ones(len(tv), dtype=bool)
    cos_tol = np.cos(np.radians(COPLANAR_ANGLE_DEG))
    for g in np.unique(group):  # one step per window group
        members = np.flatnonzero(group == g)
        n, a = normals[members], areas[members]
        cov = (n * a[:, None]).T @ n
        d = np.linalg.eigh(cov)[1][:, -1]  # the main plane's normal (either sign)
        pane = np.abs(n @ d) >= cos_tol
        offs = tv[members].mean(axis=1) @ d
        po = np.sort(offs[pane])
        layers = np.r_[True, np.diff(po) > COPLANAR_OFFSET_M].sum() if len(po) else 0
        if layers < 2 or po[-1] - po[0] > MAX_GLAZING_THICKNESS_M:
            continue
        side = 1.0 if (tv[members].reshape(-1, 3).mean(axis=0) - centre) @ d >= 0 else -1.0
        outer = (side * offs).max()
        keep[members] = pane & (np.abs(side * offs - outer) <= COPLANAR_OFFSET_M)
    return keep


def coplanar_clusters(normals: np.ndarray, centroids: np.ndarray) -> np.ndarray:
    """Index of a representative face for each face (k,), faces grouped by their plane: normals
    within :data:`COPLANAR_ANGLE_DEG` (either sign) and offsets within :data:`COPLANAR_OFFSET_M`,
    whether or not they touch. The first face not yet placed opens a plane, vectorised over faces."""
    cos_tol = np.cos(np.radians(COPLANAR_ANGLE_DEG))
    rep = np.full(len(normals), -1)
    while (rep < 0).any():  # one pass per plane (a window has one to a few)
        i = int(np.flatnonzero(rep < 0)[0])
        same = (rep < 0) & (np.abs(normals @ normals[i]) >= cos_tol) & (np.abs((centroids - centroids[i]) @ normals[i]) <= COPLANAR_OFFSET_M)
        rep[same] = i
    return rep


def find_windows(vertices: np.ndarray, triangles: np.ndarray, face_ids: np.ndarray, parts: list[Part],
                 part: np.ndarray, centre: np.ndarray | None = None) -> tuple[list[Window], np.ndarray]:
    """Group window faces into windows, after reducing thin-solid glass to its outer faces.

    Faces of a product that names its windows (``Part.window``, an IfcWindow's GlobalId) form one
    window per plane, its panes together, named after the product. Other glazing forms windows of
    edge-connected coplanar faces: vertices are welded within :data:`WELD_M`; two faces sharing
    an edge join when their normals differ by less than :data:`COPLANAR_ANGLE_DEG` and their
    planes by less than :data:`COPLANAR_OFFSET_M`; such a window is named after the part of its
    first face. Glass modelled with thickness keeps its outer face (:func:`outer_surface`).

    Returns
    -------
    windows, dropped : the windows, and the face ids of glazing left out (inner faces and rims of
        thin solids)
    """
    if len(face_ids) == 0:
        return [], np.zeros(0, np.int64)
    tri = triangles[face_ids]
    used, inverse = np.unique(tri, return_inverse=True)  # weld only the glazing's own vertices
    keys = np.round(vertices[used] / WELD_M).astype(np.int64)
    _, welded = np.unique(keys, axis=0, return_inverse=True)
    t = welded.reshape(-1)[inverse.reshape(tri.shape)]
    a, b = shared_edges(t)
    tv = vertices[tri]
    normals, areas = triangle_normals(tv)
    wkey = np.array([parts[p].window or "" for p in part[face_ids]], dtype=object)
    keyed = wkey != ""
    solid = connected_components(len(tri), a, b)  # glazing joined by edges, whatever the angle
    _, group = np.unique(np.where(keyed, "k:" + wkey.astype(str), "s:" + solid.astype(str)), return_inverse=True)
    if centre is None:
        centre = vertices.mean(axis=0)
    keep = outer_surface(tv, normals, areas, group, centre)
    dropped = face_ids[~keep]
    face_ids, tri, tv, normals, areas, wkey, keyed = (x[keep] for x in (face_ids, tri, tv, normals, areas, wkey, keyed))
    a, b = shared_edges(t[keep])
    cos_ok = np.abs(np.einsum("ij,ij->i", normals[a], normals[b])) >= np.cos(np.radians(COPLANAR_ANGLE_DEG))
    offset_ok = np.abs(np.einsum("ij,ij->i", normals[a], tv[b].mean(axis=1) - tv[a].mean(axis=1))) <= COPLANAR_OFFSET_M
    join = cos_ok & offset_ok & ~keyed[a] & ~keyed[b]
    label = connected_components(len(tv), a[join], b[join])
    if keyed.any():  # a product's panes: one window per plane, whether or not they touch
        for k in np.unique(wkey[keyed]):  # one step per window product
            idx = np.flatnonzero(wkey == k)
            label[idx] = idx[coplanar_clusters(normals[idx], tv[idx].mean(axis=1))]
    roots = np.unique(label)
    base_names = []
    for root in roots:  # one small step per window, not per face
        p = parts[part[face_ids[np.flatnonzero(label == root)[0]]]]
        base_names.append(p.label or p.attrs.get("file", "") or "window")
    counts = {n: base_names.count(n) for n in base_names}
    seen: dict = {}
    windows = []
    for k, root in enumerate(roots):
        members = np.flatnonzero(label == root)
        tris = tv[members]
        n, ar = triangle_normals(tris)
        normal = (n * ar[:, None]).sum(axis=0)
        normal /= np.linalg.norm(normal)
        name = base_names[k]
        if counts[name] > 1:
            seen[name] = seen.get(name, 0) + 1
            name = f"{name} #{seen[name]}"
        windows.append(Window(name=name, index=k, face_ids=face_ids[members], triangles=tris, normal=normal,
                              area_m2=float(ar.sum()), key=wkey[members[0]] or None))
    return windows, dropped


def check_glazing_over_opaque(vertices, triangles, layer, windows: list[Window], labels, part, where: str) -> None:
    """Raise InputError where glazing lies over an opaque face that has no opening cut for it.

    An opaque face within :data:`UNCUT_DISTANCE_M` of a window's plane, whose overlap with the
    window covers more than :data:`UNCUT_SHARE` of the window's area, hides the glazing from every
    ray (a silent zero view). Walls whose opening is cut around a glazing in the same plane only
    touch its outline and pass. Vectorised over faces; one shapely overlap per window.

    Parameters
    ----------
    labels : callable, part index -> 'file: object' label for the message
    part : (m,) int, part of each face
    """
    import shapely

    opaque = np.flatnonzero(layer != WINDOW)
    if len(opaque) == 0:
        return
    n_parts = int(part.max()) + 1 if len(part) else 0
    for w in windows:  # one pass per window
        c, n = w.centroid, w.normal
        s_v = (vertices - c) @ n  # per vertex first: no (m, 3, 3) copy of a large scene
        near = opaque[np.all(np.abs(s_v[triangles[opaque]]) <= UNCUT_DISTANCE_M, axis=1)]
        if len(near) == 0:
            continue
        a, up = window_axes(n)
        rel_w = w.triangles - c
        win = shapely.union_all(shapely.polygons(np.stack([rel_w @ a, rel_w @ up], axis=-1))).buffer(0)
        rel = vertices[triangles[near]] - c
        faces = shapely.polygons(np.stack([rel @ a, rel @ up], axis=-1))
        overlap = shapely.area(shapely.intersection(shapely.make_valid(faces), win))
        per_part = np.bincount(part[near], overlap, n_parts)
        worst = int(np.argmax(per_part))
        if per_part[worst] > UNCUT_SHARE * w.area_m2:
            raise InputError(
                f"{where}: window '{w.name}' ({labels(int(part[w.face_ids[0]]))}) lies on '{labels(worst)}', an opaque face "
                f"within {UNCUT_DISTANCE_M * 1000:.0f} mm of the glazing covering {100 * per_part[worst] / w.area_m2:.0f}% "
                "of it: no ray could pass; cut the opening in that wall, or move the glazing off the wall plane")
