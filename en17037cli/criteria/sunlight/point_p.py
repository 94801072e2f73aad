"""Point P of EN 17037 Annex A.3: where the sunlight of a window is judged."""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.errors import NotAssessable
from en17037cli.geometry import window_axes
from en17037cli.project.settings import SunSettings
from en17037cli.raytrace import RayEngine
from en17037cli.scene.hosts import reveal_depth_from_host
from en17037cli.scene.model import GLAZING_OFFSET_M, Room, Scene, Window

#: Start of the reveal search, outside the glazing plane [m], and the lateral steps beyond a jamb of
#: the glass [m]: the first lands in the reveal of a wall that meets the glass, the others beyond a
#: window frame up to 23 cm wide (BIM windows: the glass sits in a frame, the frame in the opening).
REVEAL_PROBE_OUTSIDE_M = 0.01
REVEAL_PROBE_BEYOND_JAMB_M = (0.02, 0.12, 0.25)
#: Glazing whose normal's vertical component is at least this is roof glazing (tilted more than
#: 30 degrees from vertical): where A.3's height falls outside it, P is its centre.
ROOF_GLAZING_MIN_NZ = 0.5
#: Where the room is a space of the model and the model names no host, a probed reveal ends at most
#: this far beyond where the space begins [m] (a space drawn to the finish, short of the wall's face):
#: a lintel, a shelf or a wall top inside the room is not the room-side plane of the opening.
SPACE_REVEAL_SLACK_M = 0.15


#: Faces parallel to the glazing this far from the window's outline count for a candidate plane's
#: extent [m] (:func:`reveal_depth`) ...
PLANE_NEIGHBOURHOOD_M = 1.0
#: ... and the room-side plane of the opening is the deepest candidate with at least this share of
#: the most extensive one's area (the wall's face, not a door's architrave or a frame's inner face).
PLANE_MIN_SHARE = 0.5


def plane_areas(scene: Scene, window: Window, normal: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """(c,) [m2]: area of the ``interior`` faces parallel to the window (|cos| > 0.9) lying in each
    plane ``normal . x = offsets[c]`` (within 1 mm) and within :data:`PLANE_NEIGHBOURHOOD_M` of the
    window's outline. Vectorised over faces; the interior faces' normals are computed once per scene."""
    from en17037cli.geometry import triangle_normals
    from en17037cli.scene.model import INTERIOR

    cache = getattr(scene, "cache", {})  # stand-in scenes in tests have none
    cached = cache.get("interior_planes")
    if cached is None:
        ids = np.flatnonzero(scene.layer == INTERIOR)
        tri = scene.vertices[scene.triangles[ids]]
        nrm, area = triangle_normals(tri)
        cached = cache["interior_planes"] = (tri.min(axis=1), tri.max(axis=1), tri.mean(axis=1), nrm, area)
    lo, hi, centre, nrm, area = cached
    w = window.triangles.reshape(-1, 3)
    grow = PLANE_NEIGHBOURHOOD_M
    near = np.all((lo <= w.max(axis=0) + grow) & (hi >= w.min(axis=0) - grow), axis=1) & (np.abs(nrm @ normal) > 0.9)
    off = centre[near] @ normal
    return np.array([float(area[near][np.abs(off - o) <= 1e-3].sum()) for o in offsets])  # a few candidates


def reveal_depth(engine: RayEngine, scene: Scene, start: np.ndarray, normal: np.ndarray, axis: np.ndarray, half_width: float,
                 max_depth: float, window: Window | None = None) -> float:
    """Depth of the room-side plane of the opening behind the glazing plane [m].

    Probes start just outside the glazing plane, 2, 12 and 25 cm beyond each jamb of the glass
    (inside the wall, or the window's frame, if they have thickness), and run inwards along -normal
    through the interior faces; every face parallel to the window (|cos| > 0.9) they cross within
    ``max_depth`` is a candidate plane. The room-side plane is the deepest candidate whose extent
    around the window (:func:`plane_areas`) is at least :data:`PLANE_MIN_SHARE` of the largest
    one's: the wall's inner face, not a frame's inner face in front of it, nor a door's casing or
    architrave standing a few centimetres proud of it. Without ``window`` (stand-ins), the deepest.
    Zero where the wall has no thickness or no wall flanks the window.

    Parameters
    ----------
    start : (3,) point on the glazing plane at the horizontal centre [m]
    normal, axis : (3,) outward normal and horizontal width axis (unit)
    half_width, max_depth : float [m]
    """
    off = half_width + np.asarray(REVEAL_PROBE_BEYOND_JAMB_M)
    origins = np.concatenate([start + off[:, None] * axis, start - off[:, None] * axis]) + REVEAL_PROBE_OUTSIDE_M * normal
    dirs = np.tile(-normal, (len(origins), 1))
    travelled = np.zeros(len(origins))
    found: list[float] = []
    for _ in range(4):  # a few crossings: outer face, inner face, beyond
        face, t = engine.first_hit("interior", origins, dirs)
        hit = face >= 0
        if not hit.any():
            break
        v = scene.vertices[scene.triangles[np.maximum(face, 0)]]  # the faces hit, not the whole scene
        fn = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        cos = np.abs(fn @ normal) / np.maximum(np.linalg.norm(fn, axis=1), 1e-30)
        depth = travelled + np.where(hit, t, np.inf) - REVEAL_PROBE_OUTSIDE_M
        ok = hit & (cos > 0.9) & (depth <= max_depth)
        found.extend(float(d) for d in depth[ok])
        step = np.where(hit, t, 0)
        step = step + engine.restart_offset(origins + step[:, None] * dirs)
        origins = origins + step[:, None] * dirs
        travelled = travelled + step
        if not np.any(hit & (depth <= max_depth)):
            break
    depths = np.array([d for d in found if d > 0])
    if len(depths) == 0:
        return 0.0
    planes = np.unique(np.round(depths / 1e-3))  # candidates a millimetre apart are one plane
    if window is None or len(planes) == 1 or not hasattr(scene, "layer"):  # stand-ins: the deepest
        return float(depths.max())
    areas = plane_areas(scene, window, normal, start @ normal - planes * 1e-3)
    chosen = planes[areas >= PLANE_MIN_SHARE * areas.max()].max()
    return float(depths[np.round(depths / 1e-3) == chosen].max())


def point_p_height(room: Room, window: Window) -> float:
    """Height of point P [m, local]: max(floor + 1.2 m, sill + 0.3 m) (EN 17037 Annex A.3).

    Roof glazing (a roof light, a skylight: :data:`ROOF_GLAZING_MIN_NZ`) where that height falls
    outside it: the height of its centre. A.3 places P by heights above floor and sill, which a
    horizontal opening does not have; this tool takes its centre on the room-side face of the
    opening (a choice, documented in docs/bim.md).

    Raises
    ------
    NotAssessable
        Where that height lies above the head of a wall window (a small or high window): the rule
        has no point P in the opening.
    """
    z_p = max(room.floor_z + standard.SUN_POINT_MIN_ABOVE_FLOOR_M, window.sill_z + standard.SUN_POINT_MIN_ABOVE_SILL_M)
    normal = getattr(window, "normal", None)  # stand-ins in tests may have none: a wall window
    if z_p > window.head_z + 1e-9 and normal is not None and abs(normal[2]) >= ROOF_GLAZING_MIN_NZ:
        return float(window.centroid[2])
    if z_p > window.head_z + 1e-9:
        raise NotAssessable(
            f"window '{window.name}': point P at max(floor + 1.2 m, sill + 0.3 m) = {z_p - room.floor_z:.3f} m above the "
            f"floor lies above the window head ({window.head_z - room.floor_z:.3f} m); give rooms[].sun_points to assess it")
    return z_p


def point_p(engine: RayEngine, scene: Scene, room: Room, window: Window, settings: SunSettings) -> tuple[np.ndarray, float, list]:
    """Point P of a window (local frame) by EN 17037 Annex A.3, its reveal depth [m] and notes.

    On the room-side plane of the opening, at the horizontal centre of the window, at height
    :func:`point_p_height`. Where the model says which element the opening is cut in (the host
    wall: ``Window.host``), that plane is the host's face behind the glazing
    (:func:`~en17037cli.scene.hosts.reveal_depth_from_host`), and nothing else in the room moves
    P; otherwise it is probed (:func:`reveal_depth`).
    """
    n = window.normal
    a, up = window_axes(n)
    verts = window.triangles.reshape(-1, 3)
    s = verts @ a
    c = window.centroid
    centre = c + (0.5 * (s.min() + s.max()) - c @ a) * a
    z_p = point_p_height(room, window)
    if abs(up[2]) > 1e-9:
        q = centre + ((z_p - centre[2]) / up[2]) * up
    else:
        q = centre
    depth = reveal_depth_from_host(scene, window, q, settings.max_reveal_depth_m)
    notes = []
    if depth is None:
        depth = reveal_depth(engine, scene, q, n, a, 0.5 * (s.max() - s.min()), settings.max_reveal_depth_m, window)
        space = getattr(window, "space_distance_m", None)
        if space is not None and depth > max(space, 0.0) + SPACE_REVEAL_SLACK_M:  # not deeper than the room's space begins
            depth = max(space, 0.0) + SPACE_REVEAL_SLACK_M
            notes.append(f"room '{room.name}', window '{window.name}': the model names no host for it and the probe "
                         f"behind it met a face inside the room; P lies {depth:.2f} m behind the glazing, "
                         f"{SPACE_REVEAL_SLACK_M:.2f} m beyond where the room's space begins")
    open_depth = min(float(getattr(window, "open_depth_m", 0.0)), settings.max_reveal_depth_m)
    if open_depth > depth:  # the opening runs on, open, to the room's space: its room-side end is there
        depth = open_depth
        notes.append(f"room '{room.name}', window '{window.name}': P lies {depth:.2f} m behind the glazing, where the "
                     "open path from it (a light well) meets the room's space")
    if depth < GLAZING_OFFSET_M:  # no reveal, or only the wall's own plane found again through round-off
        depth = 0.0
    if depth > 0:
        p = q - depth * n
    else:
        p = q - GLAZING_OFFSET_M * n
        notes.append(f"room '{room.name}', window '{window.name}': P lies on the glazing plane (no reveal found) and was moved {GLAZING_OFFSET_M * 1000:.0f} mm into the room")
    return p, depth, notes
