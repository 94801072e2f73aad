"""The rules of EN 17037:2018+A1:2021 that this tool checks, in one place.

Every threshold of the standard lives in :data:`THRESHOLDS` (Annex A, Tables A.5 and A.6); a
project may override the values (a national annex) through its ``thresholds`` key. Every way of
turning values into levels, and levels into a verdict, is a function here: the engines compute
quantities, this module judges them.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

#: Levels in increasing order. ``none`` means not even ``minimum`` is reached.
LEVELS: tuple[str, ...] = ("none", "minimum", "medium", "high")


@dataclass(frozen=True)
class LevelThresholds:
    """The values a quantity must reach (``>=``) for each level, in the quantity's unit."""

    minimum: float
    medium: float
    high: float

    def values(self) -> tuple[float, float, float]:
        """(minimum, medium, high)."""
        return (self.minimum, self.medium, self.high)

    def as_dict(self) -> dict[str, float]:
        return {"minimum": self.minimum, "medium": self.medium, "high": self.high}


@dataclass(frozen=True)
class Thresholds:
    """The thresholds of every criterion (EN 17037 Annex A, or a national annex's values)."""

    horizontal_sight_angle_deg: LevelThresholds
    outside_distance_m: LevelThresholds
    sunlight_hours: LevelThresholds
    daylight_target_lx: LevelThresholds
    daylight_minimum_target_lx: LevelThresholds

    @classmethod
    def from_dict(cls, d: dict) -> Thresholds:
        return cls(**{k: LevelThresholds(**d[k]) for k in THRESHOLDS})


#: EN 17037:2018+A1:2021 Annex A. Table A.5 (view out) and Table A.6 (exposure to sunlight).
#: Values compare with ``>=``.
THRESHOLDS: dict[str, dict[str, float]] = {
    # clause 5.2, Table A.5: horizontal sight angle [deg]
    "horizontal_sight_angle_deg": {"minimum": 14.0, "medium": 28.0, "high": 54.0},
    # clause 5.2, Table A.5: outside distance of the view [m]
    "outside_distance_m": {"minimum": 6.0, "medium": 20.0, "high": 50.0},
    # clause 5.3, Table A.6: duration of exposure to sunlight on the assessed day [h]
    "sunlight_hours": {"minimum": 1.5, "medium": 3.0, "high": 4.0},
    # clause 5.1, Table A.1: target illuminance E_T over DAYLIGHT_SHARES["target"] of the reference plane [lx]
    "daylight_target_lx": {"minimum": 300.0, "medium": 500.0, "high": 750.0},
    # clause 5.1, Table A.1: minimum target illuminance E_TM over DAYLIGHT_SHARES["minimum_target"] of it [lx]
    "daylight_minimum_target_lx": {"minimum": 100.0, "medium": 300.0, "high": 500.0},
}

#: Clause 5.1, Table A.1: share of the reference plane that must reach the target (``target``)
#: and the minimum target (``minimum_target``) illuminance, for vertical and inclined openings.
DAYLIGHT_SHARES: dict[str, float] = {"target": 0.50, "minimum_target": 0.95}
#: Clause 5.1: a point reaches an illuminance when it is exceeded for at least this share of the daylight hours.
DAYLIGHT_HOURS_FRACTION = 0.5
#: Clause 5.1 and Annex A.2: the daylight hours are the half of the year's hours (8760 / 2) with the
#: highest diffuse horizontal illuminance; E_v,d,med is the median diffuse horizontal illuminance over them.
DAYLIGHT_HOURS = 4380
#: Annex A: height of the reference plane above the floor [m] ...
REFERENCE_PLANE_M = 0.85
#: ... which leaves out a band this wide along the walls [m].
REFERENCE_PLANE_WALL_BAND_M = 0.5

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

#: Clause 5.4 (EN 17037:2018+A1:2021): the daylight glare probability a level allows at
#: a critical position, exceeded in at most GLARE_EXCEEDANCE of the usage hours (compared with ``<=``).
GLARE_DGP_LIMITS: dict[str, float] = {"minimum": 0.45, "medium": 0.40, "high": 0.35}
GLARE_EXCEEDANCE = 0.05
#: Clause 5.4: the usage time of the annual method, local clock: 08:00 to 18:00, Monday to Friday.
GLARE_USAGE = ("08:00", "18:00", "weekdays")


def dgp_exceeded(dgp, fraction: float = GLARE_EXCEEDANCE) -> np.ndarray:
    """DGP exceeded in ``fraction`` of the hours (DGP_e,5% of clause 5.4): the (m + 1)-th largest
    value, m = floor(fraction n), so that at most m hours lie above it. ``dgp``: (..., n) per hour;
    NaN with no hour. A level's limit is met when this value is at or below it (:func:`glare_level`)."""
    v = np.sort(np.asarray(dgp, dtype=float), axis=-1)
    n = v.shape[-1]
    if n == 0:
        return np.full(v.shape[:-1], np.nan)
    m = int(np.floor(fraction * n + 1e-9))
    return v[..., n - 1 - min(m, n - 1)]


def glare_level(dgp_5pct, limits: dict[str, float] | None = None) -> np.ndarray:
    """Level index (0..3) of the DGP exceeded in 5 % of the usage hours: the highest level whose limit
    it does not pass (clause 5.4); NaN reaches none."""
    lim = limits or GLARE_DGP_LIMITS
    v = np.asarray(dgp_5pct, dtype=float)
    with np.errstate(invalid="ignore"):
        return ((v <= lim["minimum"]).astype(int) * (1 + (v <= lim["medium"]).astype(int) * (1 + (v <= lim["high"]).astype(int))))


#: The view criteria of Table A.5, each judged over the viewpoints (clause 5.2).
VIEW_CRITERIA = ("horizontal_sight_angle", "outside_distance", "layers")


def level_index(level: str) -> int:
    """Position of ``level`` in :data:`LEVELS` (0 for ``none``)."""
    return LEVELS.index(level)


def level_name(index) -> str:
    """Inverse of :func:`level_index`."""
    return LEVELS[int(index)]


def level_from_value(values, thresholds: LevelThresholds) -> np.ndarray:
    """Level index (0..3) reached by each value, comparing with ``>=``.

    Parameters
    ----------
    values : (n,) float
        Quantity in the thresholds' unit; ``+inf`` reaches every level, NaN none.
    thresholds : LevelThresholds
        In the same unit.

    Returns
    -------
    (n,) int
    """
    v = np.asarray(values, dtype=float)
    with np.errstate(invalid="ignore"):
        return (
            (v >= thresholds.minimum).astype(int)
            * (1 + (v >= thresholds.medium).astype(int) * (1 + (v >= thresholds.high).astype(int)))
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


def layer_visible(solid_angle_sr, threshold_sr: float) -> np.ndarray:
    """Whether a view layer counts as visible: its solid angle exceeds the threshold [sr].

    EN 17037 does not say how much of a layer must be seen; the threshold is a project parameter
    (``view.layer_threshold_sr``, 0 by default: any part of it, as in Brembilla et al. 2021).
    """
    return np.asarray(solid_angle_sr, dtype=float) > threshold_sr


def near_threshold(values, errors, thresholds: LevelThresholds | Sequence[float]) -> np.ndarray:
    """True where a value lies within its (positive) error estimate of a threshold: the level could flip.

    A value with zero error is exact and never near, even when it equals a threshold.

    Parameters
    ----------
    values, errors : (n,) float
        Value and its error estimate, in the thresholds' unit.
    thresholds : LevelThresholds or sequence of float
        The level thresholds, or the threshold values themselves (e.g. the one solid angle above
        which a view layer counts).
    """
    v = np.asarray(values, dtype=float)[..., None]
    e = np.asarray(errors, dtype=float)[..., None]
    t = np.array(thresholds.values() if isinstance(thresholds, LevelThresholds) else list(thresholds), dtype=float)
    with np.errstate(invalid="ignore"):
        return np.any(np.isfinite(v) & (e > 0) & (np.abs(v - t) <= e), axis=-1)


def room_level(point_levels, area_fraction: float) -> tuple[int, dict[str, float]]:
    """Room level: the highest level reached by at least ``area_fraction`` of the points.

    EN 17037 clause 5.2 judges view over the utilised area; the share of it that must reach a
    level is a project parameter (``view.area_fraction``, 0.75 by default).

    Parameters
    ----------
    point_levels : (n,) int
    area_fraction : float in (0, 1]

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


def point_view_level(*criterion_levels) -> np.ndarray:
    """View level of each point: the lowest of its criteria's levels (clause 5.2, Table A.5)."""
    out = np.asarray(criterion_levels[0])
    for lv in criterion_levels[1:]:
        out = np.minimum(out, lv)
    return out


def view_level(levels: Iterable[int]) -> int:
    """The lowest of several levels (over the criteria of an eye height, or over the eye heights
    of a room: EN 17037 clause 5.2 asks the view of seated and standing people); 0 if none."""
    levels = list(levels)
    return min(levels) if levels else 0


def passes(level: str, required: str) -> bool:
    """Whether ``level`` meets ``required``."""
    return level_index(level) >= level_index(required)


def status(level: str, required: str) -> str:
    """``pass`` or ``fail`` of one criterion of one room."""
    return "pass" if passes(level, required) else "fail"


def sunlight_rooms_pass(room_passes: Sequence[bool], rule: str) -> bool:
    """Whether the rooms of one dwelling meet the sunlight requirement together.

    EN 17037 clause 5.3 asks sunlight of at least one habitable room of a dwelling (``any``: of
    its main rooms, those that may satisfy the rule); ``all`` asks it of every room. An empty list
    passes (no room of the dwelling requires sunlight).
    """
    if not room_passes:
        return True
    return all(room_passes) if rule == "all" else any(room_passes)


@dataclass(frozen=True)
class Limit:
    """What limits a room's level in one check, and by how much.

    level : the level the margin is measured to (:func:`target_level`)
    criterion : ``horizontal_sight_angle``, ``outside_distance``, ``layers`` (view) or
        ``sunlight_hours``
    value : share of viewpoints reaching ``level`` (view, in [0, 1]) or hours on the assessed day
        (sunlight, [h])
    needed : the share the standard asks (``view.area_fraction``) or the level's threshold [h]
    eye_height_m : the eye height whose points limit the view [m]; None for sunlight
    """

    level: str
    criterion: str
    value: float
    needed: float
    eye_height_m: float | None = None

    @property
    def margin(self) -> float:
        """``value - needed``: negative when the level is missed (share, or [h])."""
        return self.value - self.needed


def target_level(reached: int, required: str) -> int:
    """The level a margin is measured to: the required level where one is required (how far
    above or below it the room is), else the level above the one reached (what keeps the room
    from it), ``high`` once high is reached."""
    if required != "none":
        return level_index(required)
    return min(int(reached) + 1, len(LEVELS) - 1)


def view_limit(eye_heights: Sequence[tuple[float, dict[str, dict[str, float]]]], reached: int, required: str,
               area_fraction: float) -> Limit:
    """The criterion and eye height with the smallest share of viewpoints reaching the target level.

    Clause 5.2: a room's view level is the lowest over its criteria and eye heights, each judged
    by the share of the utilised area (of its viewpoints) reaching it, ``area_fraction`` needed.

    Parameters
    ----------
    eye_heights : (eye height [m], criterion -> level name -> share in [0, 1]) per eye height,
        criteria of :data:`VIEW_CRITERIA`
    reached : the room's view level index; required : the level required ("none" if none)
    area_fraction : share of the viewpoints that must reach a level, in (0, 1]
    """
    t = LEVELS[target_level(reached, required)]
    cands = [(shares[c][t], i, k, eye, c) for i, (eye, shares) in enumerate(eye_heights)
             for k, c in enumerate(VIEW_CRITERIA) if c in shares]
    if not cands:
        return Limit(t, "", 0.0, area_fraction, None)
    share, _, _, eye, c = min(cands)  # ties: the lower eye height, then the order of Table A.5
    return Limit(t, c, share, area_fraction, eye)


def sunlight_limit(hours: float, reached: int, required: str, thresholds: LevelThresholds) -> Limit:
    """Hours of sunlight on the assessed day against the threshold of the target level (clause 5.3,
    Table A.6)."""
    t = target_level(reached, required)
    return Limit(LEVELS[t], "sunlight_hours", float(hours), thresholds.values()[t - 1] if t > 0 else 0.0)


def daylight_level(target_share: dict[str, float], minimum_share: dict[str, float]) -> int:
    """Level index (0..3) of daylight provision (clause 5.1, Table A.1): the highest level whose
    target illuminance is reached on at least :data:`DAYLIGHT_SHARES` ``target`` of the reference
    plane and whose minimum target illuminance on at least ``minimum_target`` of it.

    Parameters
    ----------
    target_share, minimum_share : level name -> share of the reference plane's points in [0, 1]
        that reach the level's target (minimum target) illuminance for at least half of the
        daylight hours (method 2), or whose daylight factor reaches D_T (D_TM) (method 1)
    """
    level = 0
    for i in range(1, len(LEVELS)):
        name = LEVELS[i]
        if (target_share[name] >= DAYLIGHT_SHARES["target"] - 1e-12
                and minimum_share[name] >= DAYLIGHT_SHARES["minimum_target"] - 1e-12):
            level = i
        else:
            break
    return level


def daylight_limit(target_share: dict[str, float], minimum_share: dict[str, float], reached: int, required: str,
                   minimum_lx: dict[str, float] | None = None) -> Limit:
    """The requirement of Table A.1 with the smallest margin at the target level: ``daylight_target``
    (share of the plane reaching E_T, 50 % needed) or ``daylight_minimum_target`` (E_TM, 95 %). A
    minimum target of 0 lx (``minimum_lx``, level -> E_TM [lx]: a practice that asks none, as the UK
    National Annex) never limits: every point reaches it."""
    t = LEVELS[target_level(reached, required)]
    a = Limit(t, "daylight_target", float(target_share[t]), DAYLIGHT_SHARES["target"])
    b = Limit(t, "daylight_minimum_target", float(minimum_share[t]), DAYLIGHT_SHARES["minimum_target"])
    if minimum_lx is not None and minimum_lx[t] <= 0:
        return a
    return a if a.margin <= b.margin else b


# --- continuous scores (beyond the standard) -------------------------------------------------
#
# EN 17037 gives levels only. For design optimisation and sensitivity studies a score in [0, 3]
# follows the underlying quantity: it equals the level index at the level's threshold and is
# linear in the quantity between thresholds (0 at a quantity of 0, 3 at and above ``high``), so
# it is continuous and non-decreasing in the quantity, and floor(score) is the level.


def score_from_value(values, thresholds: LevelThresholds) -> np.ndarray:
    """Continuous score in [0, 3] of quantities (beyond the standard): piecewise linear through
    (0, 0), (minimum, 1), (medium, 2), (high, 3); 3 above high (+inf included), 0 below 0, NaN kept.

    Parameters
    ----------
    values : array_like, in the thresholds' unit ([deg], [m], [h])
    """
    v = np.asarray(values, dtype=float)
    out = np.interp(np.where(np.isnan(v), 0.0, v), [0.0, *thresholds.values()], [0.0, 1.0, 2.0, 3.0])
    return np.where(np.isnan(v), np.nan, out)


def area_quantile(values, area_fraction: float) -> float:
    """The value that ``area_fraction`` of the points reach: the k-th largest, k = ceil(n x
    area_fraction) (NaN and -inf count as not reaching anything). ``level_from_value`` of it is
    the room level of :func:`room_level` on the same points (clause 5.2: the share of the
    utilised area); NaN without points."""
    v = np.asarray(values, dtype=float).ravel()
    if not v.size:
        return float("nan")
    v = np.sort(np.where(np.isnan(v), -np.inf, v))[::-1]
    k = max(1, int(np.ceil(v.size * area_fraction - 1e-9)))
    return float(v[k - 1])


def margins(quantity: float, level: int, thresholds: LevelThresholds) -> tuple[float | None, float | None]:
    """(up, down): how much ``quantity`` must grow to reach the next level, and how much it can
    lose before it drops a level, in the quantity's unit; None beyond high or below minimum, and
    ``down`` None for an infinite quantity."""
    t = thresholds.values()
    up = None if level >= 3 else t[level] - quantity
    down = None if level <= 0 or not np.isfinite(quantity) else quantity - t[level - 1]
    return up, down


def share_score(share_by_level: dict[str, float], area_fraction: float) -> tuple[float, int]:
    """Score of a criterion judged by shares of points (the view layers, whose points have levels
    but no continuous quantity): level L plus the share reaching L + 1 over the share needed,
    ``L + min(s(L+1) / area_fraction, 1)`` capped at 3; (score, L). It reaches L + 1 as the share
    does; at that moment it continues from L + 1 + s(L+2) / area_fraction, so it is continuous
    where no point reaches two levels up."""
    level = 0
    for i in range(1, len(LEVELS)):
        if share_by_level[LEVELS[i]] >= area_fraction - 1e-12:
            level = i
    nxt = share_by_level[LEVELS[level + 1]] if level < 3 else 0.0
    return min(3.0, level + min(nxt / area_fraction, 1.0)), level
