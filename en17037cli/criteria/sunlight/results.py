"""Typed result of the sunlight criterion for one room."""
from __future__ import annotations

import datetime as dt
from dataclasses import dataclass, field

import numpy as np


@dataclass
class SunlightResult:
    """Point P per window, every day's sun hours and intervals, the assessed day and its level.

    points_local : (k, 3) float [m], point P of each window of the room
    reveal_depths_m : per window, the reveal depth found [m], None where P was given explicitly
    hours : (d,) float [h], per day of the period; intervals : per day, (j, 2) float unix times [s]
    error_h : (d,) float [h], error estimate of each day's hours
    assessed_index : the day judged (``sunlight.date``); level : level index reached that day
    window_problems : per window, why it has no point P (its P is NaN and it is left out), or None
    window_hours : (k, d) float [h], each window's hours alone (P through that window only), NaN
        where it has no point P
    window_points : per window, (j, 3) float [m] the points whose sun is the window's (P, or the
        clear glass beside a member of its frame in front of P), None where it has no point P
    member_hours : per window whose P lies behind a member of its frame, (d,) [h] hours with P
        ``as_drawn`` and at the ``nearest_glass`` beside the member; None for the others
    """

    points_local: np.ndarray
    reveal_depths_m: list
    dates: list[dt.date]
    hours: np.ndarray
    intervals: list[np.ndarray]
    error_h: np.ndarray
    assessed_index: int
    level: int
    near_threshold: bool
    timestep_s: float
    notes: list[str] = field(default_factory=list)
    window_problems: list[str | None] = field(default_factory=list)
    window_hours: np.ndarray | None = None
    window_points: list = field(default_factory=list)
    member_hours: list = field(default_factory=list)
