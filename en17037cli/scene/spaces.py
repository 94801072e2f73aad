"""Rooms from the spaces a model defines (IfcSpace, gbXML Space): one room per space a project's
``ifc_spaces`` / ``gbxml_spaces`` glob picks, among the spaces of that kind."""
from __future__ import annotations

import fnmatch
from dataclasses import replace

from en17037cli.errors import InputError
from en17037cli.io.mesh import Space
from en17037cli.project.settings import RoomSpec
from en17037cli.scene.model import Room, Scene
from en17037cli.scene.rooms import make_room


def room_name(space: Space) -> str:
    """How reports name a space: 'LongName (Name)', or whichever of them it has, or its GlobalId."""
    if space.long_name and space.name:
        return f"{space.long_name} ({space.name})"
    return space.long_name or space.name or space.id


def rooms_from_spaces(scene: Scene, spec: RoomSpec, where: str) -> list[Room]:
    """A room for each space whose Name, LongName or GlobalId the spec's glob matches.

    Floor: the space's footprint at its bottom; ceiling: its top. Windows: those the file's space
    boundaries name where the file has any (IfcRelSpaceBoundary), else those that bound the room
    geometrically (:func:`~en17037cli.scene.rooms.bounds_room`). A space with no window is left out
    of the check, with a note (``validate`` lists it).
    """
    key, kind = ("gbxml_spaces", "gbXML Space") if spec.gbxml_spaces is not None else ("ifc_spaces", "IfcSpace")
    glob = getattr(spec, key) or "*"
    spaces = [(d, s) for d, s in scene.spaces if s.kind == kind]
    if not spaces:
        raise InputError(f"{where}.{key}: the model has no {kind}; list the rooms with name and floor_z instead")
    picked = [(d, s) for d, s in spaces
              if any(fnmatch.fnmatchcase(v, glob) for v in (s.name, s.long_name, s.id, room_name(s)) if v)]
    if not picked:
        known = ", ".join(room_name(s) for _, s in spaces[:8])
        raise InputError(f"{where}.{key}: '{glob}' matches no {kind}; spaces: {known}")
    with_boundaries = {d for d, s in spaces if s.windows}
    rooms = []
    for display, space in sorted(picked, key=lambda ds: (ds[1].floor_z, room_name(ds[1]))):  # storey by storey
        name = room_name(space)
        room_spec = replace(spec, name=name, floor_z=space.floor_z, floor=space.footprint, ceiling_z=space.top_z,
                            view_points=None, sun_points=None)
        keys = set(space.windows) if display in with_boundaries else None
        room = make_room(scene, room_spec, f"{where} '{name}'", keys=keys)
        room.zones, room.storey = space.zones, space.storey
        room.floor_source, room.ceiling_source = f"the {kind}'s footprint", f"the {kind}'s top"
        if room.problem and not room.windows:
            scene.notes.append(f"{kind} '{name}': {room.problem}; left out of the check")
            scene.left_out.append(name)
            continue
        rooms.append(room)
    return rooms
