"""Numbers as the reports write them: fixed decimals, so the same inputs give byte-identical files."""
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
