"""``report.md``: the report as Markdown, for people (GitHub, pull-request comments)."""
from __future__ import annotations

from en17037cli.report.glare_text import glare_markdown, glare_parameters
from en17037cli.report.labels import STATUS_LABEL, assessed, is_repair, md, unassessed
from en17037cli.report.numbers import fmt_bound, fmt_duration
from en17037cli.report.validation import kind_text
from en17037cli.report.verdicts import limit_text
from en17037cli.standard import LEVELS


def dwellings_markdown(report: dict) -> list[str]:
    """The dwellings section: each dwelling's sunlight rule, the room that meets it or the best
    one and its shortfall, and the counts."""
    s, practice = report["summary"], report["practice"]
    out = []
    if practice["set"]:
        out += [f"Practice: {practice['name']} ({practice['source']}); it set " +
                ", ".join(f"`{k}: {v}`" for k, v in practice["set"].items()) + ".", ""]
    defined = not (len(report["dwellings"]) == 1 and report["dwellings"][0]["grouped_by"] == "the whole project (no dwellings: key)")
    if s["dwellings_sunlight_required"] and defined:  # no dwelling line for a project without dwellings
        out += [f"Sunlight: {s['dwellings_sunlight_pass']} of {s['dwellings_sunlight_required']} dwellings pass "
                f"(rule: {'one main room' if report['dwellings'][0]['sunlight']['rule'] == 'any' else 'every room'} of a dwelling). "
                f"View: {s['rooms_view_pass']} of {s['rooms_view_required']} rooms pass.", ""]
    if defined:
        out += ["| dwelling | rooms | sunlight met by | hours | required | result |", "|---|---|---|---|---|---|"]
        for d in report["dwellings"]:
            sun = d["sunlight"]
            if sun["status"] is None:
                continue
            who = md(sun["room"]) if sun["status"] == "pass" else f"best: {md(sun['room'])}, {fmt_duration(sun['shortfall_h'])} short"
            out.append(f"| {md(d['name'])} | {md(', '.join(d['rooms']))} | {who} | {fmt_duration(sun['hours_h'])} | {sun['required']} | "
                       f"{STATUS_LABEL[sun['status']]} |")
        out.append("")
    return out


#: (criterion key, how the reports title it)
CHECKS = (("daylight", "daylight provision (5.1)"), ("view", "view out (5.2)"), ("sunlight", "exposure to sunlight (5.3)"),
          ("glare", "protection from glare (5.4)"))


def verdict_rows(report: dict) -> list[dict]:
    """One row per room and check with a result or a requirement: room, check, reached, required,
    result and what limits it (the summary tables of report.md and report.html)."""
    rows = []
    for room in report["rooms"]:
        for key, title in CHECKS:
            sec = room.get(key)
            if sec is None:
                continue
            u = unassessed(sec)
            limit = limit_text(key, sec) if not u else f"{u['reason']}"
            if key in ("sunlight", "daylight", "glare") and assessed(sec) and sec.get("near_threshold"):
                limit += " (within its error estimate of a threshold)"
            score = (sec.get("score") or {}).get("value")
            rows.append({"room": room["name"], "check": title, "reached": sec["level"] or "-", "required": sec["required"],
                         "result": STATUS_LABEL[sec["status"]], "limits": limit, "score": "-" if score is None else f"{score:.2f}"})
    return rows


def parameter_lines(report: dict) -> list[str]:
    """The choices the standard leaves open, as this run made them (plain sentences)."""
    cfg = report["inputs"]["config"]
    L = []
    if "view" in cfg:
        v = cfg["view"]
        L += [f"View: eye heights {v['eye_heights_m']} m; grid {v['grid_spacing_m']} m over the floor inset by {v['wall_margin_m']} m "
              f"(explicit view points where given); a layer counts when its solid angle exceeds {v['layer_threshold_sr']} sr; "
              f"a room reaches a level when {v['area_fraction']:.0%} of its points do; outside distance: {v['distance_method']} method, "
              f"{v['distance_statistic']} over the directions; angular resolution {v['angular_resolution_deg']} deg "
              f"(refined {v['refine_levels']} times); horizontal sight angle "
              + (f"in plan, mullions and transoms {'blocking' if v.get('mullions_block', True) else 'left out (the opening between its reveals)'}, "
                 f"rays every {v['horizontal_resolution_deg']} deg beyond the glazing."
                 if v.get("sight_angle_method", "plan") == "plan" else f"by a horizontal fan of {v['horizontal_resolution_deg']} deg.")]
    site = report["inputs"]["site"]
    if "sunlight" in cfg:
        s = cfg["sunlight"]
        L += [f"Sunlight: year {s['year']}, period {s['period']['start']} to {s['period']['end']}, assessed date {s['date']}; "
              f"sun counted above {s['min_altitude_deg']} deg apparent altitude (refraction {'on' if s['refraction'] else 'off'}); "
              + (f"exact method: edge-crossing times located to {s['tolerance_s']} s; "
                 if s.get("method", "exact") == "exact" else
                 f"timestep {s['timestep_min']} min with changes located to {s['tolerance_s']} s; ")
              + "point P per EN 17037 A.3 on the "
              "room-side plane of the opening unless given.",
              f"Location: {site['latitude']} N, {site['longitude']} E, {site['timezone']}; "
              f"true north {site['true_north_deg']} deg clockwise from model +Y."]
        L += [f"{key} {v['value']} from {v['source']}." for key, v in report["inputs"].get("resolved", {}).items()]
    if "daylight" in cfg:
        d = cfg["daylight"]
        r = d["radiance"]
        L += [f"Daylight: {'method 1, daylight factor under the CIE overcast sky' if d['method'] == 'daylight_factor' else 'method 2, climate-based, ' + d['aggregation'].replace('_', ' ')}; "
              f"reference plane {d['reference_plane_m']} m above the floor, grid {d['grid_spacing_m']} m over the floor inset by "
              f"{d['wall_margin_m']} m; reflectance floor / walls / ceiling {d['reflectance']['floor']} / {d['reflectance']['walls']} / "
              f"{d['reflectance']['ceiling']}, landscape {d['reflectance']['landscape']}, ground {d['reflectance']['ground']}; glazing "
              f"tv {d['glazing_transmittance']} (layer rules' values win); Radiance -ab {r['ab']} -ad {r['ad']} -as {r['as']} -lw {r['lw']}, "
              f"{r['replicates']} replicates per point."]
    L += glare_parameters(cfg)
    t = cfg["thresholds"]

    def fmt(d):
        return " / ".join(f"{d[k]:g}" for k in LEVELS[1:])

    L += [f"Thresholds (minimum / medium / high): sight angle {fmt(t['horizontal_sight_angle_deg'])} deg, outside distance "
          f"{fmt(t['outside_distance_m'])} m, sunlight {fmt(t['sunlight_hours'])} h"
          + (f", daylight target {fmt(t['daylight_target_lx'])} lx on 50 % and minimum target {fmt(t['daylight_minimum_target_lx'])} "
             "lx on 95 % of the plane." if "daylight" in cfg else ".")]
    for kind, values in report["practice"].get("kinds", {}).items():  # a practice's values per room kind
        L += [f"Practice {report['practice']['name']} for a {kind.replace('_', ' ')}: "
              + ", ".join(f"{k.removeprefix('thresholds.')} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in values.items())
              + f" ({report['practice']['kinds_source']})."]
    return L


def share_table(e: dict) -> list[list[str]]:
    """Rows of an eye height's share of points reaching each level, per criterion (header first)."""
    rows = [["criterion", *LEVELS[1:], "level"]]
    for c, share in e["share_by_level"].items():
        lv = e["level"] if c == "view" else e["level_by_criterion"].get(c, "")
        rows.append([c.replace("_", " "), *(f"{share[k]:.0%}" for k in LEVELS[1:]), lv])
    return rows


def daylight_paragraph(d: dict) -> str:
    """The daylight verdict of a room in words: level, method, E_v,d,med and its source, the errors."""
    ee = d["error_estimates"]
    how = ("daylight factor (method 1)" if d["method"] == "daylight_factor"
           else f"climate-based (method 2, {d['aggregation'].replace('_', ' ')}, {d['daylight_hours']} daylight hours)")
    err = (f"D ± {ee['max_daylight_factor_error_pct']} % at most" if "max_daylight_factor_error_pct" in ee
           else f"share of hours ± {ee.get('max_share_of_hours_error')} at most")
    med = f"median D {d['median_daylight_factor_pct']} %; " if "median_daylight_factor_pct" in d else ""
    return (f"**Daylight provision: {d['level']}** (required {d['required']}, {STATUS_LABEL[d['status']]}); "
            f"{limit_text('daylight', d)}. {how}; E_v,d,med {d['median_diffuse_lx']:g} lx ({d['median_diffuse_source']}); "
            f"{med}{len(d['points'])} points ({err}; shares ± {d['error_estimates']['max_share_error']}). Every point: "
            "`daylight_points.csv`.")


def daylight_table(d: dict) -> list[list[str]]:
    """Rows of the shares of the plane reaching each level's target and minimum target (Table A.1)."""
    rows = [["level", "target", "share (50 % needed)", "minimum target", "share (95 % needed)"]]
    for name, lv in d["levels"].items():
        dt = f" (D {lv['target_daylight_factor_pct']:g} %)" if "target_daylight_factor_pct" in lv else ""
        dtm = f" (D {lv['minimum_target_daylight_factor_pct']:g} %)" if "minimum_target_daylight_factor_pct" in lv else ""
        none = lv["minimum_target_lx"] == 0  # a practice that asks no minimum target (gb-br209-2022 per room kind)
        rows.append([name, f"{lv['target_lx']:g} lx{dt}", f"{lv['target_share']:.0%} ± {lv['target_share_error']:.0%}",
                     "none asked" if none else f"{lv['minimum_target_lx']:g} lx{dtm}",
                     "-" if none else f"{lv['minimum_target_share']:.0%} ± {lv['minimum_target_share_error']:.0%}"])
    return rows


def window_rows(room: dict) -> list[list[str]]:
    """Rows of a room's windows with their point P and hours on the assessed day (header first)."""
    sun = assessed(room["sunlight"])
    by_name = {w["name"]: w for w in sun["windows"]} if sun else {}
    rows = [["window", "area m²", "sill / head m", "point P m", "sunlight on the assessed day"]]
    for w in room["windows"]:
        p = by_name.get(w["name"], {})
        hours = fmt_duration(p["hours_h"]) if p.get("hours_h") is not None else p.get("reason", "")
        rows.append([w["name"], f"{w['area_m2']}", f"{w['sill_z_m']} / {w['head_z_m']}",
                     "" if not p.get("point_p_m") else ", ".join(f"{c:g}" for c in p["point_p_m"]), hours])
    return rows


def solid_angle_words(ee: dict) -> str:
    """The view's solid angles' error as the reports print it: the estimate, and with ``view.refine:
    decided`` the widest interval and the tolerance it was refined to (docs/method.md)."""
    words = f"solid angles {fmt_bound(ee['max_solid_angle_error_sr'])} sr"
    if ee.get("refine") == "decided" and ee.get("max_solid_angle_interval_sr") is not None:
        words += (f" (computed as finely as the levels and view.tolerance {ee['tolerance']:g} need: every interval at most "
                  f"{ee['max_solid_angle_interval_sr']} sr wide)")
    return words


class Markup(str):
    """A table cell that is Markdown already (not escaped by :func:`_md_table`)."""


def _md_table(rows: list[list[str]]) -> list[str]:
    """A Markdown table; every cell is text (:func:`~en17037cli.report.labels.md`) but :class:`Markup` ones."""
    esc = lambda c: c if isinstance(c, Markup) else md(c)  # noqa: E731
    return (["| " + " | ".join(map(esc, rows[0])) + " |", "|" + "---|" * len(rows[0])]
            + ["| " + " | ".join(map(esc, r)) + " |" for r in rows[1:]])


def report_markdown(report: dict, figures=()) -> str:
    """report.md: the verdict and what limits each room on top, the pictures (PNG files beside it)
    per room, the parameters and notes; the per-point values stay in the CSV files."""
    L = [f"# EN 17037 check: {md(report['project']['name'])}", "",
         f"Overall status: **{report['status'].upper()}** (en17037cli {report['tool']['version']}, project file "
         f"`{report['project']['file']}`).", ""]
    if report["project"].get("description"):
        L += [report["project"]["description"], ""]
    L += dwellings_markdown(report)
    rows = verdict_rows(report)
    L += _md_table([["room", "check", "reached", "required", "result", "what limits it", "score"]]
                   + [[r["room"], r["check"], r["reached"], r["required"], Markup(f"**{r['result']}**"), r["limits"], r["score"]]
                      for r in rows])
    L += ["", "Score: 0 to 3, the level at each threshold and linear in between (beyond the standard; see docs/method.md of en17037cli).", ""]
    attention = [w for w in report["warnings"] if not is_repair(w)]
    if attention:
        L += ["**Warnings:**", ""] + [f"- {md(w)}" for w in attention] + [""]
    for room in report["rooms"]:
        L += ["", f"## Room {md(room['name'])}", "", f"Kind: {md(kind_text(room['kind']))}.", ""]
        if room.get("problem"):
            L += [f"Not assessable: {md(room['problem'])}", ""]
        L += _md_table(window_rows(room)) + [""]
        pics = [f for f in figures if f.room == room["name"]]
        v = assessed(room["view"])
        if v:
            ee = v["error_estimates"]
            L += [f"**View out: {v['level']}** (required {v['required']}, {STATUS_LABEL[v['status']]}); "
                  f"{md(limit_text('view', v))}.", "",
                  f"Error estimates: {solid_angle_words(ee)}, sight angle "
                  f"{fmt_bound(ee['max_horizontal_sight_angle_error_deg'])} deg, outside distance "
                  f"{fmt_bound(ee['max_outside_distance_error_m'])} m."]
            for e in v["eye_heights"]:
                L += ["", f"### Eye height {e['eye_height_m']} m: {len(e['points'])} points, level {e['level']}", ""]
                L += _md_table(share_table(e))
                L += ["", f"Points within their error estimate of a threshold: {e['points_near_threshold']}. "
                      "Every point's values: `view_points.csv`.", ""]
                for f in pics:
                    if f.section == "view" and f"-view-{e['eye_height_m']:g}m-" in f.name:
                        L += [f"![{md(f.caption)}]({f.name})", f"*{md(f.caption)}*", ""]
        s = assessed(room["sunlight"])
        if s:
            hrs = [d["hours_h"] for d in s["days"]]
            L += ["", f"**Exposure to sunlight: {s['level']}** (required {s['required']}, {STATUS_LABEL[s['status']]}); "
                  f"{md(limit_text('sunlight', s))}; ± {fmt_duration(s['error_estimates']['hours_error_h'])}. Over the period "
                  f"{fmt_duration(min(hrs))} to {fmt_duration(max(hrs))} a day (every day: `sunlight_days.csv`).", ""]
            L += [x for f in pics if f.section == "sunlight" for x in (f"![{md(f.caption)}]({f.name})", f"*{md(f.caption)}*", "")]
        d = assessed(room.get("daylight"))
        if d:
            L += ["", daylight_paragraph(d), ""] + _md_table(daylight_table(d)) + [""]
            L += [x for f in pics if f.section == "daylight" for x in (f"![{md(f.caption)}]({f.name})", f"*{md(f.caption)}*", "")]
        L += glare_markdown(room, pics, _md_table)
    L += ["", "## Technical notes", ""]
    files = report["inputs"].get("model_files", {})
    if files:
        L += _md_table([["model file", "SHA-256"]] + [[name, h.removeprefix("sha256:")] for name, h in files.items()]) + [""]
    L += ["### Parameters the standard leaves open", ""] + [f"- {line}" for line in parameter_lines(report)]
    repairs = [w for w in report["warnings"] if is_repair(w)]
    if repairs or report["notes"]:
        L += ["", "### The model as read", ""] + [f"- {md(n)}" for n in repairs + report["notes"]]
    return "\n".join(L) + "\n"
