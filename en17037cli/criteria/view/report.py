"""The view criterion's part of report.json: per room, per eye height, per point."""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.criteria.view.results import LAYER_NAMES, ViewResult
from en17037cli.criteria.view.scores import room_view_score, view_scores
from en17037cli.project.settings import ViewSettings
from en17037cli.report.numbers import json_limit, json_number, json_scores, json_xyz
from en17037cli.scene.model import Scene
from en17037cli.standard import LEVELS, VIEW_CRITERIA

#: How each view figure is computed and what its error estimate means (repeated in the report).
VIEW_METHOD = {
    "solid_angle_sr": "each window sampled per viewpoint on a grid uniform in the gnomonic angles of its plane, cells at "
                      "most view.angular_resolution_deg each way plus a grid line through the image of every frame vertex "
                      "(opaque faces within view.frame_depth_m of the glazing: mullions, transoms, reveals); each cell "
                      "weighted by its exact solid angle and classified by the rays through its corners, shared with its "
                      "neighbours, and by two rays just beside the image of any frame edge crossing it; cells whose samples "
                      "disagree, and cells crossed by the image of a frame edge that is not on a grid line (round, arched "
                      "or diagonal members), count as mixed and split in four (at most view.refine_levels times); view.refine: "
                      "decided splits a point's mixed cells only while its layers level or its room's could still change or an "
                      "interval is wider than 2 x view.tolerance x the windows' solid angle at the point, exact until each "
                      "layer's error estimate is within max(view.solid_angle_rel_tolerance x value, "
                      "view.solid_angle_abs_tolerance_sr); error = half the solid angle of the cells still mixed; interval = "
                      "[cells wholly of the layer, plus every mixed cell that can hold it], which holds the estimate of any "
                      "finer refinement (the exact mode's among them); features narrower than a cell and not part of a "
                      "frame can be missed",
    "horizontal_sight_angle_deg": "in plan (view.sight_angle_method: plan): the eye-height plane cuts the windows and the "
                                  "opaque faces within view.frame_depth_m of them and of the viewpoints into segments; the "
                                  "windows' azimuth intervals minus the segments' shadows, exact by construction (members "
                                  "inside an opening left out when view.mullions_block is false); rays every "
                                  "view.horizontal_resolution_deg confirm what lies further beyond the glazing, a far interior "
                                  "face bisected to view.angle_tolerance_deg; error = round-off bound plus those brackets",
    "horizontal_sight_angle_deg_fan": "with view.sight_angle_method: fan: horizontal fan over the azimuths of the windows every "
                                      "view.horizontal_resolution_deg, each change between leaving through a window and "
                                      "blocked located by bisection to view.angle_tolerance_deg; error = sum of remaining "
                                      "bracket widths and end insets (a gap narrower than the fan can be missed)",
    "outside_distance_m": "weighted statistic (view.distance_statistic) of the distance from the glazing plane to the "
                          "first landscape face, perpendicular to the window; error = gap to the neighbouring sampled distance",
}


#: The method entry of the solid angles where they were not traced.
NOT_TRACED = ("not traced: the model has no landscape (in front of the room's windows), so the layers cannot be judged "
              "and the room's view is not assessable; sight angle and outside distance are measured as usual")


def view_method(settings: ViewSettings) -> dict:
    """:data:`VIEW_METHOD` with the sight-angle entry of the project's ``view.sight_angle_method``."""
    out = {k: v for k, v in VIEW_METHOD.items() if not k.endswith("_fan")}
    if settings.sight_angle_method == "fan":
        out["horizontal_sight_angle_deg"] = VIEW_METHOD["horizontal_sight_angle_deg_fan"]
    return out


def _intervals(solid, i: int) -> dict | None:
    """The interval [lo, hi] [sr] of each layer's solid angle at point ``i`` (None: not traced)."""
    if solid.lo_sr is None or not np.isfinite(solid.glazing_sr[i]):
        return None
    return {k: [json_number(solid.lo_sr[k][i]), json_number(solid.hi_sr[k][i])] for k in LAYER_NAMES}


def _distance_interval(dist: float, gap: float) -> list | None:
    """[d - gap, d + gap] [m] of a finite outside distance (None: unobstructed, or none leaves)."""
    if not np.isfinite(dist):
        return None
    return [json_number(max(dist - gap, 0.0), 4), json_number(dist + gap, 4)]


def _widest(res: ViewResult) -> float:
    """The widest interval of a layer's solid angle over the room's points [sr] (0 without any)."""
    out = 0.0
    for e in res.eye_heights:
        s = e.values.solid if e.values is not None else None
        if s is not None and s.lo_sr is not None:
            for k in LAYER_NAMES:
                d = s.hi_sr[k] - s.lo_sr[k]
                if np.isfinite(d).any():
                    out = max(out, float(np.nanmax(d)))
    return out


def view_section(scene: Scene, res: ViewResult, required: str, settings: ViewSettings,
                 thresholds: standard.Thresholds) -> dict:
    """The ``view`` section of a room in report.json (see ``schemas/report.schema.json``)."""
    eye_out = []
    err = {"solid_angle_sr": 0.0, "horizontal_sight_angle_deg": 0.0, "outside_distance_m": 0.0}
    for e in res.eye_heights:
        v = e.values
        pts_world = scene.to_world(e.points_local)
        points = []
        for i in range(len(pts_world)):  # formatting each point's record
            dist = v.distance_m[i]
            unob = bool(np.isinf(dist) and dist > 0)
            sa_err = {k: json_number(v.solid.err_sr[k][i]) for k in LAYER_NAMES}
            err["solid_angle_sr"] = max([err["solid_angle_sr"], *[x for x in sa_err.values() if x is not None]])
            err["horizontal_sight_angle_deg"] = max(err["horizontal_sight_angle_deg"], float(v.sight.angle_err_deg[i]))
            if np.isfinite(v.distance_gap_m[i]):
                err["outside_distance_m"] = max(err["outside_distance_m"], float(v.distance_gap_m[i]))
            points.append({
                "point": json_xyz(pts_world[i]),
                "horizontal_sight_angle_deg": json_number(v.sight.angle_deg[i], 4),
                "horizontal_sight_angle_error_deg": json_number(v.sight.angle_err_deg[i], 6),
                "outside_distance_m": None if unob else json_number(dist, 4),
                "outside_distance_unobstructed": unob,
                "outside_distance_error_m": json_number(v.distance_gap_m[i], 4),
                "window_solid_angle_sr": json_number(v.solid.sr["sky"][i] + v.solid.sr["landscape"][i] + v.solid.sr["ground"][i]),
                "glazing_solid_angle_sr": json_number(v.solid.glazing_sr[i]),
                "solid_angle_sr": {k: json_number(v.solid.sr[k][i]) for k in LAYER_NAMES},
                "solid_angle_error_sr": sa_err,
                "solid_angle_interval_sr": _intervals(v.solid, i),
                "horizontal_sight_angle_interval_deg": [json_number(max(v.sight.angle_deg[i] - v.sight.angle_err_deg[i], 0.0), 4),
                                                        json_number(v.sight.angle_deg[i] + v.sight.angle_err_deg[i], 4)],
                "outside_distance_interval_m": _distance_interval(dist, v.distance_gap_m[i]),
                "layers_decided": None if v.solid.decided is None else bool(v.solid.decided[i]),
                "layers": [k for k in LAYER_NAMES if v.visible[k][i]],
                "level_by_criterion": {c: LEVELS[v.level_by_criterion[c][i]] for c in VIEW_CRITERIA},
                "level": LEVELS[v.level[i]],
                "near_threshold": bool(v.near[i]),
            })
        eye_out.append({
            "eye_height_m": json_number(e.eye_height_m, 3),
            "level": LEVELS[e.level],
            "level_by_criterion": {k: LEVELS[x] for k, x in e.level_by_criterion.items()},
            "share_by_level": {c: {k: json_number(x, 4) for k, x in sh.items()} for c, sh in e.share_by_level.items()},
            "points_near_threshold": int(np.count_nonzero(v.near)) if len(points) else 0,
            "points_layers_undecided": int(np.count_nonzero(~v.solid.decided)) if len(points) and v.solid.decided is not None else 0,
            "points": points,
        })
    traced = any(e.values is not None and np.isfinite(e.values.solid.glazing_sr).any() for e in res.eye_heights)
    level = LEVELS[res.level]
    limit = standard.view_limit([(e.eye_height_m, e.share_by_level) for e in res.eye_heights], res.level, required,
                                settings.area_fraction)
    scores = view_scores(res, thresholds, settings.area_fraction)
    verdict = {"level": level, "required": required, "status": standard.status(level, required)}
    if res.layers_unassessable is not None:  # sight angle and distance measured; the layers cannot be judged
        verdict = {"level": None, "required": required, "status": "not_assessable", "reason": res.layers_unassessable}
    return {
        **verdict,
        "limiting": json_limit(limit),
        "score": json_scores(room_view_score(scores), scores),
        "error_estimates": {
            "refine": settings.refine,
            "tolerance": settings.tolerance if settings.refine == "decided" else None,
            "max_solid_angle_error_sr": json_number(err["solid_angle_sr"] if traced else None),
            "max_solid_angle_interval_sr": json_number(_widest(res) if traced else None),
            "max_horizontal_sight_angle_error_deg": json_number(err["horizontal_sight_angle_deg"], 6),
            "max_outside_distance_error_m": json_number(err["outside_distance_m"], 4),
            "smallest_feature_resolved_deg": {"solid_angle": settings.angular_resolution_deg,  # frames: exactly
                                              "horizontal_sight_angle": settings.horizontal_resolution_deg},
            "method": view_method(settings) | ({} if traced else {"solid_angle_sr": NOT_TRACED}),
        },
        "eye_heights": eye_out,
    }
