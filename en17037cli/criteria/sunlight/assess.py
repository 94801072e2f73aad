"""The sunlight of a room (EN 17037 clause 5.3): point P per window, sun hours of every day, the assessed day."""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.criteria.sunlight.exact import SunSpline, exact_intervals, union_intervals
from en17037cli.criteria.sunlight.intervals import day_bounds, visible_intervals
from en17037cli.criteria.sunlight.point_p import point_p
from en17037cli.criteria.sunlight.results import SunlightResult
from en17037cli.criteria.sunlight.visibility import SunPath, SunVisibility
from en17037cli.errors import InputError, NotAssessable
from en17037cli.project.settings import Location, SunSettings
from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import Room, Scene, room_window_group
from en17037cli.standard import Thresholds


def assessed_day(hours: np.ndarray, dates: list, date: str) -> int:
    """Index of the day judged: ``worst`` (fewest hours), ``best`` (most) or the given MM-DD.

    Ties go to the earliest day (argmin/argmax return the first).
    """
    if date == "worst":
        return int(np.argmin(hours))
    if date == "best":
        return int(np.argmax(hours))
    return [d.strftime("%m-%d") for d in dates].index(date)


def assess_room(engine: RayEngine, scene: Scene, room: Room, settings: SunSettings, location: Location,
                thresholds: Thresholds, sun_path: SunPath | None = None) -> SunlightResult:
    """Sunlight result of one room: P per window, every day's hours and intervals, assessed date and
    level. ``sun_path``: the run's shared sun positions (:class:`~.visibility.SunPath`)."""
    notes = []
    explicit = room.spec.sun_points
    problems: list[str | None] = [None] * len(room.windows)
    if explicit is not None:
        check_sun_points(room)
        pts = scene.to_local(explicit)
        depths: list = [None] * len(pts)
        notes.append(f"room '{room.name}': point P given explicitly (rooms[].sun_points)")
    else:
        pts = np.full((len(room.windows), 3), np.nan)
        depths = [None] * len(room.windows)
        for i, w in enumerate(room.windows):  # one point P per window
            try:
                pts[i], depths[i], more = point_p(engine, scene, room, w, settings)
            except NotAssessable as exc:
                problems[i] = str(exc)
                continue
            notes.extend(more)
        if all(problems):
            raise NotAssessable("no window of the room has a point P: " + "; ".join(p for p in problems if p))
    ok = np.array([p is None for p in problems])
    normals = np.array([w.normal for w in room.windows])
    vis = SunVisibility(engine, pts[ok], normals[ok], room_window_group(room), location, settings, scene.true_north_deg, sun_path)
    dates, t0, t1 = day_bounds(settings.year, settings.period_start, settings.period_end, location.timezone)
    step = settings.timestep_min * 60.0
    window_hours = np.full((len(room.windows), len(dates)), np.nan)
    if settings.method == "exact":
        intervals, err_s, per_window = _exact(vis, scene, room, location, settings, t0, t1, sun_path)
        for i, iv in zip(np.flatnonzero(ok), per_window):
            window_hours[i] = [float(np.sum(x[:, 1] - x[:, 0])) / 3600.0 for x in iv]
        hours = np.array([float(np.sum(iv[:, 1] - iv[:, 0])) / 3600.0 for iv in intervals])
    else:
        intervals, err_s = visible_intervals(vis, t0, t1, step, settings.tolerance_s)
        hours = np.array([float(np.sum(iv[:, 1] - iv[:, 0])) / 3600.0 for iv in intervals])
        if ok.sum() == 1:
            window_hours[ok] = hours
        else:  # each window alone: its own intervals (for the report; the room's hours are their union)
            for i in np.flatnonzero(ok):  # one pass per window with a point P
                one = SunVisibility(engine, pts[i:i + 1], normals[i:i + 1], room_window_group(room), location, settings,
                                    scene.true_north_deg, sun_path)
                iv, _ = visible_intervals(one, t0, t1, step, settings.tolerance_s)
                window_hours[i] = [float(np.sum(x[:, 1] - x[:, 0])) / 3600.0 for x in iv]
    k = assessed_day(hours, dates, settings.date)
    err_h = err_s / 3600.0
    level = int(standard.level_from_value([hours[k]], thresholds.sunlight_hours)[0])
    near = bool(standard.near_threshold([hours[k]], [err_h[k]], thresholds.sunlight_hours)[0])
    return SunlightResult(points_local=pts, reveal_depths_m=depths, dates=dates, hours=hours, intervals=intervals,
                          error_h=err_h, assessed_index=k, level=level, near_threshold=near, timestep_s=step, notes=notes,
                          window_problems=problems, window_hours=window_hours)


def _exact(vis: SunVisibility, scene: Scene, room: Room, location: Location, settings: SunSettings, t0, t1,
           sun_path: SunPath | None):
    """``sunlight.method: exact`` (:mod:`.exact`): each point P's intervals by edge crossings, the
    room's as their union; the error bound of the room adds the points' bounds."""
    spline = SunSpline(vis.sun_path, float(t0[0]), float(t1[-1]), scene.true_north_deg)
    per_window, errors = [], []
    for i in range(len(vis.points)):  # one pass per window with a point P
        iv, e = exact_intervals(vis, spline, vis.sun_path, scene, room, i, t0, t1, settings, float(location.latitude))
        per_window.append(iv)
        errors.append(e)
    intervals, err = union_intervals(per_window, errors, len(t0))
    return intervals, err, per_window


def check_sun_points(room: Room) -> None:
    """Explicit points P must be one per window of the room, in the order ``validate`` lists them."""
    explicit = room.spec.sun_points
    if explicit is not None and len(explicit) != len(room.windows):
        names = ", ".join(f"'{w.name}'" for w in room.windows)
        raise InputError(f"room '{room.name}': sun_points has {len(explicit)} points for {len(room.windows)} windows ({names}); "
                         "give one per window, in that order")
