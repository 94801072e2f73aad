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


def find_windows(vertices: np.ndarray, triangles: np.ndarray, face_ids: np.ndarray, parts: list[Part],
                 part: np.ndarray) -> list[Window]:
    """Group window faces into windows: edge-connected components of coplanar faces.

    Vertices are welded within :data:`WELD_M`; two faces sharing an edge join when their normals
    differ by less than :data:`COPLANAR_ANGLE_DEG` and their planes by less than
    :data:`COPLANAR_OFFSET_M`. A window is named after the part of its first face.
    """
    if len(face_ids) == 0:
        return []
    tri = triangles[face_ids]
    keys = np.round(vertices / WELD_M).astype(np.int64)
    _, welded = np.unique(keys, axis=0, return_inverse=True)
    welded = welded.reshape(-1)
    t = welded[tri]
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(tri)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    e, o = edges[order], owner[order]
    same = np.all(e[1:] == e[:-1], axis=1)
    a, b = o[:-1][same], o[1:][same]
    tv = vertices[tri]
    normals, _ = triangle_normals(tv)
    cos_ok = np.abs(np.einsum("ij,ij->i", normals[a], normals[b])) >= np.cos(np.radians(COPLANAR_ANGLE_DEG))
    offset_ok = np.abs(np.einsum("ij,ij->i", normals[a], tv[b].mean(axis=1) - tv[a].mean(axis=1))) <= COPLANAR_OFFSET_M
    label = connected_components(len(tri), a[cos_ok & offset_ok], b[cos_ok & offset_ok])
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
        n, areas = triangle_normals(tris)
        normal = (n * areas[:, None]).sum(axis=0)
        normal /= np.linalg.norm(normal)
        name = base_names[k]
        if counts[name] > 1:
            seen[name] = seen.get(name, 0) + 1
            name = f"{name} #{seen[name]}"
        windows.append(Window(name=name, index=k, face_ids=face_ids[members], triangles=tris,
                              normal=normal, area_m2=float(areas.sum())))
    return windows


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
