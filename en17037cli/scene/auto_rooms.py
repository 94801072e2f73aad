"""Automatic rooms: ``rooms: [{auto: true, floor_z: Z}]`` makes every region the walls enclose at
that level (:mod:`~en17037cli.scene.section`) with a window opening from it a room; without
``floor_z``, at every storey of the model (each level of horizontal interior faces of at least
:data:`~en17037cli.scene.levels.MIN_LEVEL_AREA_M2` with a room's height clear above it: a floor slab, not a table top, a
stair tread or a plenum's floor)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from en17037cli.project.settings import RoomSpec
from en17037cli.scene.levels import FLOOR_COVER, floor_cover, storey_levels
from en17037cli.scene.model import Room, Scene
from en17037cli.scene.rooms import make_room
from en17037cli.scene.section import cells_with_windows, level_windows, plan_of


def auto_rooms(scene: Scene, spec: RoomSpec, where: str) -> list[Room]:
    """One room per region with a window at ``spec.floor_z`` (or at every storey), named
    ``z 3.00 room at (2.0, 4.5)`` (the level and a point inside the region, in the model's
    coordinates), made like a room given by name and ``inside`` point."""
    if not spec.auto_all_storeys:
        return _rooms_at(scene, spec, where, [spec.floor_z - scene.origin[2]])
    rooms = _rooms_at(scene, spec, where, storey_levels(scene))
    if not rooms:
        scene.notes.append(f"{where}: auto found no region the walls enclose with a window")
    return rooms


def _rooms_at(scene: Scene, spec: RoomSpec, where: str, levels: list[float]) -> list[Room]:
    rooms = []
    for z in levels:
        plan = plan_of(scene, z)
        found = cells_with_windows(scene, plan, level_windows(scene, z))
        floored = {i: floor_cover(scene, plan.cells[i], z) >= FLOOR_COVER for i in found}
        if any(floored.values()):  # a level with floors: a region without one is a void, not a room
            void = [i for i in found if not floored[i]]
            for i in void:
                found.pop(i)
            if void:
                scene.notes.append(f"{where}: {len(void)} region(s) at z {z + scene.origin[2]:.2f} m with windows but no floor "
                                   "(the void over a double-height room, a well) are not rooms")
        for i in sorted(found, key=lambda k: (round(plan.cells[k].centroid.y, 1), round(plan.cells[k].centroid.x, 1))):
            p = plan.cells[i].representative_point()
            x, y = p.x + scene.origin[0], p.y + scene.origin[1]
            name = f"z {z + scene.origin[2]:.2f} room at ({x:.1f}, {y:.1f})"
            room_spec = replace(spec, name=name, floor_z=z + scene.origin[2], inside=np.array([x, y]), auto=False,
                                auto_all_storeys=False)
            rooms.append(make_room(scene, room_spec, f"{where} '{name}'"))
    if not rooms and not spec.auto_all_storeys:
        scene.notes.append(f"{where}: auto found no region the walls enclose with a window at floor_z = {spec.floor_z:g} m")
    return rooms
