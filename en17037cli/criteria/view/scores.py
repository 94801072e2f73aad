"""Continuous view scores of a room (beyond the standard; see :mod:`en17037cli.standard`): per eye
height and criterion, the quantity that the area fraction of the points reaches, its score in
[0, 3] and its margins to the neighbouring levels; the room's score is the lowest, as its level is.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli import standard
from en17037cli.criteria.view.results import ViewResult
from en17037cli.standard import Thresholds

#: The unit of each view criterion's quantity and margins.
UNITS = {"horizontal_sight_angle": "deg", "outside_distance": "m", "layers": "share of points"}


@dataclass(frozen=True)
class CriterionScore:
    """One criterion at one eye height.

    quantity : the value reached by ``view.area_fraction`` of the points ([deg], [m]), or for the
        layers the share of points reaching the next level up
    score : in [0, 3]; level : floor of it, the criterion's level
    margin_up, margin_down : to the next level up / down, in ``unit`` (None beyond high / below minimum)
    """

    criterion: str
    eye_height_m: float
    quantity: float
    unit: str
    score: float
    level: int
    margin_up: float | None
    margin_down: float | None


def view_scores(res: ViewResult, thresholds: Thresholds, area_fraction: float) -> list[CriterionScore]:
    """Every (eye height, criterion) score of a room's view result."""
    out = []
    for e in res.eye_heights:
        v = e.values
        if v is None:
            continue
        for c, values, th in (("horizontal_sight_angle", v.sight.angle_deg, thresholds.horizontal_sight_angle_deg),
                              ("outside_distance", v.distance_m, thresholds.outside_distance_m)):
            q = standard.area_quantile(values, area_fraction)
            lv = int(standard.level_from_value([q], th)[0]) if np.isfinite(q) or q > 0 else 0
            up, down = standard.margins(q, lv, th)
            out.append(CriterionScore(c, e.eye_height_m, q, UNITS[c], float(standard.score_from_value([q], th)[0]), lv,
                                      up, down))
        shares = e.share_by_level["layers"]
        s, lv = standard.share_score(shares, area_fraction)
        up = None if lv >= 3 else area_fraction - shares[standard.LEVELS[lv + 1]]
        down = None if lv <= 0 else shares[standard.LEVELS[lv]] - area_fraction
        nxt = shares[standard.LEVELS[lv + 1]] if lv < 3 else 1.0
        out.append(CriterionScore("layers", e.eye_height_m, nxt, UNITS["layers"], s, lv, up, down))
    return out


def room_view_score(scores: list[CriterionScore]) -> float:
    """The room's view score: the lowest of its criteria and eye heights (NaN without any)."""
    return min((s.score for s in scores), default=float("nan"))
