"""Building a :class:`~en17037cli.scene.model.Scene` from a project's settings.

Data flow: read each model file, scale it to metres, turn y-up files to z-up, place it, assign
every face a layer, drop degenerate faces (:mod:`~en17037cli.scene.load`), shift everything to a
local origin (float64), find the windows (:mod:`~en17037cli.scene.windows`), take true north and
the location from the model where the project leaves them out (:mod:`~en17037cli.scene.site`,
which checks them), make each room's floor and windows (:mod:`~en17037cli.scene.rooms`; rooms
from IfcSpaces with :mod:`~en17037cli.scene.spaces`) and check the city models against the rooms
(:mod:`~en17037cli.scene.context`). Engines receive a Scene and never read files.
"""
from __future__ import annotations

import numpy as np

from en17037cli.errors import InputError
from en17037cli.project.settings import Project
from en17037cli.scene.city_frame import city_frame
from en17037cli.scene.kinds import assign_kinds
from en17037cli.scene.load import load_geometry
from en17037cli.scene.model import INTERIOR, WINDOW, Geometry, Scene
from en17037cli.scene.openings import join_openings
from en17037cli.scene.quarantine import quarantine_windows
from en17037cli.scene.rooms import check_shared_floors, make_room
from en17037cli.scene.site import resolve_location, resolve_north
from en17037cli.scene.spaces import rooms_from_spaces
from en17037cli.scene.windows import check_glazing_over_opaque, find_windows


def building_centre(g: Geometry) -> np.ndarray:
    """A point inside the building [m, world]: the centre of the interior faces' bounding box."""
    faces = g.triangles[g.layer == INTERIOR] if np.any(g.layer == INTERIOR) else g.triangles
    v = g.vertices[faces].reshape(-1, 3)
    return 0.5 * (v.min(axis=0) + v.max(axis=0))


def build_scene(project: Project) -> Scene:
    """Load the project's geometry and resolve windows and rooms (see module docstring)."""
    where = project.path.name
    if not project.rooms:
        raise InputError(f"{where}: rooms: none given; check, validate, batch and study assess rooms: give rooms (docs/rooms.md), "
                         "or probe the city model's facades with 'en17037 screen' (its screen: section)")
    g = load_geometry(project.model, where)
    win_mask = g.layer == WINDOW
    if not np.any(win_mask):
        unread = "".join(f"; {label} ({display}): {why}" for display, label, why in g.windows_left_out[:3])
        raise InputError(f"{where}: model.files: no face is on the 'window' layer: no glazing was found (no glazed IfcWindow, "
                         "IfcDoor or curtain-wall panel, no gbXML Opening that lets light through, no file or object placed "
                         "on the window layer); give the glazing's file layer: window, or a layer rule matching its objects "
                         f"(object, material, IFC class or Name), e.g. layers: [{{match: \"*glass*\", layer: window}}]{unread}")
    # Local origin: centre of the windows' bounding box, float64 (see trimesh/ray/ray_pyembree.py).
    wv = g.vertices[g.triangles[win_mask]].reshape(-1, 3)
    origin = 0.5 * (wv.min(axis=0) + wv.max(axis=0))
    local = g.vertices - origin
    windows, dropped = find_windows(local, g.triangles, np.flatnonzero(win_mask), g.parts, g.part,
                                    building_centre(g) - origin)
    if len(dropped):
        g.notes.append(f"{len(dropped)} glazing faces of glass modelled as thin solids (inner faces, rims) left out: "
                       "each pane keeps its outer face")
    city = city_frame(g, origin[:2], project.model.files) if g.context else None  # the building set in a georeferenced city model
    north, north_src, site_warnings = resolve_north(project, g, city)
    location, resolved, loc_warnings, loc_notes = resolve_location(project, g, where, city)
    g.notes.extend(loc_notes)
    if north_src:
        resolved["model.true_north_deg"] = north_src
    scene = Scene(vertices=local, triangles=g.triangles, layer=g.layer, obstructs_sun=g.obstructs_sun, parts=g.parts,
                  part=g.part, notes=g.notes, warnings=[*project.warnings, *g.warnings, *site_warnings, *loc_warnings],
                  file_hashes=g.file_hashes,
                  sites=g.sites, spaces=g.spaces, optics=g.optics, read=g.read, windows_left_out=g.windows_left_out,
                  context=g.context, files=g.files,
                  origin=origin, windows=windows, true_north_deg=north, location=location, resolved=resolved)
    partly, hidden = check_glazing_over_opaque(local, g.triangles, g.layer, windows, g.parts, g.part, where)
    scene.warnings.extend(partly)
    for spec in project.rooms:
        if spec.auto:
            from en17037cli.scene.auto_rooms import auto_rooms

            scene.rooms.extend(auto_rooms(scene, spec, f"{where}: rooms[{spec.index}]"))
        elif spec.ifc_spaces is not None or spec.gbxml_spaces is not None:
            scene.rooms.extend(rooms_from_spaces(scene, spec, f"{where}: rooms[{spec.index}]"))
        else:
            scene.rooms.append(make_room(scene, spec, f"{where}: rooms[{spec.index}] '{spec.name}'"))
    check_shared_floors(scene.rooms, scene.origin, f"{where}: rooms")
    names = [r.name for r in scene.rooms]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise InputError(f"{where}: rooms: room name '{dupes[0]}' is used twice (a named room and an IfcSpace, or two "
                         "rooms[] entries matching one space); give each room its own name")
    quarantine_windows(scene, hidden)  # after the rooms: which of them each would have lit
    scene.notes.extend(join_openings(scene))  # one window per opening, whatever the format
    for i, room in enumerate(scene.rooms):  # indices in the scene's order: ray groups and reports follow it
        room.index = i
    assign_kinds(scene, project)  # what each room is used for, and what its uses ask of it
    if scene.context:
        from en17037cli.scene.context import context_warnings

        scene.warnings.extend(context_warnings(scene, project.model.files, where))
    return scene
