"""Rooms: floor polygons (given, or derived from the model) and the windows of each room."""
from __future__ import annotations

import fnmatch

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.project.settings import RoomSpec
from en17037cli.scene.model import INTERIOR, Room, Scene, Window


def derive_floor(scene: Scene, floor_z: float, near: np.ndarray, where: str):
    """The floor polygon at ``floor_z`` [m, local]: union of horizontal interior faces within 2 cm
    of it, the part nearest to the room's windows (``near``, (k, 2) [m])."""
    import shapely

    mask = scene.layer == INTERIOR
    tris = scene.faces_of(mask)
    normals, areas = triangle_normals(tris)
    flat = (np.abs(normals[:, 2]) > 0.999) & np.all(np.abs(tris[..., 2] - floor_z) < 0.02, axis=1) & (areas > 0)
    if not np.any(flat):
        raise InputError(f"{where}: no horizontal interior faces at floor_z; check floor_z or give 'floor' as a polygon [[x, y], ...]")
    polys = shapely.polygons(tris[flat][..., :2])
    union = shapely.union_all(shapely.make_valid(polys)).buffer(1e-6).buffer(-1e-6)
    parts = [union] if union.geom_type == "Polygon" else [g for g in getattr(union, "geoms", []) if g.geom_type == "Polygon"]
    if not parts:
        raise InputError(f"{where}: the floor at floor_z has no area; give 'floor' as a polygon [[x, y], ...]")
    pts = shapely.points(near)
    dist = [float(np.min(shapely.distance(p, pts))) for p in parts]
    return parts[int(np.argmin(dist))]


def make_room(scene: Scene, spec: RoomSpec, where: str) -> Room:
    """The :class:`Room` of ``spec``: its windows (by the spec's globs), its floor, and each
    window's normal turned away from the room."""
    import shapely

    chosen = [w for w in scene.windows if any(fnmatch.fnmatchcase(w.name, g) for g in spec.windows)]
    if not chosen:
        known = ", ".join(f"'{w.name}'" for w in scene.windows)
        raise InputError(f"{where}.windows: no window matches {list(spec.windows)}; windows found: {known}")
    floor_z = spec.floor_z - scene.origin[2]
    if spec.floor is not None:
        poly = shapely.Polygon(spec.floor - scene.origin[:2])
        if not poly.is_valid or poly.area <= 0:
            raise InputError(f"{where}.floor: not a simple polygon with area; list its corners in order")
        source = "given"
    else:
        near = np.array([w.centroid[:2] for w in chosen])
        poly = derive_floor(scene, floor_z, near, where)
        source = "derived from horizontal interior faces at floor_z"
    return Room(name=spec.name, index=spec.index, floor_z=floor_z, floor=poly,
                windows=orient_windows(chosen, poly, floor_z), spec=spec, floor_source=source)


def orient_windows(windows: list[Window], floor, floor_z: float) -> list[Window]:
    """Windows with their normals pointing away from the room (from a point 1.5 m above the
    floor's centroid)."""
    centre = np.array([floor.centroid.x, floor.centroid.y, floor_z + 1.5])
    return [w if np.dot(w.normal, w.centroid - centre) >= 0 else w.facing(-w.normal) for w in windows]
