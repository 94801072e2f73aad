"""What limits each room, in words: the sentences report.md, report.html and the terminal print
from the ``limiting`` entries of report.json (see :func:`en17037cli.standard.view_limit` and
:func:`en17037cli.standard.sunlight_limit`)."""
from __future__ import annotations

import datetime as dt

from en17037cli.report.glare_text import glare_limit_text
from en17037cli.report.labels import assessed
from en17037cli.report.numbers import fmt_duration

#: How the sentences name the view criteria of Table A.5.
CRITERION_WORDS = {"horizontal_sight_angle": "sight angle", "outside_distance": "outside distance", "layers": "layers"}


def percent(share: float) -> str:
    """A share in [0, 1] as a whole percentage, never rounded up to 100 % or down to 0 % when it is not."""
    p = round(100.0 * share)
    if p == 100 and share < 1.0:
        p = 99
    if p == 0 and share > 0.0:
        p = 1
    return f"{p} %"


def long_date(iso: str) -> str:
    """``2021-02-01`` as ``1 February``."""
    d = dt.date.fromisoformat(iso)
    return f"{d.day} {d.strftime('%B')}"


def view_limit_text(section: dict) -> str:
    """``sight angle: 67 % of points reach medium at 1.2 m eye height, 75 % needed``."""
    lim = section["limiting"]
    if not lim["criterion"]:
        return "no viewpoint"
    eye = f" at {lim['eye_height_m']:g} m eye height" if lim.get("eye_height_m") is not None else ""
    return (f"{CRITERION_WORDS[lim['criterion']]}: {percent(lim['value'])} of points reach {lim['level']}{eye}, "
            f"{percent(lim['needed'])} needed")


def sunlight_limit_text(section: dict) -> str:
    """``sunlight: 1 h 12 min on 1 February, 18 min short of medium`` (or ``... above medium``)."""
    lim = section["limiting"]
    margin = lim["margin"]
    how = f"{fmt_duration(-margin)} short of" if margin < 0 else f"{fmt_duration(margin)} above"
    if margin == 0:
        how = "exactly at"
    return f"sunlight: {fmt_duration(section['hours_h'])} on {long_date(section['assessed_date'])}, {how} {lim['level']}"


def daylight_limit_text(section: dict) -> str:
    """``daylight: 41 % of the plane reaches 300 lx (D >= 2.1 %) at minimum, 50 % needed``."""
    lim = section["limiting"]
    lv = section["levels"][lim["level"]]
    minimum = lim["criterion"] == "daylight_minimum_target"
    lx = lv["minimum_target_lx" if minimum else "target_lx"]
    df = lv.get("minimum_target_daylight_factor_pct" if minimum else "target_daylight_factor_pct")
    how = f" (D ≥ {df:g} %)" if df is not None else " on half of the daylight hours"
    return (f"daylight: {percent(lim['value'])} of the plane reaches {lx:g} lx{how} at {lim['level']}, "
            f"{percent(lim['needed'])} needed")


def limit_text(criterion: str, section: dict | None) -> str:
    """The sentence for a room's criterion section, or "" where it holds no result."""
    s = assessed(section)
    if s is None or "limiting" not in s:
        return ""
    if criterion == "daylight":
        return daylight_limit_text(s)
    if criterion == "glare":
        return glare_limit_text(s)
    return view_limit_text(s) if criterion == "view" else sunlight_limit_text(s)
