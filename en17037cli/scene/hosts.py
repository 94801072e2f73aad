"""A window's host: the element its opening is cut in (the wall, the roof), where the model says.

IFC gives it by IfcRelFillsElement -> IfcOpeningElement -> IfcRelVoidsElement (``Part.host``;
a curtain wall holds its plates). The host's faces around the glazing, parallel to it, are the
wall's two faces: they give the wall's thickness on each side of the glass (how far a space may lie
from the window and still be the one it opens into) and the room-side plane of the opening (point
P of EN 17037 Annex A.3). Nothing else (railings, stairs, furniture, other rooms' walls) counts.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry import triangle_normals
from en17037cli.scene.model import Scene, Window

#: Host faces count when within this angle of the glazing's plane (the wall's faces) [deg] ...
HOST_PARALLEL_DEG = 10.0
#: ... and their bounding box comes within this distance of the glazing's [m] (the wall around the opening) ...
HOST_NEAR_M = 0.3
#: ... and within this distance of its plane [m] (the thickest wall or roof, with a roof light's curb).
HOST_DEEP_M = 1.5


def host_faces(scene: Scene, window: Window) -> np.ndarray:
    """Indices of the faces of the window's host (parts whose ``id`` is one of ``window.host``, and
    the pieces of such an assembly), and of the window's own element (its frame), near the glazing."""
    if not window.host and window.key is None:
        return np.zeros(0, np.int64)
    index = scene.cache.get("parts_by_object")
    if index is None:  # object id -> its parts, once per scene
        index = {}
        for i, p in enumerate(scene.parts):
            for key in {p.attrs.get("id"), p.assembly} - {None}:
                index.setdefault(key, []).append(i)
        order = np.argsort(scene.part, kind="stable")
        starts = np.searchsorted(scene.part[order], np.arange(len(scene.parts) + 1))
        scene.cache["parts_by_object"] = index = (index, order, starts)
    by_object, order, starts = index
    wanted = sorted({i for key in (*window.host, window.key) if key for i in by_object.get(key, ())})
    if not wanted:
        return np.zeros(0, np.int64)
    faces = np.concatenate([order[starts[i]:starts[i + 1]] for i in wanted])
    grow = HOST_NEAR_M + HOST_DEEP_M * np.abs(np.asarray(window.normal, float))
    lo = window.triangles.reshape(-1, 3).min(axis=0) - grow
    hi = window.triangles.reshape(-1, 3).max(axis=0) + grow
    tri = scene.vertices[scene.triangles[faces]]
    near = np.all((tri.min(axis=1) <= hi) & (tri.max(axis=1) >= lo), axis=1)
    return faces[near]


def _parallel(scene: Scene, window: Window, faces: np.ndarray) -> np.ndarray | None:
    """(k, 3, 3) [m]: the triangles of ``faces`` parallel to the glazing (within
    :data:`HOST_PARALLEL_DEG`, zero-area ones left out), or None where there are none."""
    if len(faces) == 0:
        return None
    tri = scene.vertices[scene.triangles[faces]]
    normals, areas = triangle_normals(tri)
    par = (np.abs(normals @ np.asarray(window.normal, float)) >= np.cos(np.radians(HOST_PARALLEL_DEG))) & (areas > 0)
    return tri[par] if par.any() else None


def host_depths(scene: Scene, window: Window) -> tuple[float, float] | None:
    """How far the host (and the window's own frame) reaches from the glazing's plane [m] on the
    side the normal points to and on the other: (front, back), each >= 0; None without a host.

    From the vertices of the host's faces parallel to the glazing (within :data:`HOST_PARALLEL_DEG`)
    near it: the wall's outer and inner faces (a roof light's curb and the roof's underside).
    """
    par = _parallel(scene, window, host_faces(scene, window))
    if par is None:
        return None
    n = np.asarray(window.normal, float)
    off = par.reshape(-1, 3) @ n - window.centroid @ n
    return max(float(off.max()), 0.0), max(float(-off.min()), 0.0)


def reveal_depth_from_host(scene: Scene, window: Window, point: np.ndarray, max_depth: float) -> float | None:
    """Depth [m] of the room-side plane of the opening behind ``point`` (on the glazing's plane),
    along -``window.normal`` (outward normal): the deepest face of the host parallel to the glazing
    within ``max_depth``, the window's own frame not counted (it lies in front of the wall's inner
    face or flush with it). None where the window has no host faces near it."""
    if not getattr(window, "host", ()):  # a window the model names no host for (and stand-ins in tests)
        return None
    own = window.key
    faces = host_faces(scene, window)
    if own is not None and len(faces):
        mine = np.array([scene.parts[p].attrs.get("id") == own for p in scene.part[faces]], bool)
        faces = faces[~mine]
    par = _parallel(scene, window, faces)
    if par is None:
        return None
    depth = (np.asarray(point, float) - par.mean(axis=1)) @ np.asarray(window.normal, float)  # > 0: behind the glazing, on the room's side
    depth = depth[(depth > 0) & (depth <= max_depth)]
    return float(depth.max()) if len(depth) else 0.0
