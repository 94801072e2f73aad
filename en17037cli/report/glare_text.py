"""Clause 5.4 in words and tables for report.md, report.html and the terminal, from report.json's
``glare`` sections; and the section that reads sunlight (5.3) and glare (5.4) together."""
from __future__ import annotations

from en17037cli.report.labels import STATUS_LABEL, assessed, md
from en17037cli.report.numbers import fmt_duration


def glare_limit_text(section: dict) -> str:
    """``glare: DGP 0.62 exceeded in 5 % of the 2610 usage hours at window 'W', towards; at most 0.45 for minimum``."""
    lim = section["limiting"]
    p = section["positions"][section["worst_position"]]
    return (f"glare: DGP {lim['value']:.2f} exceeded in 5 % of the {section['usage_hours']} usage hours at view "
            f"{section['worst_position'] + 1} ({p['label']}); at most {lim['needed']:.2f} for {lim['level']}")


def shading_words(section: dict) -> str:
    """What the shading of the check is, and what the room needs."""
    sh = section.get("shading")
    now = "no shading device" if sh is None else (f"a movable device of transmittance {sh['transmittance']:g}, down "
                                                  + ("every usage hour" if sh["control"] == "always" else
                                                     "in the hours its DGP exceeds the required level's limit"))
    if section.get("status") == "fail" and section.get("level") is not None:
        now += "; " + needed_words(section)
    return now


def needed_words(section: dict) -> str:
    """The movable device a failing room needs, found by re-running the hours of glare behind it."""
    need, hidden = section.get("transmittance_needed"), section.get("transmittance_needed_sun_hidden")
    tried = min(section.get("transmittance_tried") or [0])
    req = section["required"]
    if need is not None:
        return f"it reaches {req} with a movable device of transmittance {need:g} or less, down in the hours of glare"
    if hidden is not None:
        return (f"no device that only dims the sun (to transmittance {tried:g}) brings it to {req}; one through which "
                f"the sun's disc is not seen (normal-normal transmittance 0) does at transmittance {hidden:g} or less")
    return f"no movable device down to transmittance {tried:g}, even one hiding the sun's disc, brings it to {req}"


def glare_paragraph(section: dict) -> str:
    """The glare verdict of a room in words: level, what limits it, the method and its errors."""
    m = section["method"]
    head = f"**Protection from glare: {section['level'] or '-'}** (required {section['required']}, {STATUS_LABEL[section['status']]})"
    if "limiting" not in section:
        return f"{head}; {section.get('reason', '')}."
    err = section["error_estimates"]
    ref = section["reference_check"]
    check = ""
    if ref["hours"]:
        check = (f" Reference check at {len(ref['hours'])} hours of view {section['worst_position'] + 1} (evalglare on rpict "
                 f"fisheyes): DGP differs by {ref['max_abs_dgp_difference']:.3f} at most, the annual method "
                 f"{abs(ref['mean_dgp_difference']):.3f} {'lower' if ref['mean_dgp_difference'] < 0 else 'higher'} on average; "
                 f"every hour moved by that mean, the room's level is {ref['level_with_mean_difference']}.")
    return (f"{head}; {glare_limit_text(section)}. Usage time {m['usage']} of {m['year']} ({section['usage_hours']} hours, "
            f"weather `{m['weather']}`); DGP ± {err['dgp_error']:.3f}. The sun is in view at a critical position in "
            f"{section['sun_in_view_hours']} usage hours. Shading: {shading_words(section)}.{check} Every view: "
            "`glare_points.csv`; every hour of the worst view: `glare_hours.csv`.")


def positions_table(section: dict) -> list[list[str]]:
    """Rows of a room's views (header first): where, which way, the DGP exceeded in 5 % of the hours."""
    lims = sorted(section["method"]["dgp_limits"].values())
    rows = [["view", "position", "point m", "looks (deg from N)", "DGP 5 %", *[f"hours > {x:.2f}" for x in lims],
             "sun in view h", "level"]]
    for p in section["positions"]:
        rows.append([str(p["index"] + 1), p["label"], ", ".join(f"{c:g}" for c in p["point"]), f"{p['direction_deg']:g}",
                     f"{p['dgp_5pct']:.3f} ± {p['dgp_5pct_error']:.3f}", *[str(p["hours_over"].get(f"{x:.2f}", "")) for x in lims],
                     str(p["sun_in_view_hours"]), p["level"]])
    return rows


def reference_table(section: dict) -> list[list[str]]:
    """Rows of the reference check (header first)."""
    rows = [["hour", "DGP annual method", "DGP evalglare", "E_v annual lx", "E_v evalglare lx", "classes"]]
    for h in section.get("reference_check", {}).get("hours", []):
        rows.append([h["local_time"], f"{h['dgp_fast']:.3f}", f"{h['dgp_evalglare']:.3f}", f"{h['ev_fast_lx']:.0f}",
                     f"{h['ev_evalglare_lx']:.0f}", f"{h['class_fast']} / {h['class_evalglare']}"])
    return rows


def moments_table(section: dict) -> list[list[str]]:
    """Rows of the point-in-time checks (header first)."""
    rows = [["time", "position", "looks (deg from N)", "DGP", "E_v lx", "sky"]]
    for m in section.get("moments", []):
        rows.append([m["time"], m["position"], f"{m['direction_deg']:g}", "-" if m["dgp"] is None else f"{m['dgp']:.3f}",
                     "-" if m["vertical_illuminance_lx"] is None else f"{m['vertical_illuminance_lx']:.0f}", m["sky"]])
    return rows


def together_text(room: dict) -> str | None:
    """Sunlight (5.3) and glare (5.4) read together (Brembilla et al. 2021: a room that reaches sunlight
    needs the shading 5.4 asks for), for a room with both: None otherwise."""
    sun, gl = assessed(room.get("sunlight")), assessed(room.get("glare"))
    if not sun or not gl or "limiting" not in gl:
        return None
    text = (f"Sunlight and glare together: {fmt_duration(sun['hours_h'])} of sunlight at point P on "
            f"{sun['assessed_date']} (5.3: {sun['level']}); the sun in view at a critical position in {gl['sun_in_view_hours']} "
            f"of the {gl['usage_hours']} usage hours of the year (5.4: {gl['level']}).")
    if sun["status"] == "pass" and gl["status"] == "fail":
        text += f" The room passes 5.3 and fails 5.4: it needs shading; {needed_words(gl)}."
    return text


def glare_markdown(room: dict, figures, md_table) -> list[str]:
    """The glare part of a room in report.md (``md_table`` draws a table)."""
    g = room.get("glare")
    if not g or g.get("status") not in ("pass", "fail", "not_assessable") or "method" not in g:
        return []
    L = ["", glare_paragraph(g), ""]
    if g["positions"]:
        L += md_table(positions_table(g)) + [""]
    if g.get("reference_check", {}).get("hours"):
        L += md_table(reference_table(g)) + [""]
    if g.get("moments"):
        L += md_table(moments_table(g)) + [""]
    both = together_text(room)
    if both:
        L += [both, ""]
    L += [x for f in figures if f.section == "glare" for x in (f"![{md(f.caption)}]({f.name})", f"*{md(f.caption)}*", "")]
    return L


def glare_parameters(cfg: dict) -> list[str]:
    """The choices of clause 5.4 this run made, for the reports' list of parameters."""
    if "glare" not in cfg:
        return []
    g = cfg["glare"]
    u = g["usage"]
    days = u["days"] if isinstance(u["days"], str) else ", ".join(u["days"])
    pos = ("auto: per window an eye {} m into the room at {} m, looking {}".format(
        g["facade_distance_m"], g["eye_height_m"], " and ".join(g["directions"])) if g["positions"] == "auto"
           else f"{len(g['positions'])} listed")
    lim = g["dgp_limits"]
    return [f"Glare: usage {u['start']} to {u['end']}, {days}, {g['year']}; positions {pos}; DGP limits {lim['minimum']} / "
            f"{lim['medium']} / {lim['high']} exceeded in at most 5 % of the usage hours; glare sources above "
            f"{g['source_threshold_cd_m2']:g} cd/m²; low-light correction {'on' if g['low_light_correction'] else 'off'}; "
            f"{g['view_rays']} rays per eye, Reinhart sky MF {g['sky_subdivision']}, Radiance -ab {g['radiance']['ab']} "
            f"-ad {g['radiance']['ad']}, {g['radiance']['replicates']} replicates; shading {g['shading']}."]
