"""What the report's plan maps need of a room beyond its view result: the floor, the utilised area
and the windows' traces in plan, in the model's coordinates."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.geometry.triangles import window_axes
from en17037cli.project.settings import ViewSettings
from en17037cli.scene.model import Room, Scene


@dataclass
class RoomPlan:
    """A room in plan [m, model frame xy].

    floor : (k, 2) ring of the floor outline; utilised : (k, 2) ring of the utilised area (floor
    inset by ``view.wall_margin_m``), or None for explicit viewpoints; windows : per window its
    trace in plan (2, 2), the glazing's extreme points along its horizontal axis; spacing_m : the
    viewpoint grid's spacing, or None for explicit viewpoints
    """

    floor: np.ndarray
    utilised: np.ndarray | None
    windows: list[np.ndarray]
    spacing_m: float | None
    true_north_deg: float


def window_trace(triangles: np.ndarray, normal) -> np.ndarray:
    """(2, 2) [m]: a window's two extreme points in plan along its horizontal axis (local frame)."""
    a, _ = window_axes(np.asarray(normal, float))
    pts = triangles.reshape(-1, 3)
    s = pts @ a
    c = pts.mean(axis=0)
    ends = c[None, :] + (np.array([s.min(), s.max()]) - c @ a)[:, None] * a[None, :]
    return ends[:, :2]


def room_plan(scene: Scene, room: Room, settings: ViewSettings) -> RoomPlan:
    """The :class:`RoomPlan` of ``room`` as the view criterion laid its viewpoints out."""
    o = scene.origin[:2]
    floor = np.asarray(room.floor.simplify(1e-4).exterior.coords)[:-1] + o  # drawn: 0.1 mm detail is enough
    explicit = room.spec.view_points is not None
    utilised = None
    if not explicit:
        u = room.floor.buffer(-settings.wall_margin_m, join_style="mitre")
        if not u.is_empty and u.geom_type == "Polygon":
            utilised = np.asarray(u.exterior.coords)[:-1] + o
    windows = [window_trace(w.triangles, w.normal) + o for w in room.windows]
    return RoomPlan(floor, utilised, windows, None if explicit else settings.grid_spacing_m, scene.true_north_deg)
