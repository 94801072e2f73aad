"""``report.md``: the report as Markdown, for people (GitHub, pull-request comments)."""
from __future__ import annotations

import numpy as np

from en17037cli.report.labels import STATUS_LABEL, assessed, unassessed
from en17037cli.standard import LEVELS

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


def dwellings_markdown(report: dict) -> list[str]:
    """The dwellings section: each dwelling's sunlight rule, the room that meets it or the best
    one and its shortfall, and the counts."""
    s, practice = report["summary"], report["practice"]
    out = []
    if practice["set"]:
        out += [f"Practice: {practice['name']} ({practice['source']}); it set " +
                ", ".join(f"`{k}: {v}`" for k, v in practice["set"].items()) + ".", ""]
    if s["dwellings_sunlight_required"]:
        out += [f"Sunlight: {s['dwellings_sunlight_pass']} of {s['dwellings_sunlight_required']} dwellings pass "
                f"(rule: {report['dwellings'][0]['sunlight']['rule']} room of a dwelling). "
                f"View: {s['rooms_view_pass']} of {s['rooms_view_required']} rooms pass.", ""]
    if len(report["dwellings"]) > 1 or report["dwellings"][0]["grouped_by"] != "the whole project (no dwellings: key)":
        out += ["| dwelling | rooms | sunlight met by | hours | required | result |", "|---|---|---|---|---|---|"]
        for d in report["dwellings"]:
            sun = d["sunlight"]
            if sun["status"] is None:
                continue
            who = sun["room"] if sun["status"] == "pass" else f"best: {sun['room']}, {sun['shortfall_h']} h short"
            out.append(f"| {d['name']} | {', '.join(d['rooms'])} | {who} | {sun['hours']} | {sun['required']} | "
                       f"{STATUS_LABEL[sun['status']]} |")
        out.append("")
    return out


def report_markdown(report: dict) -> str:
    cfg = report["inputs"]["config"]
    L = [f"# EN 17037 check: {report['project']['name']}", "",
         f"Overall status: **{report['status'].upper()}** (en17037cli {report['tool']['version']}, project file `{report['project']['file']}`).", ""]
    L += dwellings_markdown(report)
    L += ["| room | criterion | level reached | level required | result |", "|---|---|---|---|---|"]
    for room in report["rooms"]:
        for key, title in (("view", "view out (5.2)"), ("sunlight", "exposure to sunlight (5.3)")):
            u = unassessed(room[key])
            if u:
                L.append(f"| {room['name']} | **{title}** | | {u['required']} | {STATUS_LABEL[u['status']]}: {u['reason']} |")
        if assessed(room["view"]):
            v = room["view"]
            for e in v["eye_heights"]:
                for crit, lv in e["level_by_criterion"].items():
                    L.append(f"| {room['name']} | view, eye {e['eye_height_m']} m: {crit.replace('_', ' ')} | {lv} | | |")
            L.append(f"| {room['name']} | **view out (5.2)** | **{v['level']}** | {v['required']} | {STATUS_LABEL[v['status']]} |")
        if assessed(room["sunlight"]):
            s = room["sunlight"]
            flag = " (near a threshold)" if s["near_threshold"] else ""
            L.append(f"| {room['name']} | **exposure to sunlight (5.3)**: {s['hours']} h on {s['assessed_date']}{flag} | **{s['level']}** | {s['required']} | {STATUS_LABEL[s['status']]} |")
    L += ["", "## Parameters the standard leaves open", ""]
    if "view" in cfg:
        v = cfg["view"]
        L += [f"- View: eye heights {v['eye_heights_m']} m; grid {v['grid_spacing_m']} m over the floor inset by {v['wall_margin_m']} m "
              f"(explicit view points where given); a layer counts when its solid angle exceeds {v['layer_threshold_sr']} sr; "
              f"a room reaches a level when {v['area_fraction']:.0%} of its points do; outside distance: {v['distance_method']} method, "
              f"{v['distance_statistic']} over the directions; angular resolution {v['angular_resolution_deg']} deg "
              f"(refined {v['refine_levels']} times), horizontal fan {v['horizontal_resolution_deg']} deg."]
    site = report["inputs"]["site"]
    if "sunlight" in cfg:
        s = cfg["sunlight"]
        L += [f"- Sunlight: year {s['year']}, period {s['period']['start']} to {s['period']['end']}, assessed date {s['date']}; "
              f"sun counted above {s['min_altitude_deg']} deg apparent altitude (refraction {'on' if s['refraction'] else 'off'}); "
              f"timestep {s['timestep_min']} min with changes located to {s['tolerance_s']} s; point P per EN 17037 A.3 on the "
              f"room-side plane of the opening unless given.",
              f"- Location: {site['latitude']} N, {site['longitude']} E, {site['timezone']}; "
              f"true north {site['true_north_deg']} deg clockwise from model +Y."]
        L += [f"- {key} {v['value']} from {v['source']}." for key, v in report["inputs"].get("resolved", {}).items()]
    t = cfg["thresholds"]
    def fmt(d):
        return " / ".join(f"{d[k]:g}" for k in LEVELS[1:])

    L += [f"- Thresholds (minimum / medium / high): sight angle {fmt(t['horizontal_sight_angle_deg'])} deg, outside distance "
          f"{fmt(t['outside_distance_m'])} m, sunlight {fmt(t['sunlight_hours'])} h."]
    for room in report["rooms"]:
        L += ["", f"## Room {room['name']}", ""]
        for w in room["windows"]:
            L.append(f"- Window '{w['name']}': {w['area_m2']} m², outward normal {w['outward_normal']}, sill {w['sill_z_m']} m, head {w['head_z_m']} m.")
        if assessed(room["sunlight"]):
            s = room["sunlight"]
            for w in s["windows"]:
                L.append(f"- Point P of '{w['name']}': {w['point_p_m']} ({w['point_p_source']}, reveal depth {w['reveal_depth_m']} m).")
            hrs = [d["hours"] for d in s["days"]]
            L += [f"- Sunlight over the period: {min(hrs)} h to {max(hrs)} h a day; assessed {s['assessed_date']}: {s['hours']} h "
                  f"± {s['error_estimates']['hours_error_h']} h."]
        if assessed(room["view"]):
            v = room["view"]
            ee = v["error_estimates"]
            L += [f"- View error estimates: solid angles ≤ {ee['max_solid_angle_error_sr']} sr, sight angle ≤ "
                  f"{ee['max_horizontal_sight_angle_error_deg']} deg, outside distance ≤ {ee['max_outside_distance_error_m']} m."]
            for e in v["eye_heights"]:
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
