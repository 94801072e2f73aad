"""The steep sides of ground-type city objects: landscape, not ground.

A ground-type object (the ``ground`` rows of :mod:`~en17037cli.io.cityjson.semantics`:
``LandUse``, ``PlantCover`` given as surfaces, ``Road``, ``WaterBody``, ``TINRelief``...) is the
ground the view looks down on. Real tiles also draw such objects as blocks: Delft's LoD1
PlantCover are prisms up to 16 m tall (a park's trees as one block), its LandUse and Road carry
walls and embankments up to 2.5 m. Their sides stand above the ground like a hedge or a wall, so
the faces that are steep (tilted :data:`STEEP_TILT_DEG` or more from the horizontal) and reach
more than :data:`RISE_M` above their object's base (its lowest point) go to a part of their own,
``slope: steep``, on the ``landscape`` layer; kerbs and gentle banks stay ground. A layer rule
that matches the object (``{class: PlantCover, layer: ground}``) places both parts, so the project
can undo it; ``match: steep`` finds the sides alone.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry import triangle_normals
from en17037cli.io.cityjson.semantics import counted
from en17037cli.io.mesh import Part

#: A face tilted at least this far from the horizontal is steep [deg] (|n_z| <= cos 60 deg = 0.5):
#: a block's sides (90 deg), a wall; not a terrain's bank or a ramp.
STEEP_TILT_DEG = 60.0
#: ... and stands above the ground when its top is more than this above its object's base [m]:
#: higher than a kerb (0.1-0.2 m), lower than a hedge or a garden wall.
RISE_M = 0.5


def steep_sides(vertices: np.ndarray, tris: np.ndarray, part: np.ndarray, parts: list[Part], name: str,
                notes: list) -> tuple[np.ndarray, list[Part]]:
    """Move the steep, high faces of ground-type objects to landscape parts of their own.

    Parameters
    ----------
    vertices : (n, 3) float64 [m]; tris : (m, 3) int64; part : (m,) int64 index into ``parts``
    parts : the reader's parts (``layer`` the class table's default; ``attrs['id']`` the object)
    name : the file's name, for the note; notes : the reader's notes (one is appended when faces move)

    Returns
    -------
    part : (m,) int64, the moved faces pointing at the new parts
    parts : ``parts`` with one ``slope: steep`` landscape part per ground part that lost faces,
        appended in the order of those parts
    """
    ground = np.fromiter((p.layer == "ground" for p in parts), dtype=bool, count=len(parts))
    if len(tris) == 0 or not ground.any():
        return part, parts
    rows = np.flatnonzero(ground[part])
    if len(rows) == 0:
        return part, parts
    ids: dict = {}
    obj_of_part = np.array([ids.setdefault(p.attrs.get("id", f"#{i}"), len(ids)) for i, p in enumerate(parts)], dtype=np.int64)
    z = vertices[:, 2][tris]  # (m, 3)
    tri_obj = obj_of_part[part]
    base = np.full(len(ids), np.inf)
    np.minimum.at(base, tri_obj, z.min(axis=1))
    normals, areas = triangle_normals(vertices[tris[rows]])
    steep = ((areas > 0) & (np.abs(normals[:, 2]) <= np.cos(np.radians(STEEP_TILT_DEG)) + 1e-12)
             & (z[rows].max(axis=1) - base[tri_obj[rows]] > RISE_M))
    rows = rows[steep]
    if len(rows) == 0:
        return part, parts
    parts = list(parts)
    remap = np.arange(len(parts), dtype=np.int64)
    for p in np.unique(part[rows]).tolist():
        remap[p] = len(parts)
        src = parts[p]
        parts.append(Part({**src.attrs, "slope": "steep"}, layer="landscape", obstructs_sun=src.obstructs_sun))
    part = part.copy()
    part[rows] = remap[part[rows]]
    cls_of_obj: dict = {}
    for i, o in enumerate(obj_of_part.tolist()):
        cls_of_obj.setdefault(o, parts[i].attrs.get("class", "?"))
    objs = sorted({int(o) for o in tri_obj[rows]})
    by_class: dict = {}
    for o in objs:
        by_class[cls_of_obj[o]] = by_class.get(cls_of_obj[o], 0) + 1
    detail = ", ".join(f"{k} {v}" for k, v in by_class.items())
    notes.append(f"{name}: {counted(len(rows), 'steep face')} of {counted(len(objs), 'ground-type object')} ({detail}) "
                 f"rising more than {RISE_M:g} m above their object's base given layer landscape, with slope: steep (the "
                 "sides of a block of vegetation, a wall, an embankment stand above the ground); a layer rule matching "
                 "the object places them too")
    return part, parts
