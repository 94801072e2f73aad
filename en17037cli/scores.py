"""Continuous scores of a run, per room, for design loops (beyond the standard; see
:func:`en17037cli.standard.score_from_value`): what :func:`en17037cli.Session.scores` returns."""
from __future__ import annotations

from en17037cli import standard
from en17037cli.criteria.view.scores import room_view_score, view_scores
from en17037cli.pipeline import RunResult


def room_scores(result: RunResult) -> dict[str, dict[str, float]]:
    """room name -> {"view": score, "sunlight": score} in [0, 3], for the checks that assessed it."""
    project = result.project
    out: dict[str, dict[str, float]] = {}
    for r in result.rooms:
        s = out.setdefault(r.room.name, {})
        view = r.assessed("view")
        if view is not None and project.view is not None:
            s["view"] = room_view_score(view_scores(view, project.thresholds, project.view.area_fraction))
        sun = r.assessed("sunlight")
        if sun is not None:
            s["sunlight"] = float(standard.score_from_value([sun.hours[sun.assessed_index]], project.thresholds.sunlight_hours)[0])
    return out
