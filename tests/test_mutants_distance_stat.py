"""weighted_statistic of criteria/view/distance.py against values counted by hand.

Written to kill mutants of ``make mutation`` (docs/mutation.md). Rows are independent: every case
has two rows whose answers differ, so a statistic taken over the whole array instead of per row
shows. Values and weights are exact binary fractions; 1e-12 covers one division's round-off.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.distance import weighted_statistic

EXACT = 1e-12


def test_median_and_its_gap_per_row():
    values = np.array([[1.0, 2.0, 5.0, 9.0], [10.0, 40.0, 50.0, 60.0]])
    weights = np.array([[1.0, 1.0, 1.0, 1.0], [3.0, 1.0, 1.0, 1.0]])
    value, gap = weighted_statistic(values, weights, "median")
    # row 0: half of 4 reached at the 2nd value, 2; neighbours 1 and 5: gap max(1, 3) = 3
    # row 1: half of 6 reached at the 1st value (weight 3), 10; no lower neighbour, next 40: gap 30
    np.testing.assert_allclose(value, [2.0, 10.0], rtol=0, atol=EXACT)
    np.testing.assert_allclose(gap, [3.0, 30.0], rtol=0, atol=EXACT)


def test_percentile_is_read_as_a_percentage():
    values = np.array([[1.0, 2.0], [1.0, 2.0]])
    weights = np.array([[0.4999, 0.5001], [0.6, 0.4]])
    value, _ = weighted_statistic(values, weights, "p50")
    # 50 % of 1: row 0 reaches it only at the 2nd value (0.4999 < 0.5); row 1 at the first
    np.testing.assert_allclose(value, [2.0, 1.0], rtol=0, atol=EXACT)
    value, _ = weighted_statistic(np.array([[3.0, 1.0, 2.0, 4.0]]), np.ones((1, 4)), "p75")
    assert value[0] == 3.0  # 75 % of 4 reached at the 3rd smallest


def test_min_skips_zero_weights_and_unsorted_input():
    values = np.array([[7.0, 1.0, 5.0], [np.nan, 9.0, 4.0]])
    weights = np.array([[1.0, 0.0, 2.0], [0.0, 1.0, 1.0]])
    value, gap = weighted_statistic(values, weights, "min")
    np.testing.assert_allclose(value, [5.0, 4.0], rtol=0, atol=EXACT)
    np.testing.assert_allclose(gap, [2.0, 5.0], rtol=0, atol=EXACT)  # next weighted values 7 and 9


def test_mean_with_infinite_and_zero_weight_values():
    values = np.array([[1.0, 3.0, np.inf], [2.0, 4.0, np.nan], [1.0, np.inf, 2.0], [5.0, 6.0, 7.0]])
    weights = np.array([[1.0, 1.0, 0.0], [1.0, 3.0, 0.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]])
    value, gap = weighted_statistic(values, weights, "mean")
    # (1 + 3) / 2; (2 + 3 x 4) / 4; a weighted +inf makes the mean +inf; no weight: NaN
    assert value[0] == 2.0 and value[1] == 3.5 and value[2] == np.inf and np.isnan(value[3])
    assert gap.tolist() == [0.0, 0.0, 0.0, 0.0]


def test_empty_row_and_infinite_neighbour():
    values = np.array([[1.0, np.inf, 3.0], [1.0, 2.0, 3.0]])
    weights = np.array([[1.0, 1.0, 2.0], [0.0, 0.0, 0.0]])
    value, gap = weighted_statistic(values, weights, "median")
    # row 0 sorted 1, 3, inf with weights 1, 2, 1: half of 4 reached at 3; gaps 2 and inf -> 2
    assert value[0] == 3.0 and gap[0] == 2.0
    assert np.isnan(value[1]) and np.isnan(gap[1])


def test_gap_per_row_with_an_infinite_or_missing_neighbour():
    values = np.array([[1.0, 1.5, np.inf, np.nan], [1.0, 3.0, np.nan, np.nan], [1.0, 2.0, 3.0, 4.0]])
    weights = np.array([[1.0, 2.0, 1.0, 0.0], [1.0, 1.0, 0.0, 0.0], [1.0, 1.0, 1.0, 1.0]])
    value, gap = weighted_statistic(values, weights, "p90")
    # row 0: 90 % of 4 = 3.6 reached at +inf; row 1: 1.8 of 2 at 3 (gap 2 to 1, no next value);
    # row 2: 3.6 of 4 at 4 (gap 1 to 3)
    assert value.tolist() == [np.inf, 3.0, 4.0] and gap[1] == 2.0 and gap[2] == 1.0
    value, gap = weighted_statistic(values[:1], weights[:1], "median")
    # half of 4 reached at 1.5: lower neighbour 0.5 below, upper +inf (not a finite gap): 0.5
    assert value[0] == 1.5 and gap[0] == 0.5
