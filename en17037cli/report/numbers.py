"""Numbers as the reports write them: fixed decimals and durations to the minute, so the same inputs give byte-identical files."""
from __future__ import annotations

import datetime as dt
import math


def json_number(x, nd: int = 6):
    """Round for JSON: None for NaN and infinities, floats to ``nd`` decimals (``-0.0`` folded to ``0.0``)."""
    if x is None:
        return None
    x = float(x)
    if math.isnan(x) or math.isinf(x):
        return None
    v = round(x, nd)
    return 0.0 if v == 0 else v


def json_xyz(p, nd: int = 4) -> list:
    """A point [m] as a list of rounded coordinates."""
    return [json_number(c, nd) for c in p]


def iso_time(t: float, tz) -> str:
    """Unix time [s] as local ISO 8601 to the second, in time zone ``tz``."""
    return dt.datetime.fromtimestamp(round(float(t)), tz).isoformat(timespec="seconds")


def _minutes(hours: float) -> tuple[str, int]:
    """A finite duration [h] as its sign (``"-"`` or ``""``) and whole minutes, half a minute rounding up whatever the parity."""
    total = math.floor(abs(hours) * 60.0 + 0.5)
    return ("-" if hours < 0 and total else ""), total


def fmt_duration(hours: float) -> str:
    """A duration as reports write it, rounded to the minute: ``"5 h 52 min"``, ``"18 min"``, ``"0 min"``, ``"4 h"``.

    Parameters
    ----------
    hours : float [h]
        None, NaN or infinite gives ``"n/a"``; a negative duration keeps its sign.

    Returns
    -------
    str
    """
    if hours is None:
        return "n/a"
    h = float(hours)
    if not math.isfinite(h):
        return "n/a"
    sign, total = _minutes(h)
    hh, mm = divmod(total, 60)
    if hh == 0:
        return f"{sign}{mm} min"
    return f"{sign}{hh} h" + (f" {mm} min" if mm else "")


def fmt_hm(hours: float) -> str:
    """A finite duration [h] as ``"h:mm"`` rounded to the minute, like :func:`fmt_duration`: ``"5:52"``, ``"-0:30"``."""
    sign, total = _minutes(hours)
    return f"{sign}{total // 60}:{total % 60:02d}"


def json_limit(limit) -> dict:
    """A :class:`~en17037cli.standard.Limit` in report.json (shares and hours to 4 decimals)."""
    digits = 4
    out = {"level": limit.level, "criterion": limit.criterion, "value": json_number(limit.value, digits),
           "needed": json_number(limit.needed, digits), "margin": json_number(limit.margin, digits)}
    if limit.eye_height_m is not None:
        out["eye_height_m"] = json_number(limit.eye_height_m, 3)
    return out


def json_scores(score: float, parts=()) -> dict:
    """A continuous score in report.json: its value (0 to 3, 4 decimals) and, for the view, each
    eye height and criterion's quantity, score and margins (see en17037cli.criteria.view.scores)."""
    out: dict = {"value": json_number(score, 4)}
    if parts:
        out["by_criterion"] = [{"criterion": p.criterion, "eye_height_m": json_number(p.eye_height_m, 3),
                                "quantity": json_number(p.quantity, 4), "unit": p.unit, "score": json_number(p.score, 4),
                                "margin_up": json_number(p.margin_up, 4), "margin_down": json_number(p.margin_down, 4)}
                               for p in parts]
    return out


def fmt_bound(x, nd: int = 6) -> str:
    """An error bound as the reports print it: ``"≤ 0.0054"``; a bound the JSON rounded to 0 at
    ``nd`` decimals is ``"< 5e-07"`` (half the last decimal), since 0 would read as "no error"."""
    if x is None:
        return "n/a"
    if float(x) == 0.0:
        return f"< {0.5 * 10.0 ** -nd:g}"
    return f"≤ {x}"
