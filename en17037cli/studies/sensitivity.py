"""Sensitivity study: how robust is each room's verdict to the choices EN 17037 leaves open.

``en17037 study sensitivity project.yaml --out DIR`` assesses the project once with its own
settings and again with each open choice set, one at a time, to each value of a documented range
of defensible values (:data:`RANGES`; a project overrides them under ``sensitivity.ranges``):

========================  ===============================================================  ============
choice                    values tried                                                      new rays
========================  ===============================================================  ============
``sunlight.date``         every day of the period                                           none
``sunlight.point_p``      P moved 0.1 m left, right and up within the opening               sunlight
``sunlight.point_p_       pane_centres, nearest_glass, as_drawn (rooms where a member of a   sunlight
behind_member``           window's frame lies in front of P)
``view.layer_threshold``  0, 3.05e-4 (a 1 x 1 deg patch), 1e-3, 1e-2 sr                     none
``view.eye_heights_m``    seated 1.2 m only, standing 1.7 m only                            none
``view.distance_method``  horizontal, solid_angle                                           view
``view.distance_stat``    median, min, p25                                                  view
``view.grid_offset``      half a cell                                                       view
``view.grid_spacing_m``   twice the project's                                               view
``view.wall_margin_m``    0.5, 1.0 m                                                        view
``view.mullions_block``   true (mullions and transoms cut the sight angle), false (the     sight angle
                          opening measured between its reveals)
``daylight.aggregation``  hours_first, points_first (method 2 only)                          daylight
``daylight.radiance.ab``  3, 7 bounces outside (Radiance, for what is seen through glass)    daylight
``daylight.radiance.ad``  4, 16 hemisphere samples at each of those bounces                  daylight
``daylight.sky_subdiv``   Reinhart MF 2 (577 patches; method 2 only)                         daylight
``glare.facade_distance`` auto positions 0.5 and 2.0 m from the glazing                     glare
``glare.eye_height_m``    standing, 1.7 m                                                   glare
``glare.directions``      towards the facade only, parallel to it only                      glare
``glare.usage``           07:00-17:00, 09:00-19:00, every day                               glare
``glare.low_light``       the DGP's low-light correction on                                 glare
``glare.source_thresh``   1000 and 4000 cd/m² (evalglare's 2000 by default)                 glare
``glare.sky_subdivision`` Reinhart MF 2                                                     glare
========================  ===============================================================  ============

Choices that do not change what is traced (the date, the layer threshold, the eye heights) are
judged again from the stored values (the view's solid angles of ``view.refine: exact``, whatever the
project's mode: a threshold that ``decided`` did not refine for is judged on the same figures); the others run the criterion again on the same scene and
ray engine (acceleration structures built once); the mullion reading changes only the
horizontal sight angle, so the solid angles are reused. With ``view.sight_angle_method: fan`` the
mullion reading is not tried (the fan's rays stop at a mullion). For each room and check it reports the level
under the project's settings, the lowest and highest over the ranges, which choices move it, and
a verdict: ``robust pass`` (every value passes), ``robust fail`` (none does) or ``depends on
<choices>``; and the continuous scores (:mod:`en17037cli.criteria.view.scores`) for a tornado chart.
"""
from __future__ import annotations

import csv
import dataclasses
import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from en17037cli import standard
from en17037cli.criteria.glare.sensitivity import GLARE_LABELS, GLARE_RANGES
from en17037cli.criteria.view.scores import room_view_score, view_scores
from en17037cli.standard import LEVELS

#: A layer threshold a person would notice: a patch of 1 x 1 deg [sr] (the "miniscule visible
#: patches" of Brembilla, Azadi and Nourian 2021, Discussion).
PATCH_SR = float(np.radians(1.0) ** 2)

#: The default range of each choice (values beside the project's own).
RANGES: dict[str, tuple] = {
    "sunlight.date": ("every day",),
    "sunlight.point_p": ("left 0.1 m", "right 0.1 m", "up 0.1 m"),
    "sunlight.point_p_behind_member": ("pane_centres", "nearest_glass", "as_drawn"),
    "view.layer_threshold_sr": (0.0, PATCH_SR, 1e-3, 1e-2),
    "view.eye_heights_m": ((1.2,), (1.7,)),
    "view.distance_method": ("horizontal", "solid_angle"),
    "view.distance_statistic": ("median", "min", "p25"),
    "view.grid_offset": (0.5,),
    "view.grid_spacing_m": ("x2",),
    "view.wall_margin_m": (0.5, 1.0),
    "view.mullions_block": (True, False),
    "daylight.aggregation": ("hours_first", "points_first"),
    "daylight.radiance.ab": (3, 7),
    "daylight.radiance.ad": (4, 16),
    "daylight.sky_subdivision": (2,),
    **GLARE_RANGES,
}
#: How the tables and charts name each choice.
LABELS = {"sunlight.date": "assessed date", "sunlight.point_p": "point P", "sunlight.point_p_behind_member": "P behind a member",
          "view.layer_threshold_sr": "layer threshold",
          "view.eye_heights_m": "eye heights", "view.distance_method": "distance method",
          "view.distance_statistic": "distance statistic", "view.grid_offset": "grid offset",
          "view.grid_spacing_m": "grid spacing", "view.wall_margin_m": "wall margin",
          "view.mullions_block": "mullion reading", "daylight.aggregation": "aggregation order",
          "daylight.radiance.ab": "bounces outside", "daylight.radiance.ad": "samples per bounce outside",
          "daylight.sky_subdivision": "sky subdivision", **GLARE_LABELS}
#: P moves this far [m].
P_SHIFT_M = 0.1


@dataclass(frozen=True)
class Outcome:
    """One room and check under one choice value."""

    room: str
    check: str  # "view" | "sunlight" | "daylight" | "glare"
    choice: str  # a key of RANGES, or "default"
    value: str
    level: int
    score: float


def _fmt(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, tuple):
        return " + ".join(f"{x:g} m" if isinstance(x, (int, float)) else str(x) for x in v)
    if isinstance(v, float):
        return f"{v:g}"
    return str(v)


def view_outcome(res, settings, thresholds, layer_threshold_sr=None, eye_heights=None) -> tuple[int, float]:
    """Level and score of a view result judged again: another layer threshold [sr] (from the stored
    solid angles) and / or a subset of the eye heights [m]; no ray is traced."""
    eyes = []
    for e in res.eye_heights:
        if eye_heights is not None and not any(abs(e.eye_height_m - h) < 1e-9 for h in eye_heights):
            continue
        v = e.values
        if v is None:
            continue
        lv = dict(v.level_by_criterion)
        if layer_threshold_sr is not None:
            vis = {k: standard.layer_visible(v.solid.sr[k], layer_threshold_sr) for k in ("sky", "landscape", "ground")}
            lv["layers"] = standard.level_from_layers(vis["sky"], vis["landscape"], vis["ground"])
            v = dataclasses.replace(v, visible=vis, level_by_criterion=lv, level=standard.point_view_level(*lv.values()))
        share = {c: standard.room_level(lv[c], settings.area_fraction)[1] for c in standard.VIEW_CRITERIA}
        _, share["view"] = standard.room_level(v.level, settings.area_fraction)
        levels = {c: standard.room_level(lv[c], settings.area_fraction)[0] for c in standard.VIEW_CRITERIA}
        eyes.append(dataclasses.replace(e, values=v, share_by_level=share, level_by_criterion=levels,
                                        level=standard.view_level(levels.values())))
    if not eyes:
        return 0, float("nan")
    r = dataclasses.replace(res, eye_heights=eyes, level=standard.view_level(e.level for e in eyes))
    return r.level, room_view_score(view_scores(r, thresholds, settings.area_fraction))


def daylight_outcome(res) -> tuple[int, float]:
    """Level and score of a daylight result (clause 5.1, :func:`~en17037cli.criteria.daylight.report.daylight_score`)."""
    from en17037cli.criteria.daylight.report import daylight_score

    return res.level, float(daylight_score(res, res.level)["value"])


def daylight_variants(ds, ranges) -> list[tuple[str, object, object]]:
    """(choice, value, settings) of each daylight choice to try: the aggregation order and the sky
    subdivision for method 2 only; -ab and -ad for both."""
    out = []
    for key in ("daylight.aggregation", "daylight.radiance.ab", "daylight.radiance.ad", "daylight.sky_subdivision"):
        if key in ("daylight.aggregation", "daylight.sky_subdivision") and ds.method != "climate_based":
            continue
        for value in ranges.get(key, ()):
            if key.startswith("daylight.radiance."):
                field = {"ab": "ab", "ad": "ad"}[key.rsplit(".", 1)[1]]
                if getattr(ds.radiance, field) == value:
                    continue
                new = dataclasses.replace(ds, radiance=dataclasses.replace(ds.radiance, **{field: int(value)}))
            else:
                field = key.split(".", 1)[1]
                if getattr(ds, field) == value:
                    continue
                new = dataclasses.replace(ds, **{field: value})
            out.append((key, value, new))
    return out


def sun_outcome(hours: float, thresholds) -> tuple[int, float]:
    """Level and score of a number of hours [h] (clause 5.3, Table A.6)."""
    return int(standard.level_from_value([hours], thresholds)[0]), float(standard.score_from_value([hours], thresholds)[0])


def moved_points(scene, room, res, how: str) -> np.ndarray | None:
    """The room's points P (world [m]) moved ``P_SHIFT_M`` left, right or up in each window's plane,
    or None when a window has no point P."""
    from en17037cli.geometry.triangles import window_axes

    if any(res.window_problems):
        return None
    out = []
    for w, p in zip(room.windows, res.points_local):
        a, _ = window_axes(np.asarray(w.normal, float))
        d = {"left 0.1 m": -a, "right 0.1 m": a, "up 0.1 m": np.array([0.0, 0.0, 1.0])}[how]
        out.append(p + P_SHIFT_M * d)
    return scene.to_world(np.array(out))


def sensitivity(project_path: Path, out_dir: Path, overrides=(), log=print) -> dict:
    """Run the study; write ``sensitivity.csv``, ``sensitivity.json`` and a tornado chart per room
    (``sensitivity-<room>.png``, when matplotlib is present). Returns the JSON document."""
    from en17037cli.criteria import CRITERIA, Context, Unassessed
    from en17037cli.errors import NotAssessable
    from en17037cli.project import load_project
    from en17037cli.raytrace import RayEngine
    from en17037cli.scene import build_scene

    t0 = time.perf_counter()
    # the layer threshold is judged again on the stored solid angles: they are the exact mode's, so
    # that every threshold of the range is judged on the same figures (the project's own levels are
    # the same in either mode: docs/method.md, "Bounded figures, exact verdicts")
    project = load_project(Path(project_path), list(overrides))
    if project.view is not None and project.view.refine != "exact":
        project = load_project(Path(project_path), [*overrides, "view.refine=exact"])
    ranges = {**RANGES, **{k: tuple(tuple(v) if isinstance(v, list) else v for v in vals)
                           for k, vals in (project.config.get("sensitivity", {}).get("ranges", {}) or {}).items()}}
    scene = build_scene(project)
    outcomes: list[Outcome] = []
    th = project.thresholds
    with RayEngine(scene.vertices, scene.triangles, scene.ray_groups()) as engine:

        def assess(name: str, proj, rooms=None, reuse=None) -> dict:
            c, ctx = CRITERIA[name], Context(proj, scene, engine)
            ctx.cache["view_all_layers"] = True  # the layers' verdicts are compared, landscape or not
            if reuse:
                ctx.cache["view_reuse"] = reuse
            out = {}
            for room in rooms or scene.rooms:
                if room.problem is not None:
                    continue
                try:
                    res = c.assess(ctx, room, c.plan(ctx, room))
                except NotAssessable:
                    continue
                if not isinstance(res, Unassessed):
                    out[room.name] = res
            return out

        base = {name: assess(name, project) for name in CRITERIA
                if CRITERIA[name].settings(project) is not None and name != "glare"}  # glare: its own loop below
        t_base = time.perf_counter() - t0
        log(f"  the project's own settings: {t_base:.2f} s")
        view, sun = base.get("view", {}), base.get("sunlight", {})
        vs = project.view
        for name, res in view.items():
            outcomes.append(Outcome(name, "view", "default", "project", *view_outcome(res, vs, th)))
        for name, res in sun.items():
            outcomes.append(Outcome(name, "sunlight", "default", "project", *sun_outcome(res.hours[res.assessed_index],
                                                                                        th.sunlight_hours)))
        # judged again from the stored values
        if sun:
            for name, res in sun.items():
                for d, h in zip(res.dates, res.hours):
                    outcomes.append(Outcome(name, "sunlight", "sunlight.date", d.isoformat(), *sun_outcome(h, th.sunlight_hours)))
        if view:
            for t in ranges["view.layer_threshold_sr"]:
                for name, res in view.items():
                    outcomes.append(Outcome(name, "view", "view.layer_threshold_sr", _fmt(float(t)),
                                            *view_outcome(res, vs, th, layer_threshold_sr=float(t))))
            for eyes in ranges["view.eye_heights_m"]:
                for name, res in view.items():
                    if any(abs(e.eye_height_m - h) < 1e-9 for e in res.eye_heights for h in eyes):
                        outcomes.append(Outcome(name, "view", "view.eye_heights_m", _fmt(tuple(eyes)),
                                                *view_outcome(res, vs, th, eye_heights=eyes)))
        # traced again
        if sun:
            for how in ranges["sunlight.point_p"]:
                t = time.perf_counter()
                rooms = []
                for room in scene.rooms:
                    if room.name in sun and (pts := moved_points(scene, room, sun[room.name], how)) is not None:
                        rooms.append(dataclasses.replace(room, spec=dataclasses.replace(room.spec, sun_points=pts)))
                for name, res in assess("sunlight", project, rooms).items() if rooms else ():
                    outcomes.append(Outcome(name, "sunlight", "sunlight.point_p", how,
                                            *sun_outcome(res.hours[res.assessed_index], th.sunlight_hours)))
                log(f"  point P {how}: {time.perf_counter() - t:.2f} s")
            ss = project.sunlight
            behind = [room for room in scene.rooms if room.name in sun and any(h is not None for h in sun[room.name].member_hours)]
            for rule in ranges["sunlight.point_p_behind_member"] if behind and ss is not None else ():
                if rule == ss.point_p_behind_member:
                    continue  # the project's own setting: the default outcome
                t = time.perf_counter()
                proj = dataclasses.replace(project, sunlight=dataclasses.replace(ss, point_p_behind_member=rule))
                for name, res in assess("sunlight", proj, behind).items():
                    outcomes.append(Outcome(name, "sunlight", "sunlight.point_p_behind_member", rule,
                                            *sun_outcome(res.hours[res.assessed_index], th.sunlight_hours)))
                log(f"  sunlight.point_p_behind_member = {rule}: {time.perf_counter() - t:.2f} s")
        if view:
            for key in ("view.distance_method", "view.distance_statistic", "view.grid_offset", "view.grid_spacing_m",
                        "view.wall_margin_m", "view.mullions_block"):
                field = key.split(".", 1)[1]
                for value in ranges[key]:
                    if value == "x2":
                        value = 2 * vs.grid_spacing_m
                    if value == getattr(vs, field):
                        continue  # the project's own setting: the default outcome
                    if key == "view.mullions_block" and vs.sight_angle_method == "fan":
                        log("  view.mullions_block: not tried with view.sight_angle_method: fan")
                        continue
                    t = time.perf_counter()
                    proj = dataclasses.replace(project, view=dataclasses.replace(vs, **{field: value}))
                    # a statistic of the horizontal fan's distances: the solid angles stay as they were
                    # and the mullion reading, which changes only the sight angle
                    same_solid = (key == "view.distance_statistic" and vs.distance_method == "horizontal"
                                  or key == "view.mullions_block")
                    for name, res in assess("view", proj, reuse=view if same_solid else None).items():
                        outcomes.append(Outcome(name, "view", key, _fmt(value), *view_outcome(res, proj.view, th)))
                    log(f"  {key} = {_fmt(value)}: {time.perf_counter() - t:.2f} s")
        daylight = base.get("daylight", {})
        for name, res in daylight.items():
            outcomes.append(Outcome(name, "daylight", "default", "project", *daylight_outcome(res)))
        if daylight:
            for key, value, ds in daylight_variants(project.daylight, ranges):
                t = time.perf_counter()
                for name, res in assess("daylight", dataclasses.replace(project, daylight=ds)).items():
                    outcomes.append(Outcome(name, "daylight", key, _fmt(value), *daylight_outcome(res)))
                log(f"  {key} = {_fmt(value)}: {time.perf_counter() - t:.2f} s")
        if project.glare is not None:
            from en17037cli.criteria.glare.sensitivity import glare_outcomes

            rows, glare_base_s = glare_outcomes(project, scene, engine, ranges, log)
            outcomes += [Outcome(room, "glare", choice, value, level, score) for room, choice, value, level, score in rows]
            t_base += glare_base_s  # the cost ratio measures against every check with the project's own settings
    total = time.perf_counter() - t0
    doc = summarise({room.name: room.spec.requirements for room in scene.rooms}, outcomes)
    doc["cost"] = {"base_s": round(t_base, 3), "total_s": round(total, 3), "ratio": round(total / max(t_base, 1e-9), 2)}
    write(Path(out_dir), doc, outcomes, project.config.get("name") or Path(project_path).stem)
    return doc


def summarise(required: dict, outcomes: list[Outcome]) -> dict:
    """Per room and check: the default level, the lowest and highest, what moves it, the verdict.
    ``required``: room name -> its :class:`~en17037cli.project.settings.Requirements`."""
    specs: dict[tuple[str, str], list[Outcome]] = {}
    rows = []
    for o in outcomes:
        specs.setdefault((o.room, o.check), []).append(o)
    for (room, check), os_ in specs.items():
        default = next(o for o in os_ if o.choice == "default")
        req = getattr(required[room], check) if room in required else "none"
        need = standard.level_index(req) if req != "none" else None
        levels = [o.level for o in os_]
        movers = sorted({o.choice for o in os_ if o.level != default.level and o.choice != "default"})
        flips = sorted({o.choice for o in os_ if need is not None and (o.level >= need) != (default.level >= need)})
        if need is None:
            verdict = "not required"
        elif all(lv >= need for lv in levels):
            verdict = "robust pass"
        elif all(lv < need for lv in levels):
            verdict = "robust fail"
        else:
            verdict = "depends on " + ", ".join(LABELS[c] for c in flips)
        spans = {}
        for o in os_:
            if o.choice != "default" and np.isfinite(o.score):
                lo, hi = spans.get(o.choice, (o.score, o.score))
                spans[o.choice] = (min(lo, o.score), max(hi, o.score))
        rows.append({"room": room, "check": check, "required": req, "level": LEVELS[default.level],
                     "score": round(default.score, 4), "lowest": LEVELS[min(levels)], "highest": LEVELS[max(levels)],
                     "moved_by": [LABELS[c] for c in movers], "verdict": verdict,
                     "score_span": {LABELS[c]: [round(lo, 4), round(hi, 4)] for c, (lo, hi) in sorted(spans.items())}})
    return {"rooms": rows, "ranges": {k: [_fmt(v) for v in vals] for k, vals in RANGES.items()}}


def write(out_dir: Path, doc: dict, outcomes: list[Outcome], project_name: str = "") -> None:
    """``sensitivity.csv`` (every outcome), ``sensitivity.json``, the tornado charts and ``sensitivity.html``."""
    from en17037cli.report.html import sensitivity_html

    out_dir.mkdir(parents=True, exist_ok=True)
    charts: list[tuple[str, bytes]] = []
    with open(out_dir / "sensitivity.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["room", "check", "choice", "value", "level", "score"])
        for o in outcomes:
            w.writerow([o.room, o.check, o.choice, o.value, LEVELS[o.level], f"{o.score:.4f}"])
    (out_dir / "sensitivity.json").write_text(json.dumps(doc, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    from en17037cli.report.figures import room_slug
    from en17037cli.report.pictures import tornado

    by_room: dict[str, list] = {}
    for r in doc["rooms"]:
        by_room.setdefault(r["room"], []).append(r)
    for i, (room, rows) in enumerate(by_room.items()):
        bars = [(f"{r['check']}: {label}", lo, hi, r["score"]) for r in rows for label, (lo, hi) in r["score_span"].items()]
        if bars:
            try:
                png = tornado(bars, title=f"{room}: scores by choice")
            except ImportError:  # matplotlib missing: the tables stay
                continue
            (out_dir / f"sensitivity-{room_slug(i, room)}.png").write_bytes(png)
            charts.append((f"{room}: the score under each choice; the line is the project's own settings", png))
    (out_dir / "sensitivity.html").write_text(sensitivity_html(doc, charts, project_name), encoding="utf-8")
