"""The report's pictures, drawn from a run's results: which picture each room gets, its file name and
caption. Traces nothing: the values come from the criteria's results and illustrations
(:meth:`~en17037cli.criteria.base.Criterion.illustrate`), the drawing from :mod:`.pictures`.

Per room: for each eye height, plan maps of the horizontal sight angle, the outside distance, the
layers seen and the view level (points near a threshold ringed); the hours of sunlight per day of
the period; per window with a point P, the fisheye with the sun's paths. File names are stable
(``figures/<room>-...png``), so two runs of the same inputs give the same names and bytes.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from en17037cli.pipeline import RunResult

#: Sub-folder of the report folder holding the PNG files.
FIGURES_DIR = "figures"

#: Plan-map kinds in the order they are shown, with their captions.
MAP_KINDS = {"sight_angle": "horizontal sight angle", "distance": "outside distance", "layers": "layers seen",
             "level": "view level"}


@dataclass(frozen=True)
class Figure:
    """One picture: its file name in the report folder, the room and section it belongs to, a
    caption, and the PNG bytes."""

    name: str
    room: str
    section: str  # "view" or "sunlight"
    caption: str
    png: bytes


def room_slug(index: int, name: str) -> str:
    """A file-name stem for a room: its position and a lower-case ASCII form of its name."""
    s = re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")[:40]
    return f"{index + 1:02d}-{s or 'room'}"


def _layer_mask(visible: dict) -> np.ndarray:
    from en17037cli.report.pictures import GROUND, LANDSCAPE, SKY

    return (visible["sky"] * SKY + visible["landscape"] * LANDSCAPE + visible["ground"] * GROUND).astype(float)


def view_figures(result: RunResult, i: int, slug: str) -> list[Figure]:
    """The plan maps of room ``i``: four per eye height."""
    from en17037cli.report.pictures import plan_map

    r = result.rooms[i]
    res, plan = r.assessed("view"), r.illustrations.get("view")
    if res is None or plan is None:
        return []
    th = result.project.thresholds
    out = []
    for e in res.eye_heights:
        v = e.values
        if v is None or not len(v):
            continue
        xy = result.scene.to_world(e.points_local)[:, :2]
        values = {"sight_angle": (v.sight.angle_deg, th.horizontal_sight_angle_deg.as_dict()),
                  "distance": (v.distance_m, th.outside_distance_m.as_dict()),
                  "layers": (_layer_mask(v.visible), None), "level": (v.level.astype(float), None)}
        for kind, words in MAP_KINDS.items():
            vals, thresholds = values[kind]
            title = f"{r.room.name}: {words}, eye height {e.eye_height_m:g} m"
            png = plan_map(xy, vals, kind=kind, thresholds=thresholds, floor=plan.floor, utilised=plan.utilised,
                           windows=plan.windows, true_north_deg=plan.true_north_deg, near=v.near, spacing_m=plan.spacing_m,
                           title=title)
            out.append(Figure(f"{FIGURES_DIR}/{slug}-view-{e.eye_height_m:g}m-{kind.replace('_', '-')}.png", r.room.name,
                              "view", title, png))
    return out


def sunlight_figures(result: RunResult, i: int, slug: str) -> list[Figure]:
    """The hours chart of room ``i`` and the fisheye of each of its windows with a point P."""
    from en17037cli.report.pictures import fisheye, hours_chart

    r = result.rooms[i]
    res = r.assessed("sunlight")
    if res is None:
        return []
    th = result.project.thresholds.sunlight_hours.as_dict()
    settings = result.project.sunlight
    per_window = None
    if res.window_hours is not None and len(r.room.windows) > 1:
        per_window = {w.name: res.window_hours[k] for k, w in enumerate(r.room.windows) if np.isfinite(res.window_hours[k]).any()}
    title = f"{r.room.name}: hours of sunlight per day"
    out = [Figure(f"{FIGURES_DIR}/{slug}-sunlight-hours.png", r.room.name, "sunlight", title,
                  hours_chart(res.dates, res.hours, thresholds=th, assessed_index=res.assessed_index, per_window=per_window,
                              title=title))]
    for k, f in enumerate(r.illustrations.get("sunlight") or ()):
        paths = [{"label": p.label, "azimuth_deg": p.azimuth_deg, "altitude_deg": p.altitude_deg, "visible": p.visible,
                  "hour_marks": p.hour_marks} for p in f.paths]
        title = f"{r.room.name}: from point P of window '{f.window}'"
        png = fisheye(f.image, sun_paths=paths, min_altitude_deg=settings.min_altitude_deg if settings else 0.0,
                      view_azimuth_deg=f.view_azimuth_deg, title=title)
        out.append(Figure(f"{FIGURES_DIR}/{slug}-sunlight-fisheye-{k + 1}.png", r.room.name, "sunlight", title, png))
    return out


def render_figures(result: RunResult) -> list[Figure]:
    """Every picture of a run (a run made with ``pictures=True``), room by room; the time goes to
    the run's ``figures`` stage."""
    out = []
    for i, r in enumerate(result.rooms):
        slug = room_slug(i, r.room.name)
        out += view_figures(result, i, slug) + sunlight_figures(result, i, slug)
    result.timer.stage("figures")
    return out
