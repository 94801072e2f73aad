"""The rules of EN 17037:2018+A1:2021 that this tool checks, in one place.

Every threshold of the standard lives in :data:`THRESHOLDS` (Annex A, Tables A.5 and A.6);
a project may override the values (a national annex) through its ``thresholds`` key.
"""
from __future__ import annotations

import numpy as np

#: Levels in increasing order. ``none`` means not even ``minimum`` is reached.
LEVELS: tuple[str, ...] = ("none", "minimum", "medium", "high")

#: EN 17037:2018+A1:2021 Annex A. Table A.5 (view out) and Table A.6 (exposure to sunlight).
#: Values compare with ``>=``.
THRESHOLDS: dict[str, dict[str, float]] = {
    # clause 5.2, Table A.5: horizontal sight angle [deg]
    "horizontal_sight_angle_deg": {"minimum": 14.0, "medium": 28.0, "high": 54.0},
    # clause 5.2, Table A.5: outside distance of the view [m]
    "outside_distance_m": {"minimum": 6.0, "medium": 20.0, "high": 50.0},
    # clause 5.3, Table A.6: duration of exposure to sunlight on the assessed day [h]
    "sunlight_hours": {"minimum": 1.5, "medium": 3.0, "high": 4.0},
}

#: Clause 5.2, Table A.5: the view layers that must be visible for each level.
#: ``minimum``: landscape; ``medium``: landscape and (sky or ground); ``high``: all three.
LAYER_RULE: dict[str, str] = {
    "minimum": "landscape",
    "medium": "landscape + (sky or ground)",
    "high": "sky + landscape + ground",
}

#: Clause 5.2: eye heights of a seated and a standing person above the floor [m].
EYE_HEIGHTS_M = (1.2, 1.7)
#: Clause 5.3 and Annex A.3: point P lies at least this high above the floor [m] ...
SUN_POINT_MIN_ABOVE_FLOOR_M = 1.2
#: ... and at least this high above the window sill [m].
SUN_POINT_MIN_ABOVE_SILL_M = 0.3
#: Clause 5.3: the assessed date lies between 1 February and 21 March (MM-DD).
SUN_PERIOD = ("02-01", "03-21")


def level_index(level: str) -> int:
    """Position of ``level`` in :data:`LEVELS` (0 for ``none``)."""
    return LEVELS.index(level)


def level_name(index) -> str:
    """Inverse of :func:`level_index`."""
    return LEVELS[int(index)]


def level_from_value(values, thresholds: dict[str, float]) -> np.ndarray:
    """Level index (0..3) reached by each value, comparing with ``>=``.

    Parameters
    ----------
    values : (n,) float
        Quantity in the thresholds' unit; ``+inf`` reaches every level, NaN none.
    thresholds : dict
        ``{"minimum": a, "medium": b, "high": c}`` in the same unit.

    Returns
    -------
    (n,) int
    """
    v = np.asarray(values, dtype=float)
    with np.errstate(invalid="ignore"):
        return (
            (v >= thresholds["minimum"]).astype(int)
            * (1 + (v >= thresholds["medium"]).astype(int) * (1 + (v >= thresholds["high"]).astype(int)))
        )


def level_from_layers(sky, landscape, ground) -> np.ndarray:
    """Level index (0..3) of the view layers, EN 17037 Table A.5.

    Parameters
    ----------
    sky, landscape, ground : (n,) bool
        Whether each layer is visible from the point.
    """
    sky, landscape, ground = (np.asarray(a, dtype=bool) for a in (sky, landscape, ground))
    return np.where(
        landscape & sky & ground, 3, np.where(landscape & (sky | ground), 2, np.where(landscape, 1, 0))
    )


def near_threshold(values, errors, thresholds) -> np.ndarray:
    """True where a value lies within its (positive) error estimate of a threshold: the level could flip.

    A value with zero error is exact and never near, even when it equals a threshold.

    Parameters
    ----------
    values, errors : (n,) float
        Value and its error estimate, in the thresholds' unit.
    thresholds : dict or sequence of float
        ``{"minimum": a, "medium": b, "high": c}``, or the threshold values themselves (e.g. the
        one solid angle above which a view layer counts).
    """
    v = np.asarray(values, dtype=float)[..., None]
    e = np.asarray(errors, dtype=float)[..., None]
    levels = [thresholds[k] for k in LEVELS[1:]] if isinstance(thresholds, dict) else list(thresholds)
    t = np.array(levels, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.any(np.isfinite(v) & (e > 0) & (np.abs(v - t) <= e), axis=-1)


def room_level(point_levels, area_fraction: float) -> tuple[int, dict[str, float]]:
    """Room level: the highest level reached by at least ``area_fraction`` of the points.

    Points count equally (the viewpoint grid is equal-area).

    Returns
    -------
    level : int
    share_by_level : dict
        Share of points reaching at least each level (``none`` is always 1).
    """
    lv = np.asarray(point_levels, dtype=int)
    n = max(lv.size, 1)
    share = {name: float(np.count_nonzero(lv >= i)) / n if lv.size else 0.0 for i, name in enumerate(LEVELS)}
    share["none"] = 1.0
    level = 0
    for i in range(1, len(LEVELS)):
        if lv.size and share[LEVELS[i]] >= area_fraction - 1e-12:
            level = i
    return level, share


def passes(level: str, required: str) -> bool:
    """Whether ``level`` meets ``required``."""
    return level_index(level) >= level_index(required)
