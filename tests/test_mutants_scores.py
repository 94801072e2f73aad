"""The continuous scores, margins and limits of en17037cli.standard against values worked out by hand.

Written to kill mutants of ``make mutation`` (docs/mutation.md): these functions had no selected
test. Every expected value is worked out from the functions' documented rule (piecewise linear
through the thresholds of Table A.5 / A.6, the k-th largest value, ...), not from the code.
Values are exact binary fractions or compared to 1e-12 (round-off of one division).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from en17037cli import standard as S

ANGLE = S.LevelThresholds(14.0, 28.0, 54.0)  # Table A.5, horizontal sight angle [deg]
HOURS = S.LevelThresholds(1.5, 3.0, 4.0)  # Table A.6, sunlight [h]
EXACT = 1e-12  # one division's round-off


def test_score_from_value_is_linear_between_the_thresholds():
    v = [-5.0, 0.0, 7.0, 14.0, 21.0, 28.0, 41.0, 54.0, 100.0, np.inf, -np.inf]
    # (0, 0), (14, 1), (28, 2), (54, 3): halfway 7 -> 0.5, 21 -> 1.5, 41 -> 2.5; flat outside
    expected = [0.0, 0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.0, 3.0, 0.0]
    np.testing.assert_allclose(S.score_from_value(v, ANGLE), expected, rtol=0, atol=EXACT)
    h = S.score_from_value([0.75, 1.5, 2.25, 3.0, 3.5, 4.0, 12.0], HOURS)
    np.testing.assert_allclose(h, [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.0], rtol=0, atol=EXACT)


def test_score_from_value_keeps_nan_and_shape_and_its_floor_is_the_level():
    out = S.score_from_value([[np.nan, 28.0], [14.0, np.nan]], ANGLE)
    assert out.shape == (2, 2)
    assert np.isnan(out[0, 0]) and np.isnan(out[1, 1])
    assert out[0, 1] == 2.0 and out[1, 0] == 1.0
    assert float(S.score_from_value(2.0, HOURS)) == pytest.approx(1.0 + 0.5 / 1.5, abs=EXACT)
    x = np.linspace(0.0, 70.0, 701)
    s = S.score_from_value(x, ANGLE)
    assert np.all(np.diff(s) >= 0)  # non-decreasing
    assert np.array_equal(np.floor(s).astype(int), S.level_from_value(x, ANGLE))


def test_level_from_value_between_and_at_the_view_thresholds():
    v = [13.9, 14.0, 27.9, 28.0, 53.9, 54.0, 360.0]
    lv = S.level_from_value(v, ANGLE)
    assert lv.tolist() == [0, 1, 1, 2, 2, 3, 3]
    assert lv.dtype.kind == "i"  # documented (n,) int: levels index LEVELS
    assert S.level_from_value([0.0, 30.0, 60.0], ANGLE).dtype.kind == "i"
    assert S.level_from_value([5.9, 6.0, 19.9, 20.0, 49.9, 50.0],
                              S.LevelThresholds(6.0, 20.0, 50.0)).tolist() == [0, 1, 1, 2, 2, 3]


def test_near_threshold_by_hand():
    # 13 +- 1 touches 14; 15 +- 0.5 does not; 28 exact (error 0) is never near; 53 +- 2 reaches 54
    near = S.near_threshold([13.0, 15.0, 28.0, 53.0, np.nan, 40.0], [1.0, 0.5, 0.0, 2.0, 5.0, 1.0], ANGLE)
    assert near.tolist() == [True, False, False, True, False, False]
    assert S.near_threshold([0.001], [0.002], [0.0]).tolist() == [True]
    assert S.near_threshold([0.003], [0.002], [0.0]).tolist() == [False]


def _share(minimum, medium, high):
    return {"none": 1.0, "minimum": minimum, "medium": medium, "high": high}


@pytest.mark.parametrize("shares, fraction, score, level", [
    (_share(0.8, 0.5, 0.1), 0.75, 1.0 + 0.5 / 0.75, 1),   # level 1, medium share 0.5 of 0.75
    (_share(0.75, 0.3, 0.0), 0.75, 1.0 + 0.3 / 0.75, 1),  # exactly the fraction reaches the level
    (_share(0.7, 0.3, 0.0), 0.75, 0.7 / 0.75, 0),          # below: 0 + 0.7 / 0.75
    (_share(0.0, 0.0, 0.0), 0.75, 0.0, 0),
    (_share(1.0, 0.9, 0.6), 0.75, 2.0 + 0.6 / 0.75, 2),
    (_share(1.0, 1.0, 1.0), 0.75, 3.0, 3),
    (_share(1.0, 1.0, 0.5), 0.5, 3.0, 3),                  # high reached at a fraction of 0.5
    (_share(0.6, 0.2, 0.0), 0.5, 1.0 + 0.2 / 0.5, 1),
    (_share(0.3, 0.2, 0.0), 0.5, 0.6, 0),
])
def test_share_score_by_hand(shares, fraction, score, level):
    s, lv = S.share_score(shares, fraction)
    assert lv == level
    assert s == pytest.approx(score, abs=EXACT)


def test_share_score_agrees_with_room_level():
    pts = np.array([0, 1, 1, 2, 2, 2, 3, 3])
    for fraction in (0.125, 0.25, 0.5, 0.625, 0.75, 0.875, 1.0):
        level, share = S.room_level(pts, fraction)
        s, lv = S.share_score(share, fraction)
        assert lv == level and level <= s <= level + 1


@pytest.mark.parametrize("fraction, expected", [
    (0.5, 3.0),    # n = 5, k = ceil(2.5) = 3: third largest of 5, 4, 3, 1, NaN
    (0.4, 4.0),    # k = ceil(2.0) = 2 (not 3: the 1e-9 only absorbs round-off)
    (0.2, 5.0),    # k = 1
    (0.01, 5.0),   # k = ceil(0.05) = 1
    (0.0, 5.0),    # k at least 1
    (0.8, 1.0),    # k = 4
    (1.0, -np.inf),  # k = 5: the NaN point reaches nothing
])
def test_area_quantile_is_the_kth_largest(fraction, expected):
    assert S.area_quantile([5.0, 1.0, 3.0, np.nan, 4.0], fraction) == expected


def test_area_quantile_shapes_and_empty():
    assert math.isnan(S.area_quantile([], 0.75))
    assert S.area_quantile([[2.0, 8.0], [6.0, 4.0]], 0.75) == 4.0  # 2-d input flattened: k = 3
    assert S.area_quantile([7.0], 0.75) == 7.0
    assert S.area_quantile([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0], 0.7) == 4.0  # k = 7 exactly
    assert S.area_quantile([-np.inf, 2.0], 0.5) == 2.0
    assert isinstance(S.area_quantile(np.arange(4.0), 0.5), float)


def test_area_quantile_level_is_the_room_level():
    rng = np.random.default_rng(3)
    for _ in range(50):
        v = rng.uniform(0.0, 70.0, rng.integers(1, 30))
        for fraction in (0.5, 0.75, 0.9, 1.0):
            lv = S.level_from_value([S.area_quantile(v, fraction)], ANGLE)[0]
            assert lv == S.room_level(S.level_from_value(v, ANGLE), fraction)[0]


@pytest.mark.parametrize("quantity, level, up, down", [
    (20.0, 1, 8.0, 6.0),      # 28 - 20, 20 - 14
    (30.0, 2, 24.0, 2.0),     # 54 - 30, 30 - 28
    (10.0, 0, 4.0, None),     # below minimum: nothing to lose
    (60.0, 3, None, 6.0),     # beyond high: nothing to reach
    (np.inf, 3, None, None),  # infinite: no finite loss drops it
    (14.0, 1, 14.0, 0.0),
])
def test_margins_by_hand(quantity, level, up, down):
    u, d = S.margins(quantity, level, ANGLE)
    assert u == up and d == down


@pytest.mark.parametrize("reached, required, target", [
    (0, "none", 1), (1, "none", 2), (2, "none", 3), (3, "none", 3),
    (0, "minimum", 1), (3, "minimum", 1), (1, "medium", 2), (1, "high", 3), (3, "high", 3),
])
def test_target_level(reached, required, target):
    assert S.target_level(reached, required) == target


def test_sunlight_limit_by_hand():
    lim = S.sunlight_limit(2.0, 1, "none", HOURS)
    assert lim == S.Limit("medium", "sunlight_hours", 2.0, 3.0, None)
    assert lim.margin == -1.0
    assert S.sunlight_limit(1.0, 0, "minimum", HOURS) == S.Limit("minimum", "sunlight_hours", 1.0, 1.5)
    assert S.sunlight_limit(5, 3, "none", HOURS) == S.Limit("high", "sunlight_hours", 5.0, 4.0)
    assert S.sunlight_limit(0.5, 0, "none", HOURS).needed == 1.5
    assert S.sunlight_limit(3.5, 2, "high", HOURS).margin == -0.5
    assert isinstance(S.sunlight_limit(np.float32(2.5), 1, "none", HOURS).value, float)


def _crit(sight, distance, layers):
    return {"horizontal_sight_angle": sight, "outside_distance": distance, "layers": layers}


def test_view_limit_picks_the_smallest_share_of_the_target_level():
    low = _crit(_share(1.0, 0.9, 0.2), _share(1.0, 0.6, 0.1), _share(1.0, 1.0, 1.0))
    high = _crit(_share(1.0, 0.95, 0.5), _share(1.0, 0.7, 0.05), _share(1.0, 0.4, 0.3))
    eyes = [(1.2, low), (1.7, high)]
    # reached minimum, none required: target medium; smallest medium share 0.4 (layers at 1.7 m)
    lim = S.view_limit(eyes, 1, "none", 0.75)
    assert lim == S.Limit("medium", "layers", 0.4, 0.75, 1.7)
    assert lim.margin == pytest.approx(0.4 - 0.75, abs=EXACT)
    # high required: smallest high share 0.05 (outside distance at 1.7 m)
    assert S.view_limit(eyes, 1, "high", 0.75) == S.Limit("high", "outside_distance", 0.05, 0.75, 1.7)
    # minimum required: all shares 1.0, a tie: the lower eye height, then Table A.5's order
    assert S.view_limit(eyes, 2, "minimum", 0.5) == S.Limit("minimum", "horizontal_sight_angle", 1.0, 0.5, 1.2)


def test_view_limit_ties_and_missing_criteria():
    a = {"outside_distance": _share(1.0, 0.5, 0.0), "layers": _share(1.0, 0.5, 0.0)}
    b = {"horizontal_sight_angle": _share(1.0, 0.5, 0.0)}
    # equal medium shares: the lower eye height (listed first) wins, then outside distance before layers
    assert S.view_limit([(1.2, a), (1.7, b)], 1, "none", 0.75) == S.Limit("medium", "outside_distance", 0.5, 0.75, 1.2)
    assert S.view_limit([(1.2, b), (1.7, a)], 1, "none", 0.75) == \
        S.Limit("medium", "horizontal_sight_angle", 0.5, 0.75, 1.2)
    # keys that are not view criteria are ignored
    c = {"other": _share(0.0, 0.0, 0.0), "layers": _share(1.0, 0.8, 0.3)}
    assert S.view_limit([(1.7, c)], 3, "none", 0.9) == S.Limit("high", "layers", 0.3, 0.9, 1.7)
    # no criterion at all
    assert S.view_limit([], 0, "none", 0.75) == S.Limit("minimum", "", 0.0, 0.75, None)
    assert S.view_limit([(1.2, {})], 2, "high", 0.6) == S.Limit("high", "", 0.0, 0.6, None)
