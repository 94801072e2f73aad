"""The sunlight of a room (EN 17037 clause 5.3): point P per window, sun hours of every day, the assessed day."""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.criteria.sunlight.exact import SunSpline, exact_intervals, union_intervals
from en17037cli.criteria.sunlight.intervals import day_bounds, visible_intervals
from en17037cli.criteria.sunlight.member_at_p import member_at_p
from en17037cli.criteria.sunlight.point_p import point_p
from en17037cli.criteria.sunlight.results import SunlightResult
from en17037cli.criteria.sunlight.visibility import SunPath, SunVisibility
from en17037cli.errors import InputError, NotAssessable
from en17037cli.project.settings import Location, SunSettings
from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import GLAZING_OFFSET_M, Room, Scene, room_window_group
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


def _hours(intervals: list) -> np.ndarray:
    """(d,) [h]: each day's total of (k, 2) intervals [s]."""
    return np.array([float(np.sum(iv[:, 1] - iv[:, 0])) / 3600.0 for iv in intervals])


def points_of_windows(engine: RayEngine, scene: Scene, room: Room, settings: SunSettings):
    """Point P of every window (Annex A.3), and the points whose sun is each window's.

    Returns
    -------
    pts : (k, 3) [m] P per window (NaN where it has none); depths : reveal depth per window [m] (None:
        explicit); problems : per window, why it has no P, or None; sets : per window, named point
        sets (k_j, 3) [m]: ``rule`` the points of ``sunlight.point_p_behind_member``, and where a
        member of the frame lies in front of P also ``as_drawn`` and ``nearest_glass``
        (:mod:`.member_at_p`); notes
    """
    notes = []
    explicit = room.spec.sun_points
    problems: list[str | None] = [None] * len(room.windows)
    if explicit is not None:
        check_sun_points(room)
        pts = scene.to_local(explicit)
        notes.append(f"room '{room.name}': point P given explicitly (rooms[].sun_points)")
        return pts, [None] * len(pts), problems, [{"rule": pts[i:i + 1]} for i in range(len(pts))], notes
    pts = np.full((len(room.windows), 3), np.nan)
    depths: list = [None] * len(room.windows)
    sets: list[dict] = [{} for _ in room.windows]
    rule = settings.point_p_behind_member
    for i, w in enumerate(room.windows):  # one point P per window
        try:
            pts[i], depths[i], more = point_p(engine, scene, room, w, settings)
        except NotAssessable as exc:
            problems[i] = str(exc)
            continue
        notes.extend(more)
        member = member_at_p(engine, w, pts[i], max(depths[i], GLAZING_OFFSET_M))
        sets[i]["rule"] = pts[i:i + 1] if member is None else member.points(rule, pts[i])
        if member is not None:
            sets[i] |= {"as_drawn": pts[i:i + 1], "nearest_glass": member.nearest_glass}
            where = "beside" if rule == "as_drawn" else "moved"
            notes.append(f"room '{room.name}', window '{w.name}': point P lies behind a member of the window's frame "
                         f"(a {'mullion' if abs(member.axis[2]) < 0.5 else 'transom'}); sunlight.point_p_behind_member: "
                         f"{rule} ({where}: {len(member.pane_centres)} point(s) of clear glass beside it)")
    if all(problems):
        raise NotAssessable("no window of the room has a point P: " + "; ".join(p for p in problems if p))
    return pts, depths, problems, sets, notes


def assess_room(engine: RayEngine, scene: Scene, room: Room, settings: SunSettings, location: Location,
                thresholds: Thresholds, sun_path: SunPath | None = None) -> SunlightResult:
    """Sunlight result of one room: P per window, every day's hours and intervals, assessed date and
    level. ``sun_path``: the run's shared sun positions (:class:`~.visibility.SunPath`). A window's
    sun is the sun seen from any point of its ``rule`` set (one point P, or the clear glass either
    side of a member in front of it); the room's is the union over its windows."""
    pts, depths, problems, sets, notes = points_of_windows(engine, scene, room, settings)
    ok = np.array([p is None for p in problems])
    # every distinct point of every set, once
    flat, normals_of, where = [], [], []
    for i, named in enumerate(sets):
        for name, ps in named.items():
            idx = []
            for q in ps:
                hit = next((k for k, f in enumerate(flat) if np.array_equal(f, q)), None)
                if hit is None:
                    flat.append(q)
                    normals_of.append(room.windows[i].normal)
                    hit = len(flat) - 1
                idx.append(hit)
            where.append((i, name, idx))
    flat_pts, flat_n = np.array(flat).reshape(-1, 3), np.array(normals_of).reshape(-1, 3)
    vis = SunVisibility(engine, flat_pts, flat_n, room_window_group(room), location, settings, scene.true_north_deg, sun_path)
    dates, t0, t1 = day_bounds(settings.year, settings.period_start, settings.period_end, location.timezone)
    nd = len(dates)
    step = settings.timestep_min * 60.0
    window_hours = np.full((len(room.windows), nd), np.nan)
    member_hours: list[dict | None] = [None] * len(room.windows)
    rule_points = sorted({k for i, name, idx in where if name == "rule" for k in idx})
    if settings.method == "exact":
        spline = SunSpline(vis.sun_path, float(t0[0]), float(t1[-1]), scene.true_north_deg)
        per_point, errors = [], []
        for k in range(len(flat_pts)):  # one pass per point
            iv, e = exact_intervals(vis, spline, vis.sun_path, scene, room, k, t0, t1, settings, float(location.latitude))
            per_point.append(iv)
            errors.append(e)
        intervals, err_s = union_intervals([per_point[k] for k in rule_points], [errors[k] for k in rule_points], nd)
        of_set = lambda idx: _hours(union_intervals([per_point[k] for k in idx], [], nd)[0])  # noqa: E731
    else:
        sub = lambda idx: SunVisibility(engine, flat_pts[idx], flat_n[idx], room_window_group(room), location,  # noqa: E731
                                        settings, scene.true_north_deg, sun_path)
        intervals, err_s = visible_intervals(sub(rule_points), t0, t1, step, settings.tolerance_s)
        of_set = lambda idx: _hours(visible_intervals(sub(idx), t0, t1, step, settings.tolerance_s)[0])  # noqa: E731
    hours = _hours(intervals)
    for i, name, idx in where:
        if name == "rule":
            window_hours[i] = hours if len(rule_points) == len(idx) and ok.sum() == 1 else of_set(idx)
        else:
            member_hours[i] = (member_hours[i] or {}) | {name: of_set(idx)}
    k = assessed_day(hours, dates, settings.date)
    err_h = err_s / 3600.0
    level = int(standard.level_from_value([hours[k]], thresholds.sunlight_hours)[0])
    near = bool(standard.near_threshold([hours[k]], [err_h[k]], thresholds.sunlight_hours)[0])
    return SunlightResult(points_local=pts, reveal_depths_m=depths, dates=dates, hours=hours, intervals=intervals,
                          error_h=err_h, assessed_index=k, level=level, near_threshold=near, timestep_s=step, notes=notes,
                          window_problems=problems, window_hours=window_hours,
                          window_points=[named.get("rule") for named in sets], member_hours=member_hours)


def check_sun_points(room: Room) -> None:
    """Explicit points P must be one per window of the room, in the order ``validate`` lists them."""
    explicit = room.spec.sun_points
    if explicit is not None and len(explicit) != len(room.windows):
        names = ", ".join(f"'{w.name}'" for w in room.windows)
        raise InputError(f"room '{room.name}': sun_points has {len(explicit)} points for {len(room.windows)} windows ({names}); "
                         "give one per window, in that order")
