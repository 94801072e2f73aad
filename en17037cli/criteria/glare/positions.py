"""The critical positions of clause 5.4: where the eye is and which way it looks.

EN 17037 leaves the positions to the designer: "the expected worst condition, close to the facade,
with the sun in the occupant's field of view". ``positions: auto`` puts, for each window of a room,
one eye ``facade_distance_m`` (1.0 m) into the room from the centre of its glazing at
``eye_height_m`` (1.2 m, seated) above the floor, looking towards the facade (the window's outward
normal) and parallel to it both ways (``directions``); an eye the floor does not hold (a shallow
room, a bay) is moved to the nearest point 0.1 m inside it. Listed positions (model frame [m],
``direction_deg`` a compass bearing) belong to the room whose floor holds them between its floor
and ceiling. Directions are horizontal; bearings are clockwise from true north, as every angle of
the project.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from en17037cli.errors import InputError, NotAssessable
from en17037cli.scene.model import Room, Scene

#: An auto eye the floor does not hold is moved this far inside it [m].
INSIDE_M = 0.1


@dataclass(frozen=True)
class View:
    """One critical position and view direction.

    eye : (3,) local frame [m]; direction : (3,) unit, horizontal; bearing_deg : compass [deg]
    position : index of the eye in the room (views of one eye share its rays)
    label : ``window 'W1', towards`` or ``listed 2``
    """

    eye: np.ndarray
    direction: np.ndarray
    bearing_deg: float
    position: int
    label: str


def bearing_deg(direction, true_north_deg: float) -> float:
    """Compass bearing [deg, clockwise from true north] of a horizontal direction in the model frame
    (true north ``true_north_deg`` clockwise from +Y)."""
    return (math.degrees(math.atan2(direction[0], direction[1])) - true_north_deg) % 360.0


def direction_of(bearing: float, true_north_deg: float) -> np.ndarray:
    """Unit horizontal direction in the model frame of a compass bearing [deg]."""
    a = math.radians(bearing + true_north_deg)
    return np.array([math.sin(a), math.cos(a), 0.0])


def auto_views(scene: Scene, room: Room, eye_height_m: float, facade_distance_m: float,
               directions: tuple[str, ...]) -> list[View]:
    """The auto positions of a room (module docstring), one eye per window."""
    import shapely

    out: list[View] = []
    floor = room.floor
    inner = floor.buffer(-INSIDE_M)
    for k, w in enumerate(room.windows):  # a few windows per room
        n = np.asarray(w.normal, dtype=float)
        nh = np.array([n[0], n[1], 0.0])
        if np.linalg.norm(nh) < 1e-6:  # a roof light: look along the room's longer side, from under it
            nh = np.array([0.0, 1.0, 0.0])
        nh /= np.linalg.norm(nh)
        c = w.centroid
        xy = c[:2] - facade_distance_m * nh[:2]
        if not floor.contains(shapely.Point(xy)) and not inner.is_empty:
            from shapely.ops import nearest_points

            xy = np.array(nearest_points(inner, shapely.Point(xy))[0].coords[0])
        eye = np.array([xy[0], xy[1], room.floor_z + eye_height_m])
        dirs = []
        if "towards" in directions:
            dirs.append(("towards", nh))
        if "parallel" in directions:
            side = np.array([-nh[1], nh[0], 0.0])
            dirs += [("parallel, left", side), ("parallel, right", -side)]
        for words, d in dirs:
            out.append(View(eye, d, bearing_deg(d, scene.true_north_deg), k, f"window '{w.name}', {words}"))
    return out


def listed_views(scene: Scene, positions: np.ndarray) -> dict[str, list[View]]:
    """The listed positions by room name; an :class:`InputError` naming a position no room holds."""
    import shapely

    out: dict[str, list[View]] = {}
    pts = scene.to_local(positions[:, :3])
    for i, (p, b) in enumerate(zip(pts, positions[:, 3])):  # a few listed eyes
        room = next((r for r in scene.rooms if r.problem is None and r.floor.buffer(1e-6).contains(shapely.Point(p[:2]))
                     and r.floor_z - 1e-6 <= p[2] <= min(r.ceiling_z, r.floor_z + 10.0)), None)
        if room is None:
            raise InputError(f"glare.positions[{i}]: ({positions[i, 0]:g}, {positions[i, 1]:g}, {positions[i, 2]:g}) stands "
                             "over no room's floor between floor and ceiling; give a point inside a room (model frame, metres)")
        views = out.setdefault(room.name, [])
        views.append(View(p, direction_of(float(b), scene.true_north_deg), float(b) % 360.0, len(views),
                          f"listed position {i + 1}"))
    return out


def room_views(scene: Scene, room: Room, settings, cache: dict) -> list[View]:
    """The views of a room: listed, else auto; a :class:`NotAssessable` where there are none."""
    if settings.positions is not None:
        if "glare_listed" not in cache:
            cache["glare_listed"] = listed_views(scene, settings.positions)
        views = cache["glare_listed"].get(room.name, [])
        if not views:
            raise NotAssessable("no listed glare position stands in the room (glare.positions)")
        return views
    if not room.windows:
        raise NotAssessable("the room has no window")
    return auto_views(scene, room, settings.eye_height_m, settings.facade_distance_m, settings.directions)
