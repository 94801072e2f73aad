"""Where a BCF topic's camera stands and what it looks at: the point that limits a room's criterion
and the window that matters from there, in the scene's world frame [m].

- view: the viewpoint at the limiting eye height with the lowest level on the limiting criterion
  (ties: the smallest horizontal sight angle, then the first), looking at the window it sees under
  the largest solid angle;
- sunlight: point P of the window with the most hours on the assessed day (the room's best chance;
  ties: the first), looking out through that window along its outward normal;
- daylight: the point of the reference plane with the lowest daylight factor (method 1) or the
  lowest share of daylight hours at the target of the level measured to (method 2), looking at the
  window it sees under the largest solid angle;
- glare: the worst critical position, looking the way its view direction points;
- otherwise (not assessed, no point): the centre of the floor at 1.2 m, looking at the largest window.

The window "seen under the largest solid angle" is the one with the largest A |n . d| / |d|^2
(A its glazed area [m2], n its normal, d from the point to its centroid [m]): the small-angle
approximation of a planar patch's solid angle (Hecht, Optics, 5th ed., 5.7), enough to rank windows.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.scene.model import Room, Scene

#: Eye height of the fallback camera above the floor [m] (EN 17037 A.3's 1.2 m for P).
EYE_M = 1.2
#: A point closer than this to a window's plane looks out along the window's normal [m].
ON_GLASS_M = 0.05


@dataclass(frozen=True)
class Camera:
    """A camera in the scene's world frame.

    point : (3,) [m]; direction : (3,) unit vector; window : index of the window looked at in the
    room's windows, or None; how : what the point is, in words (for the topic's description)
    """

    point: np.ndarray
    direction: np.ndarray
    window: int | None
    how: str


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(v))
    return v / n if n > 0 else np.array([0.0, 1.0, 0.0])


def facing_window(scene: Scene, room: Room, point: np.ndarray) -> int | None:
    """Index of the room's window seen from ``point`` (world frame [m]) under the largest solid
    angle (A |n . d| / |d|^2, see the module docstring), or None for a room without windows."""
    if not room.windows:
        return None
    centroids = scene.to_world(np.array([w.centroid for w in room.windows]))
    d = centroids - point
    dist2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-6)
    normals = np.array([w.normal for w in room.windows])
    cos = np.abs(np.einsum("ij,ij->i", normals, d)) / np.sqrt(dist2)
    omega = np.array([w.area_m2 for w in room.windows]) * cos / dist2
    return int(np.argmax(omega))


def looking_at(scene: Scene, room: Room, point: np.ndarray, how: str, k: int | None = None) -> Camera:
    """A camera at ``point`` (world [m]) looking at window ``k`` of the room (the one seen largest
    where None): at its centroid, or out along its normal from a point on its glass (point P)."""
    k = facing_window(scene, room, point) if k is None else k
    if k is None:
        return Camera(point, np.array([0.0, 1.0, 0.0]), None, how)
    w = room.windows[k]
    c = scene.to_world(w.centroid)
    if abs(float((c - point) @ w.normal)) < ON_GLASS_M:
        return Camera(point, _unit(w.normal), k, how)
    return Camera(point, _unit(c - point), k, how)


def fallback(scene: Scene, room: Room) -> Camera:
    """The centre of the floor at :data:`EYE_M`, looking at the largest window."""
    c = room.floor.centroid if not room.floor.is_empty else None
    xy = (0.0, 0.0) if c is None else (c.x, c.y)
    point = scene.to_world(np.array([xy[0], xy[1], room.floor_z + EYE_M]))
    k = int(np.argmax([w.area_m2 for w in room.windows])) if room.windows else None
    return looking_at(scene, room, point, f"the middle of the floor at {EYE_M:g} m", k)


def view_camera(scene: Scene, room: Room, section: dict) -> Camera | None:
    lim = section.get("limiting") or {}
    eyes = [e for e in section.get("eye_heights", ()) if e.get("points")]
    if not eyes:
        return None
    eye = next((e for e in eyes if e["eye_height_m"] == lim.get("eye_height_m")), eyes[0])
    crit = lim.get("criterion") or "horizontal_sight_angle"
    rank = {"none": 0, "minimum": 1, "medium": 2, "high": 3}
    pts = eye["points"]
    worst = min(range(len(pts)), key=lambda i: (rank.get(pts[i]["level_by_criterion"].get(crit, "none"), 0),
                                                pts[i]["horizontal_sight_angle_deg"], i))
    words = crit.replace("_", " ")
    return looking_at(scene, room, np.array(pts[worst]["point"], float),
                      f"the viewpoint with the lowest {words} level at {eye['eye_height_m']:g} m eye height")


def sunlight_camera(scene: Scene, room: Room, section: dict) -> Camera | None:
    ws = [(i, w) for i, w in enumerate(section.get("windows", ())) if w.get("point_p_m") is not None]
    if not ws:
        return None
    i, w = max(ws, key=lambda iw: (iw[1].get("hours_h") or 0.0, -iw[0]))
    return Camera(np.array(w["point_p_m"], float), _unit(room.windows[i].normal), i,
                  f"point P of window '{w['name']}', looking out through it")


def daylight_camera(scene: Scene, room: Room, section: dict) -> Camera | None:
    pts = section.get("points") or []
    if not pts:
        return None
    if "daylight_factor_pct" in pts[0]:
        value, words = [p["daylight_factor_pct"] for p in pts], "daylight factor"
    else:
        lim = section.get("limiting") or {}
        lx = section["levels"][lim["level"]]["target_lx"] if lim.get("level") in section.get("levels", {}) else None
        key = f"{lx:g}" if lx is not None else next(iter(pts[0].get("share_of_hours", {"": 0})))
        value, words = [p.get("share_of_hours", {}).get(key, 0.0) for p in pts], f"share of hours at {key} lx"
    i = int(np.argmin(value))
    return looking_at(scene, room, np.array(pts[i]["point"], float), f"the point of the reference plane with the lowest {words}")


def glare_camera(scene: Scene, room: Room, section: dict) -> Camera | None:
    pos = section.get("positions") or []
    if not pos:
        return None
    p = pos[section.get("worst_position") or 0]
    a = np.radians(scene.true_north_deg + float(p["direction_deg"]))  # bearing from true north -> model frame
    return Camera(np.array(p["point"], float), np.array([np.sin(a), np.cos(a), 0.0]), None,
                  f"the worst critical position '{p['label']}'")


CAMERAS = {"view": view_camera, "sunlight": sunlight_camera, "daylight": daylight_camera, "glare": glare_camera}


def topic_camera(scene: Scene, room: Room, criterion: str, section: dict | None) -> Camera:
    """The camera of the topic of ``room`` and ``criterion`` (see the module docstring)."""
    cam = CAMERAS[criterion](scene, room, section) if section else None
    return cam if cam is not None else fallback(scene, room)
