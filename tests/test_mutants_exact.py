"""Mutation tests (issue 39): the exact sun intervals (``criteria/sunlight/exact.py``) and their
culling (``culling.py``), piece by piece against hand values, closed forms and brute force.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.sunlight import culling, exact


def test_union_over_points_by_hand():
    # day 0: A sees [0, 10] and [20, 30], B [5, 12] and [30, 40]: merged [0, 12] and [20, 40] (touching at 30);
    # day 1: A [100, 110], B nothing
    a = [np.array([[0.0, 10.0], [20.0, 30.0]]), np.array([[100.0, 110.0]])]
    b = [np.array([[5.0, 12.0], [30.0, 40.0]]), np.zeros((0, 2))]
    iv, err = exact.union_intervals([a, b], [np.array([0.5, 0.25]), np.array([1.0, 0.0])], 2)
    assert iv[0].tolist() == [[0.0, 12.0], [20.0, 40.0]]
    assert iv[1].tolist() == [[100.0, 110.0]]
    assert err.tolist() == [1.5, 0.25]


def test_triangle_edges_are_the_distinct_sorted_edges():
    tri = np.array([[0, 1, 2], [2, 1, 3], [4, 5, 6]])
    assert culling.triangle_edges(tri, np.array([0, 1])).tolist() == [[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]
    assert culling.triangle_edges(tri, np.array([], int)).shape == (0, 2)
