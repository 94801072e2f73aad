"""Whether the model shows surroundings in front of a room's windows: without them the view's
layers cannot be judged.

EN 17037 Table A.5 needs the landscape layer (buildings, nature) in the view for every level. A
building exported on its own has no face on the ``landscape`` layer, and every room's layers would
read 'none' whatever the design: the view is then not assessable (:func:`no_landscape`). A model
with a few landscape objects is the same case in disguise: a tree in the garden, an awning and a
ladder on the facade, a fireplace (ArchiCAD writes such objects as IfcBuildingElementProxy, which
reads as landscape), or a gbXML's Shade surfaces (the building's own balconies). The rooms that
look out where the model has nothing failed on the layers at level 'none' (ArchiCAD 13's family
house: 4 rooms), with nothing saying the model has no surroundings there.

The rule: a room's layers can be judged where, in front of at least one of its wall windows, the
model's landscape covers at least ``view.surroundings_min_share`` (0.25 by default) of the horizon:
the azimuths within 90 deg of the window's outward normal, seen from the glazing's centre, over
which some standing landscape face lies at least :data:`MIN_DEPTH_M` in front of the glazing's
plane (the building's own overhangs, balconies and fittings on its facade are nearer). Standing
(:func:`standing_landscape`): steeper than 45 deg, of an object at least :data:`MIN_HEIGHT_M`
tall: a neighbour's wall, a tree. What lies flat or low on the ground is not surroundings even on
the landscape layer: Revit's topography and its sub-regions, parking bays, road markings, kerbs,
bicycles and bollards exported as IfcBuildingElementProxy (FM_ARC_DigitalHub, Revit 2019: its
terrain covered 84-93 % of every room's horizon, and 7 upper-floor rooms with no tree in front
failed at 'none' on the layers, nothing said). A street of neighbours, a city tile, a wood covers
most of the horizon; a tree or a shed a sliver. Elsewhere the
room's view is not assessable, as on a model with no landscape at all, whatever its layers read:
'none' for want of surroundings, or a level reached on a shed or on the building's own awning
(which reads as landscape); ``view.surroundings_min_share: 0`` judges them on what the model has.
A room lit by roof lights only is judged as before.
"""
from __future__ import annotations

import numpy as np

from en17037cli.scene.model import LANDSCAPE, Room, Scene

#: Landscape faces nearer the glazing's plane than this are the building's own (an awning, a
#: balcony, a ladder on the facade), not its surroundings [m].
MIN_DEPTH_M = 2.0
#: Glazing whose normal is steeper than this (|n_z|) is a roof light: it shows no horizon.
ROOF_NZ = 0.5
#: A landscape face stands where its normal is flatter than this (|n_z|: steeper than 45 deg) ...
STANDING_NZ = float(np.cos(np.radians(45.0)))
#: ... and its object rises at least this high [m] (a storey, a young tree; not a kerb, a bicycle, a car).
MIN_HEIGHT_M = 2.0


def no_landscape(scene: Scene) -> str | None:
    """Why the view layers cannot be judged on ``scene``, or None: a model with no face on the
    ``landscape`` layer (a building exported without its surroundings) shows no landscape from any
    window, so every room's layers would read 'none' (EN 17037 Table A.5 needs the landscape layer
    for every level) whatever the design. Not a failure of the design: not assessable."""
    if (scene.layer == LANDSCAPE).any():
        return None
    return ("the view layers cannot be assessed: the model has no landscape (no face on the 'landscape' layer: no "
            "neighbouring buildings, trees or terrain), and EN 17037 Table A.5 needs the landscape layer for every level; "
            "add the surroundings as another model file (a CityJSON tile, an OBJ of the neighbours) or put objects on "
            "'landscape' with a layer rule")


def horizon_share(scene: Scene, window) -> float | None:
    """Share [-] of the horizon in front of a wall window (azimuths within 90 deg of its outward
    normal, from its centre) over which a standing landscape face (:func:`standing_landscape`) lies
    wholly at least :data:`MIN_DEPTH_M` in front of its plane; None for a roof light. The faces'
    azimuth intervals (each triangle's vertices in front of the window span an interval of less
    than 180 deg) are merged exactly."""
    n = np.asarray(window.normal, float)
    h = np.hypot(n[0], n[1])
    if abs(n[2]) >= ROOF_NZ or h == 0:
        return None
    if "landscape_xy" not in scene.cache:  # (f, 3, 2) plan of every standing landscape face, once per scene
        scene.cache["landscape_xy"] = scene.faces_of(standing_landscape(scene))[..., :2]
    xy = scene.cache["landscape_xy"]
    if not len(xy):
        return 0.0
    ahead, across = n[:2] / h, np.array([-n[1], n[0]]) / h
    rel = xy - window.centroid[:2]
    d = rel @ ahead  # (f, 3) [m] in front of the glazing's plane
    keep = d.min(axis=1) >= MIN_DEPTH_M
    if not keep.any():
        return 0.0
    ang = np.arctan2(rel[keep] @ across, d[keep])  # (k, 3) [rad] in (-pi/2, pi/2)
    lo, hi = ang.min(axis=1), ang.max(axis=1)
    order = np.argsort(lo)
    lo, hi = lo[order], hi[order]
    reach = np.maximum.accumulate(hi)
    starts = np.flatnonzero(np.r_[True, lo[1:] > reach[:-1]])  # each run of overlapping intervals
    covered = np.maximum.reduceat(hi, starts) - lo[starts]
    return float(covered.sum() / np.pi)


def standing_landscape(scene: Scene) -> np.ndarray:
    """(m,) bool: the landscape faces that stand: steeper than 45 deg (|n_z| <= :data:`STANDING_NZ`)
    and of an object (part) whose landscape faces span at least :data:`MIN_HEIGHT_M` in height."""
    land = scene.layer == LANDSCAPE
    out = np.zeros(len(land), bool)
    idx = np.flatnonzero(land)
    if not len(idx):
        return out
    tri = scene.vertices[scene.triangles[idx]]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    nz = np.abs(n[:, 2]) / np.maximum(np.linalg.norm(n, axis=1), 1e-300)
    part = scene.part[idx]
    lo, hi = np.full(len(scene.parts), np.inf), np.full(len(scene.parts), -np.inf)
    np.minimum.at(lo, part, tri[..., 2].min(axis=1))
    np.maximum.at(hi, part, tri[..., 2].max(axis=1))
    out[idx] = (nz <= STANDING_NZ) & (hi[part] - lo[part] >= MIN_HEIGHT_M)
    return out


def sparse_surroundings(scene: Scene, room: Room, min_share: float) -> str | None:
    """Why the layers of ``room`` cannot be judged on a model that has landscape, or None: in front
    of none of its wall windows does the landscape cover ``min_share`` of the horizon (see the
    module docstring)."""
    shares = [s for s in (horizon_share(scene, w) for w in room.windows) if s is not None]
    if not shares or max(shares) >= min_share:
        return None
    parts = np.unique(scene.part[scene.layer == LANDSCAPE])
    names = ", ".join(f"'{scene.parts[p].label or scene.part_label(p)}'" for p in parts[:3]) + (" ..." if len(parts) > 3 else "")
    return (f"the view layers cannot be assessed: the model has no surroundings in front of the room's windows (its "
            f"landscape standing {MIN_HEIGHT_M:g} m or more covers {max(shares):.0%} of the horizon in front of them, "
            f"{min_share:.0%} needed to judge the layers; the landscape layer holds {len(parts)} object(s): {names}; what lies "
            "flat or low, terrain, markings, bicycles, is no surroundings), and EN 17037 Table A.5 needs the landscape layer "
            "for every level; add the surroundings as another model file (a CityJSON tile, an OBJ of the neighbours), or "
            "set view.surroundings_min_share to judge them on what the model has")
