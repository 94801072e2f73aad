"""Building a :class:`~en17037cli.scene.model.Scene` from a project's settings.

Data flow: read each model file, scale it to metres, turn y-up files to z-up, assign every face
a layer, drop degenerate faces (:mod:`~en17037cli.scene.load`), shift everything to a local
origin (float64), find the windows (:mod:`~en17037cli.scene.windows`) and each room's floor and
windows (:mod:`~en17037cli.scene.rooms`). Engines receive a Scene and never read files.
"""
from __future__ import annotations

import numpy as np

from en17037cli.errors import InputError
from en17037cli.project.settings import Project
from en17037cli.scene.load import load_geometry
from en17037cli.scene.model import WINDOW, Scene
from en17037cli.scene.rooms import make_room
from en17037cli.scene.windows import check_glazing_over_opaque, find_windows


def build_scene(project: Project) -> Scene:
    """Load the project's geometry and resolve windows and rooms (see module docstring)."""
    where = project.path.name
    g = load_geometry(project.model, where)
    win_mask = g.layer == WINDOW
    if not np.any(win_mask):
        raise InputError(f"{where}: model.files: no face is on the 'window' layer; assign the glazing to layer: window")
    # Local origin: centre of the windows' bounding box, float64 (see trimesh/ray/ray_pyembree.py).
    wv = g.vertices[g.triangles[win_mask]].reshape(-1, 3)
    origin = 0.5 * (wv.min(axis=0) + wv.max(axis=0))
    local = g.vertices - origin
    windows = find_windows(local, g.triangles, np.flatnonzero(win_mask), g.parts, g.part)
    scene = Scene(vertices=local, triangles=g.triangles, layer=g.layer, obstructs_sun=g.obstructs_sun, parts=g.parts,
                  part=g.part, notes=g.notes, warnings=g.warnings, file_hashes=g.file_hashes, origin=origin,
                  windows=windows, true_north_deg=project.model.true_north_deg)
    check_glazing_over_opaque(local, g.triangles, g.layer, windows, scene.part_label, g.part, where)
    for spec in project.rooms:
        scene.rooms.append(make_room(scene, spec, f"{where}: rooms[{spec.index}] '{spec.name}'"))
    return scene
