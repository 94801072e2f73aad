"""The sunlight criterion's part of report.json: per room, per window and per day."""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.criteria.sunlight.results import SunlightResult
from en17037cli.project.settings import SunSettings
from en17037cli.report.numbers import iso_time, json_limit, json_number, json_scores, json_xyz
from en17037cli.scene.model import Room, Scene
from en17037cli.standard import LEVELS

#: How the sun hours are computed and what their error estimate means (repeated in the report), per
#: ``sunlight.method``.
SUN_METHODS = {
    "exact": ("sun position by NREL SPA (Reda and Andreas 2004); exact: edge-crossing times, polished to "
              "sunlight.tolerance_s (every time the sun's path crosses the image of an edge of a face that can occlude, "
              "the window's plane or the minimum altitude, bracketed to the tolerance; one ray between consecutive "
              "times); error = bound: sum of the brackets' half-widths at the ends of the day's intervals; no interval "
              "longer than the tolerance is missed"),
    "sampled": ("sun position by NREL SPA (Reda and Andreas 2004); visibility sampled every sunlight.timestep_min, each "
                "change located by bisection to sunlight.tolerance_s; error = sum of remaining half-brackets; intervals "
                "shorter than the timestep may be missed"),
}
SUN_METHOD = SUN_METHODS["sampled"]

def sunlight_score(hours: float, level: int, thresholds: standard.LevelThresholds) -> dict:
    """The sunlight score in report.json: hours on the assessed day [h], the score in [0, 3]
    (:func:`en17037cli.standard.score_from_value`) and the margins to the neighbouring levels [h]."""
    up, down = standard.margins(float(hours), level, thresholds)
    return json_scores(float(standard.score_from_value([hours], thresholds)[0])) | {
        "quantity": json_number(hours, 4), "unit": "h", "margin_up": json_number(up, 4), "margin_down": json_number(down, 4)}


def sunlight_section(scene: Scene, room: Room, res: SunlightResult, required: str, settings: SunSettings, tz,
                     thresholds: standard.LevelThresholds) -> dict:
    """The ``sunlight`` section of a room in report.json (see ``schemas/report.schema.json``)."""
    k = res.assessed_index
    level = LEVELS[res.level]
    windows = []
    pw = scene.to_world(res.points_local)
    for i, (w, p, depth, problem) in enumerate(zip(room.windows, pw, res.reveal_depths_m, res.window_problems)):
        entry = {"name": w.name, "point_p_m": None if problem else json_xyz(p),
                 "reveal_depth_m": None if depth is None else json_number(depth, 4),
                 "point_p_source": "explicit" if depth is None and not problem else "EN 17037 A.3 rule",
                 "hours_h": None if problem or res.window_hours is None else json_number(res.window_hours[i, k], 4)}
        if w.key:
            entry["element_id"] = w.key
        pts = res.window_points[i] if i < len(res.window_points) else None
        member = res.member_hours[i] if i < len(res.member_hours) else None
        if member is not None and pts is not None:  # P behind a member of the frame: the rule, and what it rests on
            entry["behind_member"] = {
                "rule": settings.point_p_behind_member, "points_m": [json_xyz(q) for q in scene.to_world(pts)],
                "hours_as_drawn_h": json_number(member["as_drawn"][k], 4),
                "hours_nearest_glass_h": json_number(member["nearest_glass"][k], 4)}
        if problem:
            entry |= {"status": "not_assessable", "reason": problem}
        windows.append(entry)
    days = []
    for d, h, iv, e in zip(res.dates, res.hours, res.intervals, res.error_h):
        days.append({"date": d.isoformat(), "hours_h": json_number(h, 4), "error_h": json_number(e, 5),
                     "intervals": [[iso_time(a, tz), iso_time(b, tz)] for a, b in iv]})
    limit = standard.sunlight_limit(res.hours[k], res.level, required, thresholds)
    return {
        "level": level,
        "required": required,
        "status": standard.status(level, required),
        "limiting": json_limit(limit),
        "score": sunlight_score(res.hours[k], res.level, thresholds),
        "assessed_date": res.dates[k].isoformat(),
        "hours_h": json_number(res.hours[k], 4),
        "near_threshold": res.near_threshold,
        "error_estimates": {
            "hours_error_h": json_number(res.error_h[k], 5),
            "max_hours_error_h": json_number(float(np.max(res.error_h)), 5),
            "shortest_interval_always_resolved_min": json_number(
                settings.tolerance_s / 60.0 if settings.method == "exact" else settings.timestep_min, 6),
            "method": SUN_METHODS[settings.method],
        },
        "windows": windows,
        "days": days,
    }
