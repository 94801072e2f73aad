"""Reports: ``report.json``, ``view_points.csv``, ``sunlight_days.csv`` and ``report.md``.

Formats the data of :func:`en17037cli.check.run_check`; traces no ray. Numbers are rounded to
fixed decimals so that the same inputs give byte-identical files apart from ``timings_s``.
Files are written to a temporary folder and moved into place; a failed run leaves none.
"""
from __future__ import annotations

import csv
import datetime as dt
import io
import json
import math
import os
import shutil
import tempfile
import zoneinfo
from pathlib import Path

import numpy as np

from en17037cli import __version__, standard
from en17037cli.standard import LEVELS

SCHEMA_VERSION = "1.0"
REPORT_FILES = ("report.json", "view_points.csv", "sunlight_days.csv", "report.md")

VIEW_METHOD = {
    "solid_angle_sr": "each window sampled per viewpoint on a grid uniform in the gnomonic angles of its plane, cells at "
                      "most view.angular_resolution_deg each way plus a grid line through the image of every frame vertex "
                      "(opaque faces within view.frame_depth_m of the glazing: mullions, transoms, reveals); each cell "
                      "weighted by its exact solid angle and classified by the rays through its corners, shared with its "
                      "neighbours; cells whose samples disagree split in four (at most view.refine_levels times) until each "
                      "layer's error estimate is within max(view.solid_angle_rel_tolerance x value, "
                      "view.solid_angle_abs_tolerance_sr); error = half the solid angle of the cells still mixed; features "
                      "narrower than a cell and not part of a frame can be missed",
    "horizontal_sight_angle_deg": "horizontal fan over the azimuths of the windows every view.horizontal_resolution_deg, "
                                  "each change between leaving through a window and blocked located by bisection to "
                                  "view.angle_tolerance_deg; error = sum of remaining bracket widths and end insets",
    "outside_distance_m": "weighted statistic (view.distance_statistic) of the distance from the glazing plane to the "
                          "first landscape face, perpendicular to the window; error = gap to the neighbouring sampled distance",
}
SUN_METHOD = ("sun position by NREL SPA (Reda and Andreas 2004); visibility sampled every sunlight.timestep_min, each "
              "change located by bisection to sunlight.tolerance_s; error = sum of remaining half-brackets; intervals "
              "shorter than the timestep may be missed")


def _r(x, nd=6):
    """Round for JSON: None for NaN, floats to ``nd`` decimals (``-0.0`` folded to ``0.0``)."""
    if x is None:
        return None
    x = float(x)
    if math.isnan(x) or math.isinf(x):
        return None
    v = round(x, nd)
    return 0.0 if v == 0 else v


def _xyz(p, nd=4):
    return [_r(c, nd) for c in p]


def _iso(t: float, tz) -> str:
    return dt.datetime.fromtimestamp(round(float(t)), tz).isoformat(timespec="seconds")


def _view_json(scene, res: dict, required: str, cfg: dict) -> dict:
    eye_out = []
    err = {"solid_angle_sr": 0.0, "horizontal_sight_angle_deg": 0.0, "outside_distance_m": 0.0}
    for e in res["eye_heights"]:
        v = e["values"]
        pts_world = scene.to_world(e["points_local"])
        points = []
        for i in range(len(pts_world)):  # formatting each point's record
            dist = v["distance"][i]
            unob = bool(np.isinf(dist) and dist > 0)
            sa_err = {k: _r(v["err_" + k][i]) for k in ("sky", "landscape", "ground")}
            err["solid_angle_sr"] = max(err["solid_angle_sr"], *[x for x in sa_err.values()])
            err["horizontal_sight_angle_deg"] = max(err["horizontal_sight_angle_deg"], float(v["h_angle_err_deg"][i]))
            if np.isfinite(v["distance_gap"][i]):
                err["outside_distance_m"] = max(err["outside_distance_m"], float(v["distance_gap"][i]))
            points.append({
                "point": _xyz(pts_world[i]),
                "horizontal_sight_angle_deg": _r(v["h_angle_deg"][i], 4),
                "horizontal_sight_angle_error_deg": _r(v["h_angle_err_deg"][i], 6),
                "outside_distance_m": None if unob else _r(dist, 4),
                "outside_distance_unobstructed": unob,
                "outside_distance_error_m": _r(v["distance_gap"][i], 4),
                "window_solid_angle_sr": _r(v["sky"][i] + v["landscape"][i] + v["ground"][i]),
                "glazing_solid_angle_sr": _r(v["glazing"][i]),
                "solid_angle_sr": {k: _r(v[k][i]) for k in ("sky", "landscape", "ground")},
                "solid_angle_error_sr": sa_err,
                "layers": [k for k in ("sky", "landscape", "ground") if v["visible"][k][i]],
                "level_by_criterion": {"horizontal_sight_angle": LEVELS[v["level_angle"][i]],
                                       "outside_distance": LEVELS[v["level_distance"][i]],
                                       "layers": LEVELS[v["level_layers"][i]]},
                "level": LEVELS[v["level"][i]],
                "near_threshold": bool(v["near"][i]),
            })
        eye_out.append({
            "eye_height_m": _r(e["eye_height_m"], 3),
            "level": LEVELS[e["level"]],
            "level_by_criterion": {k: LEVELS[x] for k, x in e["level_by_criterion"].items()},
            "share_by_level": {c: {k: _r(x, 4) for k, x in sh.items()} for c, sh in e["share_by_level"].items()},
            "points_near_threshold": int(np.count_nonzero(v["near"])) if len(points) else 0,
            "points": points,
        })
    level = LEVELS[res["level"]]
    return {
        "level": level,
        "required": required,
        "status": "pass" if standard.passes(level, required) else "fail",
        "error_estimates": {
            "max_solid_angle_error_sr": _r(err["solid_angle_sr"]),
            "max_horizontal_sight_angle_error_deg": _r(err["horizontal_sight_angle_deg"], 6),
            "max_outside_distance_error_m": _r(err["outside_distance_m"], 4),
            "smallest_feature_resolved_deg": {"solid_angle": cfg["angular_resolution_deg"],  # frames: exactly
                                              "horizontal_sight_angle": cfg["horizontal_resolution_deg"]},
            "method": VIEW_METHOD,
        },
        "eye_heights": eye_out,
    }


def _sun_json(scene, room, res: dict, required: str, cfg: dict, tz) -> dict:
    k = res["assessed_index"]
    level = LEVELS[res["level"]]
    windows = []
    pw = scene.to_world(res["points_local"])
    for w, p, depth in zip(room.windows, pw, res["reveal_depths_m"]):
        windows.append({"name": w.name, "point_p_m": _xyz(p), "reveal_depth_m": None if depth is None else _r(depth, 4),
                        "point_p_source": "explicit" if depth is None else "EN 17037 A.3 rule"})
    days = []
    for d, h, iv, e in zip(res["dates"], res["hours"], res["intervals"], res["error_h"]):
        days.append({"date": d.isoformat(), "hours": _r(h, 4), "error_h": _r(e, 5),
                     "intervals": [[_iso(a, tz), _iso(b, tz)] for a, b in iv]})
    return {
        "level": level,
        "required": required,
        "status": "pass" if standard.passes(level, required) else "fail",
        "assessed_date": res["dates"][k].isoformat(),
        "hours": _r(res["hours"][k], 4),
        "near_threshold": res["near_threshold"],
        "error_estimates": {
            "hours_error_h": _r(res["error_h"][k], 5),
            "max_hours_error_h": _r(float(np.max(res["error_h"])), 5),
            "shortest_interval_always_resolved_min": _r(cfg["timestep_min"], 4),
            "method": SUN_METHOD,
        },
        "windows": windows,
        "days": days,
    }


def build_report(project, result: dict, timings: dict) -> dict:
    """The ``report.json`` document (validates against ``schemas/report.schema.json``)."""
    cfg = project.config
    scene = result["scene"]
    tz = zoneinfo.ZoneInfo(cfg["location"]["timezone"]) if "location" in cfg else None
    rooms = []
    for r in result["rooms"]:
        room = r["room"]
        entry = {
            "name": room.name,
            "status": "pass",
            "floor_area_m2": _r(room.floor.area, 4),
            "floor_source": room.floor_source,
            "windows": [{"name": w.name, "area_m2": _r(w.area_m2, 4), "outward_normal": _xyz(w.normal, 6),
                         "sill_z_m": _r(w.sill_z + scene.origin[2], 4), "head_z_m": _r(w.head_z + scene.origin[2], 4)}
                        for w in room.windows],
            "view": None,
            "sunlight": None,
        }
        if r["view"] is not None:
            entry["view"] = _view_json(scene, r["view"], r["required"]["view"], cfg["view"])
        if r["sunlight"] is not None:
            entry["sunlight"] = _sun_json(scene, room, r["sunlight"], r["required"]["sunlight"], cfg["sunlight"], tz)
        if any(entry[c] is not None and entry[c]["status"] == "fail" for c in ("view", "sunlight")):
            entry["status"] = "fail"
        rooms.append(entry)
    notes = list(scene.notes)
    for r in result["rooms"]:
        for c in ("view", "sunlight"):
            if r[c] is not None:
                notes.extend(r[c]["notes"])
    return {
        "schema_version": SCHEMA_VERSION,
        "tool": {"name": "en17037cli", "version": __version__},
        "project": {"name": cfg.get("name"), "file": project.path.name},
        "inputs": {"config": cfg, "model_files": scene.file_hashes, "local_origin_m": _xyz(scene.origin, 6),
                   "checks_run": [c for c, ran in result["ran"].items() if ran]},
        "status": result["status"],
        "rooms": rooms,
        "warnings": list(scene.warnings),
        "notes": notes,
        "rays_traced": int(result["rays_traced"]),
        "timings_s": {k: round(v, 3) for k, v in timings.items()},
    }


def view_points_csv(report: dict) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["room", "eye_height_m", "x_m", "y_m", "z_m", "horizontal_sight_angle_deg", "horizontal_sight_angle_error_deg",
                "outside_distance_m", "outside_distance_unobstructed", "window_solid_angle_sr", "sky_sr", "landscape_sr",
                "ground_sr", "layers", "level_sight_angle", "level_distance", "level_layers", "level", "near_threshold"])
    for room in report["rooms"]:
        if not room["view"]:
            continue
        for e in room["view"]["eye_heights"]:
            for p in e["points"]:
                lc = p["level_by_criterion"]
                w.writerow([room["name"], e["eye_height_m"], *p["point"], p["horizontal_sight_angle_deg"],
                            p["horizontal_sight_angle_error_deg"], "" if p["outside_distance_m"] is None else p["outside_distance_m"],
                            p["outside_distance_unobstructed"], p["window_solid_angle_sr"], p["solid_angle_sr"]["sky"],
                            p["solid_angle_sr"]["landscape"], p["solid_angle_sr"]["ground"], "+".join(p["layers"]),
                            lc["horizontal_sight_angle"], lc["outside_distance"], lc["layers"], p["level"], p["near_threshold"]])
    return buf.getvalue()


def sunlight_days_csv(report: dict) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["room", "date", "hours", "error_h", "assessed", "intervals"])
    for room in report["rooms"]:
        s = room["sunlight"]
        if not s:
            continue
        for d in s["days"]:
            w.writerow([room["name"], d["date"], d["hours"], d["error_h"], d["date"] == s["assessed_date"],
                        ";".join(f"{a[11:19]}-{b[11:19]}" for a, b in d["intervals"])])
    return buf.getvalue()


_LEVEL_MARK = {"none": ".", "minimum": "1", "medium": "2", "high": "3"}


def _plan_map(points: list) -> list:
    """A plan-view character map of the points' levels (rows north to south)."""
    if not points:
        return []
    xy = np.array([p["point"][:2] for p in points], dtype=float)
    xs, ys = np.unique(np.round(xy[:, 0], 2)), np.unique(np.round(xy[:, 1], 2))
    if len(xs) * len(ys) > 4000 or len(xs) > 120:
        return []
    grid = [[" "] * len(xs) for _ in ys]
    for p, (x, y) in zip(points, xy):
        i = int(np.searchsorted(ys, round(y, 2)))
        j = int(np.searchsorted(xs, round(x, 2)))
        if i < len(ys) and j < len(xs):
            grid[len(ys) - 1 - i][j] = _LEVEL_MARK[p["level"]]
    return ["```", *("".join(row).rstrip() for row in grid), "```",
            "Plan view, model +Y up; `.` none, `1` minimum, `2` medium, `3` high (only when the points form an axis-aligned grid)."]


def report_markdown(report: dict) -> str:
    cfg = report["inputs"]["config"]
    L = [f"# EN 17037 check: {report['project']['name']}", "",
         f"Overall status: **{report['status'].upper()}** (en17037cli {report['tool']['version']}, project file `{report['project']['file']}`).", "",
         "| room | criterion | level reached | level required | result |", "|---|---|---|---|---|"]
    for room in report["rooms"]:
        if room["view"]:
            v = room["view"]
            for e in v["eye_heights"]:
                for crit, lv in e["level_by_criterion"].items():
                    L.append(f"| {room['name']} | view, eye {e['eye_height_m']} m: {crit.replace('_', ' ')} | {lv} | | |")
            L.append(f"| {room['name']} | **view out (5.2)** | **{v['level']}** | {v['required']} | {'PASS' if v['status'] == 'pass' else 'FAIL'} |")
        if room["sunlight"]:
            s = room["sunlight"]
            flag = " (near a threshold)" if s["near_threshold"] else ""
            L.append(f"| {room['name']} | **exposure to sunlight (5.3)**: {s['hours']} h on {s['assessed_date']}{flag} | **{s['level']}** | {s['required']} | {'PASS' if s['status'] == 'pass' else 'FAIL'} |")
    L += ["", "## Parameters the standard leaves open", ""]
    if "view" in cfg:
        v = cfg["view"]
        L += [f"- View: eye heights {v['eye_heights_m']} m; grid {v['grid_spacing_m']} m over the floor inset by {v['wall_margin_m']} m "
              f"(explicit view points where given); a layer counts when its solid angle exceeds {v['layer_threshold_sr']} sr; "
              f"a room reaches a level when {v['area_fraction']:.0%} of its points do; outside distance: {v['distance_method']} method, "
              f"{v['distance_statistic']} over the directions; angular resolution {v['angular_resolution_deg']} deg "
              f"(refined {v['refine_levels']} times), horizontal fan {v['horizontal_resolution_deg']} deg."]
    if "sunlight" in cfg:
        s = cfg["sunlight"]
        L += [f"- Sunlight: year {s['year']}, period {s['period']['start']} to {s['period']['end']}, assessed date {s['date']}; "
              f"sun counted above {s['min_altitude_deg']} deg apparent altitude (refraction {'on' if s['refraction'] else 'off'}); "
              f"timestep {s['timestep_min']} min with changes located to {s['tolerance_s']} s; point P per EN 17037 A.3 on the "
              f"room-side plane of the opening unless given.",
              f"- Location: {cfg['location']['latitude']} N, {cfg['location']['longitude']} E, {cfg['location']['timezone']}; "
              f"true north {cfg['model']['true_north_deg']} deg clockwise from model +Y."]
    t = cfg["thresholds"]
    def fmt(d):
        return " / ".join(f"{d[k]:g}" for k in LEVELS[1:])

    L += [f"- Thresholds (minimum / medium / high): sight angle {fmt(t['horizontal_sight_angle_deg'])} deg, outside distance "
          f"{fmt(t['outside_distance_m'])} m, sunlight {fmt(t['sunlight_hours'])} h."]
    for room in report["rooms"]:
        L += ["", f"## Room {room['name']}", ""]
        for w in room["windows"]:
            L.append(f"- Window '{w['name']}': {w['area_m2']} m², outward normal {w['outward_normal']}, sill {w['sill_z_m']} m, head {w['head_z_m']} m.")
        if room["sunlight"]:
            s = room["sunlight"]
            for w in s["windows"]:
                L.append(f"- Point P of '{w['name']}': {w['point_p_m']} ({w['point_p_source']}, reveal depth {w['reveal_depth_m']} m).")
            hrs = [d["hours"] for d in s["days"]]
            L += [f"- Sunlight over the period: {min(hrs)} h to {max(hrs)} h a day; assessed {s['assessed_date']}: {s['hours']} h "
                  f"± {s['error_estimates']['hours_error_h']} h."]
        if room["view"]:
            v = room["view"]
            ee = v["error_estimates"]
            L += [f"- View error estimates: solid angles ≤ {ee['max_solid_angle_error_sr']} sr, sight angle ≤ "
                  f"{ee['max_horizontal_sight_angle_error_deg']} deg, outside distance ≤ {ee['max_outside_distance_error_m']} m."]
            for e in v["eye_heights"]:
                share = e["share_by_level"]["view"]
                L += ["", f"### Eye height {e['eye_height_m']} m: {len(e['points'])} points, level {e['level']}", "",
                      "Share of points reaching each level: " + ", ".join(
                          f"{c.replace('_', ' ')}: " + " / ".join(f"{k} {share_c[k]:.0%}" for k in LEVELS[1:])
                          for c, share_c in e["share_by_level"].items()) + ".",
                      f"Points within their error of a threshold: {e['points_near_threshold']}.", ""]
                L += _plan_map(e["points"])
                L += ["", "| x | y | z | sight angle (deg) | distance (m) | sky / landscape / ground (sr) | level |", "|---|---|---|---|---|---|---|"]
                for p in e["points"]:
                    d = "unobstructed" if p["outside_distance_unobstructed"] else p["outside_distance_m"]
                    sa = p["solid_angle_sr"]
                    L.append(f"| {p['point'][0]} | {p['point'][1]} | {p['point'][2]} | {p['horizontal_sight_angle_deg']} | {d} | "
                             f"{sa['sky']} / {sa['landscape']} / {sa['ground']} | {p['level']}{' *' if p['near_threshold'] else ''} |")
                L.append("")
                L.append("`*` within the error estimate of a threshold: the level could flip.")
    if report["notes"] or report["warnings"]:
        L += ["", "## Notes", ""] + [f"- {n}" for n in report["warnings"] + report["notes"]]
    return "\n".join(L) + "\n"


def remove_reports(out_dir: Path) -> None:
    """Delete the report files of an earlier run in ``out_dir`` (only ours)."""
    for name in REPORT_FILES:
        try:
            (out_dir / name).unlink()
        except FileNotFoundError:
            pass


def write_reports(report: dict, out_dir: Path) -> list[Path]:
    """Write all report files atomically: into a temporary folder beside ``out_dir``, then moved."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    contents = {
        "report.json": json.dumps(report, indent=2, ensure_ascii=False, allow_nan=False) + "\n",
        "view_points.csv": view_points_csv(report),
        "sunlight_days.csv": sunlight_days_csv(report),
        "report.md": report_markdown(report),
    }
    tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", dir=out_dir.parent))
    try:
        for name, text in contents.items():
            with open(tmp / name, "w", encoding="utf-8", newline="") as fh:
                fh.write(text)
                fh.flush()
                os.fsync(fh.fileno())
        for name in contents:
            os.replace(tmp / name, out_dir / name)
    except BaseException:
        remove_reports(out_dir)
        raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return [out_dir / n for n in contents]
