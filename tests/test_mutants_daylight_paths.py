"""Mutation tests (issue 39): the daylight criterion's light paths, gather rounds, exact sky component
and climate-based parts (``criteria/daylight/``: transport, gather, sky_component, climate) with
stand-in ray engines and Radiance calls, against hand values, closed forms and brute force.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from en17037cli.criteria.daylight import sky_component as scm


def test_rect_solid_angle_closed_form():
    # the rectangle [0, a] x [0, b] at distance 1 seen from a corner's normal: atan(a b / sqrt(1 + a^2 + b^2))
    a, b = 0.7, 1.3
    G = np.array([[0.0, math.atan(a), 0.0, math.atan(b)]])
    assert scm._rect_solid_angle(G)[0] == pytest.approx(math.atan(a * b / math.sqrt(1 + a * a + b * b)), rel=1e-12)


def test_within_budget_by_hand():
    pt = np.array([0, 0, 1, 1, 1])
    own = np.array([0.25, 0.125, 0.125, 0.03, 0.5])
    budget = np.array([0.375, 0.5])
    # point 0: 0.375 in all fits its budget exactly; point 1: 0.655 does not, so each must fit 0.25 x 0.5 / 3 = 0.042
    assert scm._within_budget(pt, own, budget).tolist() == [True, True, False, True, False]
