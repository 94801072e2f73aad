"""Automatic rooms: ``rooms: [{auto: true, floor_z: Z}]`` makes every region the walls enclose at
that level (:mod:`~en17037cli.scene.section`) with a window opening from it a room; without
``floor_z``, at every storey of the model (each level of upward-facing horizontal interior faces
of at least :data:`MIN_LEVEL_AREA_M2`: a floor slab, not a table top or a stair tread)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from en17037cli.geometry import triangle_normals
from en17037cli.project.settings import RoomSpec
from en17037cli.scene.model import INTERIOR, Room, Scene
from en17037cli.scene.rooms import MIN_ROOM_HEIGHT_M

#: A level of upward-facing horizontal interior faces is a storey's floor when they cover at least this [m²].
MIN_LEVEL_AREA_M2 = 4.0
#: Floor faces within this height of each other are one level [m].
LEVEL_TOL_M = 0.01


def storey_levels(scene: Scene) -> list[float]:
    """Heights [m, local] of the model's floors: levels of upward-facing horizontal interior faces
    covering at least :data:`MIN_LEVEL_AREA_M2` in all, from the lowest up; of levels closer than a
    room's height (:data:`~en17037cli.scene.rooms.MIN_ROOM_HEIGHT_M`: the tops of walls under a
    slab, a raised floor) the one of the largest area."""
    tris = scene.faces_of(scene.layer == INTERIOR)
    normals, areas = triangle_normals(tris)
    up = (normals[:, 2] > 0.999) & (areas > 0)
    if not up.any():
        return []
    z = tris[up][..., 2].mean(axis=1)
    key = np.round(z / LEVEL_TOL_M).astype(np.int64)
    levels, inverse = np.unique(key, return_inverse=True)
    total = np.bincount(inverse, areas[up])
    chosen: list[float] = []
    for k in np.argsort(-total, kind="stable"):  # the largest first: a slab's top beats the wall tops under it
        zk = float(np.median(z[inverse == k]))
        if total[k] >= MIN_LEVEL_AREA_M2 and all(abs(zk - c) >= MIN_ROOM_HEIGHT_M for c in chosen):
            chosen.append(zk)
    return sorted(chosen)


def auto_rooms(scene: Scene, spec: RoomSpec, where: str) -> list[Room]:
    """One room per region with a window at ``spec.floor_z`` (or at every storey), named
    ``z 3.00 room at (2.0, 4.5)`` (the level and a point inside the region, in the model's
    coordinates), made like a room given by name and ``inside`` point."""
    from en17037cli.scene.rooms import make_room
    from en17037cli.scene.section import cells_with_windows, level_windows, plan_of

    levels = storey_levels(scene) if spec.auto_all_storeys else [spec.floor_z - scene.origin[2]]
    rooms = []
    for z in levels:
        plan = plan_of(scene, z)
        found = cells_with_windows(scene, plan, level_windows(scene, z))
        for i in sorted(found, key=lambda k: (round(plan.cells[k].centroid.y, 1), round(plan.cells[k].centroid.x, 1))):
            p = plan.cells[i].representative_point()
            x, y = p.x + scene.origin[0], p.y + scene.origin[1]
            name = f"z {z + scene.origin[2]:.2f} room at ({x:.1f}, {y:.1f})"
            room_spec = replace(spec, name=name, floor_z=z + scene.origin[2], inside=np.array([x, y]), auto=False,
                                auto_all_storeys=False)
            rooms.append(make_room(scene, room_spec, f"{where} '{name}'"))
    if not rooms:
        scene.notes.append(f"{where}: auto found no region the walls enclose with a window"
                           + ("" if spec.auto_all_storeys else f" at floor_z = {spec.floor_z:g} m"))
    return rooms
