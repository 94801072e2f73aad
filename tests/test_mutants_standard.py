"""The judging rules of en17037cli.standard against values read off EN 17037 Table A.5 / A.6 by hand.

Written to kill mutants of ``make mutation`` (docs/mutation.md); every expected value below is
worked out from the rule's wording, not from the code.
"""
from __future__ import annotations

import numpy as np
import pytest

from en17037cli import standard as S


def test_level_names_and_indices_round_trip():
    assert [S.level_index(n) for n in ("none", "minimum", "medium", "high")] == [0, 1, 2, 3]
    assert [S.level_name(i) for i in (0, 1, 2, 3)] == ["none", "minimum", "medium", "high"]
    assert S.level_name(np.int64(2)) == "medium"  # numpy integers from the level arrays


def test_level_from_value_at_and_around_every_threshold_of_table_a6():
    t = S.LevelThresholds(minimum=1.5, medium=3.0, high=4.0)  # sunlight hours, Table A.6
    v = [0.0, 1.4999, 1.5, 2.9999, 3.0, 3.9999, 4.0, 24.0, np.inf, -np.inf, np.nan]
    assert S.level_from_value(v, t).tolist() == [0, 0, 1, 1, 2, 2, 3, 3, 3, 0, 0]
    assert t.values() == (1.5, 3.0, 4.0) and t.as_dict() == {"minimum": 1.5, "medium": 3.0, "high": 4.0}


def test_thresholds_from_a_national_annex_dict():
    d = {k: dict(v) for k, v in S.THRESHOLDS.items()}
    d["sunlight_hours"]["minimum"] = 2.0
    th = S.Thresholds.from_dict(d)
    assert th.sunlight_hours == S.LevelThresholds(2.0, 3.0, 4.0)
    assert th.horizontal_sight_angle_deg == S.LevelThresholds(14.0, 28.0, 54.0)
    assert th.outside_distance_m == S.LevelThresholds(6.0, 20.0, 50.0)


def test_layer_rule_every_combination():
    # Table A.5: high = all three; medium = landscape and (sky or ground); minimum = landscape
    combos = [(s, la, g) for s in (False, True) for la in (False, True) for g in (False, True)]
    expected = [0 if not la else (3 if s and g else (2 if s or g else 1)) for s, la, g in combos]
    sky, land, ground = (np.array(c) for c in zip(*combos))
    assert S.level_from_layers(sky, land, ground).tolist() == expected
    # any truthy input counts (solid angles passed as visibility flags)
    assert S.level_from_layers([1.0], [2.0], [0.0]).tolist() == [2]


def test_layer_visible_is_strictly_above_the_threshold():
    assert S.layer_visible([0.0, 1e-9, 0.5, 0.50001], 0.5).tolist() == [False, False, False, True]
    assert S.layer_visible([0.0, 1e-12], 0.0).tolist() == [False, True]


def test_near_threshold_edges():
    t = S.LevelThresholds(6.0, 20.0, 50.0)
    # |v - t| <= e is near, on either side of any of the three thresholds
    assert S.near_threshold([5.0, 7.0, 4.99, 21.0, 49.0, 51.0, 51.01], [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0], t).tolist() == \
        [True, True, False, True, True, True, False]
    # NaN values or errors are never near; a negative error is not an error estimate
    assert S.near_threshold([np.nan, 20.0, 20.0], [1.0, np.nan, -1.0], t).tolist() == [False, False, False]
    # a sequence of values works like LevelThresholds; 2-d input keeps its shape
    assert S.near_threshold(np.array([[19.5, 30.0]]), np.array([[1.0, 1.0]]), [20.0]).tolist() == [[True, False]]


def test_room_level_by_area_fraction():
    # 4 points with levels 3, 2, 2, 0: shares >= minimum 3/4, >= medium 3/4, >= high 1/4
    level, share = S.room_level([3, 2, 2, 0], 0.75)
    assert level == 2
    assert share == {"none": 1.0, "minimum": 0.75, "medium": 0.75, "high": 0.25}
    assert S.room_level([3, 2, 2, 0], 0.5)[0] == 2
    assert S.room_level([3, 2, 2, 0], 0.25)[0] == 3
    assert S.room_level([3, 2, 2, 0], 0.76)[0] == 0  # no level reaches 76 %
    assert S.room_level([1], 1.0) == (1, {"none": 1.0, "minimum": 1.0, "medium": 0.0, "high": 0.0})
    # a fraction that equals the share up to round-off still counts (2/3 of 3 points)
    assert S.room_level([2, 2, 0], 2 / 3)[0] == 2
    # float levels are whole levels
    assert S.room_level(np.array([2.0, 3.0]), 1.0)[0] == 2


def test_room_level_without_points_is_none_everywhere():
    level, share = S.room_level([], 0.75)
    assert level == 0
    assert share == {"none": 1.0, "minimum": 0.0, "medium": 0.0, "high": 0.0}
    assert S.room_level([], 0.0)[0] == 0  # no point reaches anything, whatever the fraction


def test_point_and_view_levels_are_the_lowest():
    assert S.point_view_level([3, 2, 1], [1, 3, 2], [2, 2, 3]).tolist() == [1, 2, 1]
    assert S.point_view_level(np.array([2, 0])).tolist() == [2, 0]
    assert S.view_level([3, 1, 2]) == 1
    assert S.view_level(iter([2, 3])) == 2
    assert S.view_level([]) == 0


@pytest.mark.parametrize("level, required, ok", [
    ("none", "none", True), ("minimum", "minimum", True), ("medium", "minimum", True),
    ("minimum", "medium", False), ("high", "high", True), ("medium", "high", False),
])
def test_passes_and_status(level, required, ok):
    assert S.passes(level, required) is ok
    assert S.status(level, required) == ("pass" if ok else "fail")


def test_sunlight_rooms_rule_any_and_all():
    assert S.sunlight_rooms_pass([], "all") is True
    assert S.sunlight_rooms_pass([], "any") is True
    assert S.sunlight_rooms_pass([True, False], "all") is False
    assert S.sunlight_rooms_pass([True, False], "any") is True
    assert S.sunlight_rooms_pass([False, False], "any") is False
    assert S.sunlight_rooms_pass([True, True], "all") is True
