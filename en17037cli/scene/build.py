"""Building a :class:`~en17037cli.scene.model.Scene` from a project's settings.

Data flow: read each model file, scale it to metres, turn y-up files to z-up, place it, assign
every face a layer, drop degenerate faces (:mod:`~en17037cli.scene.load`), shift everything to a
local origin (float64), find the windows (:mod:`~en17037cli.scene.windows`), take true north and
the location from the model where the project leaves them out, and make each room's floor and
windows (:mod:`~en17037cli.scene.rooms`; rooms from IfcSpaces with :mod:`~en17037cli.scene.spaces`).
Engines receive a Scene and never read files.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from en17037cli.errors import InputError
from en17037cli.project.settings import Location, Project
from en17037cli.scene.load import load_geometry
from en17037cli.scene.model import INTERIOR, WINDOW, Geometry, Scene
from en17037cli.scene.rooms import check_shared_floors, make_room
from en17037cli.scene.spaces import rooms_from_spaces
from en17037cli.scene.windows import check_glazing_over_opaque, find_windows


def resolve_north(project: Project, g: Geometry) -> tuple[float, dict | None]:
    """True north [deg clockwise from +Y]: the project's, else the first model file's own (its
    TrueNorth turned with the file's rotation), else 0."""
    if project.model.true_north_deg is not None:
        return project.model.true_north_deg, None
    for _display, site, rotate_deg in g.sites:
        if site.true_north_deg is not None:
            north = (site.true_north_deg - rotate_deg) % 360.0
            return north, {"value": round(north, 6), "source": site.source + (f", turned by the file's transform ({rotate_deg:g} deg)"
                                                                             if rotate_deg else "")}
    return 0.0, None


def resolve_location(project: Project, g: Geometry, where: str) -> tuple[Location | None, dict]:
    """The project's location with a latitude or longitude it leaves out taken from the model's IfcSite."""
    loc = project.location
    out: dict = {}
    if loc is None or (loc.latitude is not None and loc.longitude is not None):
        return loc, out
    site = next((s for _, s, _ in g.sites if s.latitude is not None and s.longitude is not None), None)
    if site is None:
        raise InputError(f"{where}: location.latitude: not given, and no model file says where it stands (an IfcSite's "
                         "RefLatitude, a gbXML Campus/Location); give location.latitude and location.longitude")
    lat = loc.latitude if loc.latitude is not None else site.latitude
    lon = loc.longitude if loc.longitude is not None else site.longitude
    for key, value, given in (("latitude", lat, loc.latitude), ("longitude", lon, loc.longitude)):
        if given is None:
            out[f"location.{key}"] = {"value": value, "source": site.source}
    return replace(loc, latitude=lat, longitude=lon), out


def building_centre(g: Geometry) -> np.ndarray:
    """A point inside the building [m, world]: the centre of the interior faces' bounding box."""
    faces = g.triangles[g.layer == INTERIOR] if np.any(g.layer == INTERIOR) else g.triangles
    v = g.vertices[faces].reshape(-1, 3)
    return 0.5 * (v.min(axis=0) + v.max(axis=0))


def build_scene(project: Project) -> Scene:
    """Load the project's geometry and resolve windows and rooms (see module docstring)."""
    where = project.path.name
    g = load_geometry(project.model, where)
    win_mask = g.layer == WINDOW
    if not np.any(win_mask):
        unread = "".join(f"; {label} ({display}): {why}" for display, label, why in g.windows_left_out[:3])
        raise InputError(f"{where}: model.files: no face is on the 'window' layer; assign the glazing to layer: window{unread}")
    # Local origin: centre of the windows' bounding box, float64 (see trimesh/ray/ray_pyembree.py).
    wv = g.vertices[g.triangles[win_mask]].reshape(-1, 3)
    origin = 0.5 * (wv.min(axis=0) + wv.max(axis=0))
    local = g.vertices - origin
    windows, dropped = find_windows(local, g.triangles, np.flatnonzero(win_mask), g.parts, g.part,
                                    building_centre(g) - origin)
    if len(dropped):
        g.notes.append(f"{len(dropped)} glazing faces of glass modelled as thin solids (inner faces, rims) left out: "
                       "each pane keeps its outer face")
    north, north_src = resolve_north(project, g)
    location, resolved = resolve_location(project, g, where)
    if north_src:
        resolved["model.true_north_deg"] = north_src
    scene = Scene(vertices=local, triangles=g.triangles, layer=g.layer, obstructs_sun=g.obstructs_sun, parts=g.parts,
                  part=g.part, notes=g.notes, warnings=[*project.warnings, *g.warnings], file_hashes=g.file_hashes,
                  sites=g.sites, spaces=g.spaces, optics=g.optics, read=g.read, windows_left_out=g.windows_left_out,
                  context=g.context,
                  origin=origin, windows=windows, true_north_deg=north, location=location, resolved=resolved)
    scene.warnings.extend(check_glazing_over_opaque(local, g.triangles, g.layer, windows, g.parts, g.part, where))
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
    for i, room in enumerate(scene.rooms):  # indices in the scene's order: ray groups and reports follow it
        room.index = i
    if scene.context:
        from en17037cli.scene.context import context_warnings

        scene.warnings.extend(context_warnings(scene, project.model.files, where))
    return scene
