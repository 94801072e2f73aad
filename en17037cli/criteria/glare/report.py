"""The glare criterion's part of report.json and its two CSV tables (``glare_points.csv``, one row per
position and direction; ``glare_hours.csv``, every usage hour of each room's worst view)."""
from __future__ import annotations

import csv
import io

import numpy as np

from en17037cli import standard
from en17037cli.criteria.glare.results import GlareResult
from en17037cli.project.glare_settings import GlareSettings
from en17037cli.report.numbers import json_number, json_scores, json_xyz
from en17037cli.scene.model import Scene
from en17037cli.standard import LEVELS

#: How the annual figure is computed and what its error estimate means (repeated in the report).
ANNUAL_METHOD = (
    "DGP of every usage hour (clause 5.4) at each position and view direction: vertical illuminance at the eye from "
    "daylight coefficients (Radiance rcontrib -I against a Reinhart sky, glare.radiance -ab/-ad/-lw, replicates) times "
    "gendaymtx's sky of the weather file, the sun apart (its direct light seen from the eye by clause 5.3's visibility, "
    "NREL SPA, through the glass at its angle of incidence); glare sources: the sky seen through the glazing (rays from "
    "the eye, rcontrib -ab 0) and the sun's disc, brighter than glare.source_threshold_cd_m2, with Guth's position "
    "index (enhanced simplified DGP, imageless); DGP by evalglare's formula. Error of the DGP exceeded in 5 % of the "
    "hours = the 95 % interval of the replicates' values combined with the largest difference from evalglare on a "
    "fisheye at the reference check's hours")
#: The DGP at which the continuous score reaches 0 (the score is 1, 2, 3 at each level's limit).
SCORE_ZERO_DGP = 1.0


def glare_score(dgp_5pct: float, limits: dict[str, float]) -> dict:
    """Score in [0, 3] (beyond the standard): piecewise linear in the DGP exceeded in 5 % of the hours
    through (high's limit, 3), (medium's, 2), (minimum's, 1), (1.0, 0); floor(score) is the level."""
    x = [limits["high"], limits["medium"], limits["minimum"], SCORE_ZERO_DGP]
    score = float(np.interp(dgp_5pct, x, [3.0, 2.0, 1.0, 0.0])) if np.isfinite(dgp_5pct) else 0.0
    out = json_scores(score)
    level = int(standard.glare_level(dgp_5pct, limits))
    out.update({"quantity": json_number(dgp_5pct, 4), "unit": "DGP",
                "margin_up": None if level >= 3 else json_number(dgp_5pct - x[2 - level], 4),
                "margin_down": None if level <= 0 else json_number(x[3 - level] - dgp_5pct, 4)})
    return out


def glare_section(scene: Scene, res: GlareResult, required: str, settings: GlareSettings) -> dict:
    """The ``glare`` section of a room in report.json (see ``schemas/report.schema.json``)."""
    limits = settings.limits()
    level = None if res.level is None else LEVELS[res.level]
    out: dict = {"level": level, "required": required,
                 "status": "not_assessable" if res.level is None else standard.status(level, required),
                 "method": {**res.method, "usage": settings.usage_words, "year": settings.year,
                            "weather": settings.weather_display, "usage_hours": res.usage_hours,
                            "dgp_limits": limits, "exceedance": standard.GLARE_EXCEEDANCE},
                 "shading": None if settings.shading is None else {"transmittance": settings.shading.transmittance,
                                                                    "sun_transmittance": settings.shading.sun_transmittance,
                                                                    "control": settings.shading.control}}
    if res.unassessable:
        out["reason"] = res.unassessable
    positions = []
    for i, v in enumerate(res.views):  # formatting each view's record
        positions.append({"index": i, "label": v.view.label, "point": json_xyz(scene.to_world(v.view.eye)),
                          "direction_deg": json_number(v.view.bearing_deg, 2), "level": LEVELS[v.level],
                          "dgp_5pct": json_number(v.dgp_5pct, 4), "dgp_5pct_error": json_number(v.dgp_5pct_err, 4),
                          "hours_over": {f"{k:.2f}": n for k, n in v.hours_over.items()}, "usage_hours": len(v.dgp),
                          "sun_in_view_hours": int(v.sun_in_view.sum()), "shaded_hours": int(v.shaded.sum()),
                          "max_dgp": json_number(float(v.dgp.max()) if len(v.dgp) else None, 4)})
    out["positions"] = positions
    if res.level is not None and res.worst is not None:
        w = res.views[res.worst]
        t = standard.target_level(res.level, required)
        need = limits[LEVELS[t]] if t > 0 else limits["minimum"]
        out.update({
            "worst_position": res.worst, "dgp_5pct": json_number(w.dgp_5pct, 4),
            "limiting": {"level": LEVELS[t], "criterion": "dgp_exceeded_5pct", "value": json_number(w.dgp_5pct, 4),
                         "needed": json_number(need, 4), "margin": json_number(need - w.dgp_5pct, 4)},
            "score": glare_score(w.dgp_5pct, limits), "near_threshold": res.near_threshold,
            "usage_hours": res.usage_hours, "sun_in_view_hours": res.sun_in_view_hours,
            "transmittance_needed": json_number(res.transmittance_needed, 4),
            "transmittance_needed_sun_hidden": json_number(res.transmittance_needed_sun_hidden, 4),
            "transmittance_tried": list(res.transmittance_tried),
            "error_estimates": {"dgp_error": json_number(res.error_dgp, 4),
                                "monte_carlo_dgp_error": json_number(max(v.dgp_5pct_err for v in res.views), 4),
                                "method": ANNUAL_METHOD},
            "reference_check": reference_section(res, limits),
            "hourly": {"position": res.worst, "local_time": [str(t).replace("T", " ") for t in res.usage_local],
                      "dgp": [json_number(x, 4) for x in w.dgp], "dgp_unshaded": [json_number(x, 4) for x in w.dgp_unshaded],
                      "vertical_illuminance_lx": [json_number(x, 1) for x in w.ev_lx],
                      "sun_in_view": [bool(x) for x in w.sun_in_view], "shaded": [bool(x) for x in w.shaded]},
        })
    out["moments"] = [{"time": m.time, "position": m.view.label, "point": json_xyz(scene.to_world(m.view.eye)),
                       "direction_deg": json_number(m.view.bearing_deg, 2), "sky": m.sky, "dgp": json_number(m.dgp, 4),
                       "vertical_illuminance_lx": json_number(m.ev_lx, 1)} for m in res.moments]
    out["notes"] = list(res.notes)
    return out


def with_sunlight(glare: dict, sunlight: dict) -> dict:
    """The glare section with ``with_sunlight``: sunlight (5.3) and glare (5.4) read together, where a
    room has results of both (Brembilla et al. 2021: a room that reaches sunlight needs the shading
    5.4 asks for): the sunlight hours on 5.3's assessed day beside the usage hours with the sun in
    view at a critical position, and whether the room passes 5.3 and fails 5.4."""
    if glare.get("status") not in ("pass", "fail") or sunlight.get("status") not in ("pass", "fail") or "limiting" not in glare:
        return glare
    fails = sunlight["status"] == "pass" and glare["status"] == "fail"
    return glare | {"with_sunlight": {"sunlight_level": sunlight["level"], "sunlight_hours_h": sunlight["hours_h"],
                                      "sunlight_assessed_date": sunlight["assessed_date"],
                                      "sun_in_view_hours": glare["sun_in_view_hours"], "usage_hours": glare["usage_hours"],
                                      "passes_sunlight_fails_glare": fails,
                                      "transmittance_needed": glare["transmittance_needed"] if fails else None,
                                      "transmittance_needed_sun_hidden":
                                          glare["transmittance_needed_sun_hidden"] if fails else None}}


def reference_section(res: GlareResult, limits: dict[str, float]) -> dict:
    """The reference check in report.json: each hour's DGP and E_v both ways and the level each gives,
    the largest and mean difference (the time it took is in ``timings_s``, which alone may differ
    between runs)."""
    hours = [{"local_time": h.local_time, "dgp_fast": json_number(h.dgp_fast, 4), "dgp_evalglare": json_number(h.dgp_evalglare, 4),
              "ev_fast_lx": json_number(h.ev_fast_lx, 1), "ev_evalglare_lx": json_number(h.ev_evalglare_lx, 1),
              "class_fast": LEVELS[int(standard.glare_level(h.dgp_fast, limits))],
              "class_evalglare": LEVELS[int(standard.glare_level(h.dgp_evalglare, limits))]} for h in res.reference]
    d = np.array([h.dgp_fast - h.dgp_evalglare for h in res.reference])
    return {"hours": hours, "max_abs_dgp_difference": json_number(np.abs(d).max() if len(d) else None, 4),
            "mean_dgp_difference": json_number(d.mean() if len(d) else None, 4),
            "classes_agree": sum(h["class_fast"] == h["class_evalglare"] for h in hours),
            "level_with_mean_difference": None if res.level_reference is None else LEVELS[res.level_reference]}


def glare_points_csv(report: dict) -> str:
    """``glare_points.csv``: one row per room, position and view direction."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["room", "position", "x_m", "y_m", "z_m", "direction_deg", "dgp_5pct", "dgp_5pct_error", "hours_over_0.35",
                "hours_over_0.40", "hours_over_0.45", "usage_hours", "sun_in_view_hours", "level", "room_source_ids"])
    for room in report["rooms"]:
        sec = room.get("glare")
        if not sec or sec.get("status") not in ("pass", "fail"):
            continue
        for p in sec["positions"]:
            ho = p["hours_over"]
            w.writerow([room["name"], p["label"], *p["point"], p["direction_deg"], p["dgp_5pct"], p["dgp_5pct_error"],
                        ho.get("0.35", ""), ho.get("0.40", ""), ho.get("0.45", ""), p["usage_hours"], p["sun_in_view_hours"],
                        p["level"], " ".join(room.get("source", {}).get("ids", ()))])
    return buf.getvalue()


def glare_hours_csv(report: dict) -> str:
    """``glare_hours.csv``: the DGP of every usage hour at each room's worst position and direction."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["room", "position", "local_time", "dgp", "dgp_unshaded", "vertical_illuminance_lx", "sun_in_view", "shaded",
                "room_source_ids"])
    for room in report["rooms"]:
        sec = room.get("glare")
        if not sec or "hourly" not in sec:
            continue
        h = sec["hourly"]
        label = sec["positions"][h["position"]]["label"]
        rows = zip(h["local_time"], h["dgp"], h["dgp_unshaded"], h["vertical_illuminance_lx"], h["sun_in_view"], h["shaded"])
        ids = " ".join(room.get("source", {}).get("ids", ()))
        w.writerows([room["name"], label, t, d, u, e, int(s), int(sh), ids] for t, d, u, e, s, sh in rows)
    return buf.getvalue()
